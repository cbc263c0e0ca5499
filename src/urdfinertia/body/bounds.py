"""Axis-aligned bounding box of a link's geometry in the link frame.

Primitives give their extreme points in closed form; meshes give their (scaled) vertices.
Points are moved by the element's ``<origin>`` before taking the box, so the box is tight
for rotated elements too.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from urdfinertia.cache.library import MeshLibrary
from urdfinertia.descriptions.model import (
    Box,
    Capsule,
    Cone,
    Cylinder,
    Ellipsoid,
    GeometryRef,
    Mesh,
    Shape,
    Sphere,
)


class BoundsCache:
    """Vertices of mesh files by resolved path, read once per run."""

    def __init__(self, meshes: MeshLibrary) -> None:
        self.meshes = meshes
        self._memo: dict[Path, np.ndarray] = {}

    def vertices(self, uri: str, urdf_dir: Path) -> np.ndarray:
        path = self.meshes.resolve(uri, urdf_dir).resolve()
        found = self._memo.get(path)
        if found is None:
            found = self._memo[path] = self.meshes.points(path)
        return found


def shape_points(shape: Shape, cache: BoundsCache, urdf_dir: Path) -> np.ndarray:
    """(n, 3) points whose box is the shape's box, in the geometry frame."""
    if isinstance(shape, Box):
        half = np.asarray(shape.size, dtype=np.float64) / 2
        return _box_corners(-half, half)
    if isinstance(shape, Cylinder | Cone):  # a cone's box is its cylinder's
        half = np.array([shape.radius, shape.radius, shape.length / 2])
        return _box_corners(-half, half)
    if isinstance(shape, Sphere):
        half = np.full(3, shape.radius)
        return _box_corners(-half, half)
    if isinstance(shape, Capsule):
        half = np.array([shape.radius, shape.radius, shape.length / 2 + shape.radius])
        return _box_corners(-half, half)
    if isinstance(shape, Ellipsoid):
        half = np.asarray(shape.radii, dtype=np.float64)
        return _box_corners(-half, half)
    if isinstance(shape, Mesh):
        return cache.vertices(shape.filename, urdf_dir) * np.asarray(shape.scale)
    raise TypeError(f"unknown shape {shape!r}")


def _box_corners(lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
    idx = np.array([[i, j, k] for i in (0, 1) for j in (0, 1) for k in (0, 1)])
    return np.where(idx == 0, lo, hi)


def link_bounds(refs: tuple[GeometryRef, ...], cache: BoundsCache, urdf_dir: Path,
                ) -> tuple[np.ndarray, np.ndarray] | None:
    """(lo, hi) corners of the box holding every element of ``refs``, link frame, m."""
    boxes = []
    for ref in refs:
        pts = shape_points(ref.shape, cache, urdf_dir)
        pose = ref.origin.matrix()
        moved = pts @ pose[:3, :3].T + pose[:3, 3]
        boxes.append((moved.min(axis=0), moved.max(axis=0)))
    if not boxes:
        return None
    lo = np.min([b[0] for b in boxes], axis=0)
    hi = np.max([b[1] for b in boxes], axis=0)
    return lo, hi
