"""Collision and visual prims of a rigid body as the model's shapes, in the body frame.

`UsdGeom` Cube (`size`), Sphere (`radius`), Cylinder, Capsule and Cone (`radius`,
`height`, `axis`) become closed-form shapes; a Mesh becomes an OBJ file of its
triangles (fan-triangulated polygons) in the user cache, named by its content, which the
mesh library then reads like any mesh reference. The prim's transform relative to the
body (its xformOps and its ancestors') gives the element's origin; its scale goes into
the shape. Lengths are multiplied by the stage's `metersPerUnit`.
"""

from __future__ import annotations

import hashlib
from pathlib import Path
from typing import Any

import numpy as np

from urdfinertia.descriptions.model import (
    Box,
    Capsule,
    Cone,
    Cylinder,
    Ellipsoid,
    Mesh,
    Origin,
    Shape,
    Sphere,
)
from urdfinertia.descriptions.usd.frames import AXIS_ROTATION, matrix_rpy, rigid_and_scale, vec3
from urdfinertia.rules import Rule

SHAPE_TYPES = ("Cube", "Sphere", "Cylinder", "Capsule", "Cone", "Mesh")
"""Gprim types with a closed form or a mesh here; others (Plane, curves, points) are dropped with a
problem.
"""


class ShapeError(ValueError):
    """A prim that gives no shape: the cause, and the rule of its finding."""

    def __init__(self, cause: str, rule: Rule = Rule.UNSUPPORTED_GEOMETRY) -> None:
        super().__init__(cause)
        self.rule = rule


def element(prim: Any, relative: np.ndarray, mpu: float) -> tuple[Origin, Shape]:
    """Origin in the body frame and shape of a geometry prim.

    `relative`: the prim's (4, 4) transform in the body frame, in stage units.
    """
    kind = prim.GetTypeName()
    if kind not in SHAPE_TYPES:
        raise ShapeError(f"{kind or 'untyped'} prim gives no volume")
    try:
        rigid, scale = rigid_and_scale(relative)
    except ValueError as exc:
        raise ShapeError(str(exc)) from None
    rigid = rigid.copy()
    rigid[:3, 3] *= mpu
    scale = scale * mpu
    if kind == "Mesh":
        shape: Shape = Mesh(filename=str(mesh_file(prim)), scale=vec3(scale))
        return _origin(rigid), shape
    mirrored = bool(np.any(scale < 0))
    scale = np.abs(scale)
    del mirrored  # primitives are symmetric: a mirror changes nothing
    if kind == "Cube":
        size = _positive(prim, "size", 2.0)
        return _origin(rigid), Box(size=vec3(size * scale))
    if kind == "Sphere":
        r = _positive(prim, "radius", 1.0)
        if np.allclose(scale, scale[0], rtol=1e-9):
            return _origin(rigid), Sphere(radius=float(r * scale[0]))
        return _origin(rigid), Ellipsoid(radii=vec3(r * scale))
    axis = str(prim.GetAttribute("axis").Get() or "Z")
    if axis not in AXIS_ROTATION:
        raise ShapeError(f"axis {axis!r} is not X, Y or Z")
    turn = AXIS_ROTATION[axis]
    pose = rigid.copy()
    pose[:3, :3] = rigid[:3, :3] @ turn
    along = np.abs(turn.T @ scale)  # scale along the shape's own x, y, z
    if not np.isclose(along[0], along[1], rtol=1e-9):
        raise ShapeError(f"{kind} scaled unevenly across its axis ({along[0]:g} vs "
                         f"{along[1]:g}) is no {kind.lower()}")
    radius = float(_positive(prim, "radius", 1.0) * along[0])
    height = float(_positive(prim, "height", 2.0, allow_zero=kind == "Capsule") * along[2])
    if kind == "Cylinder":
        return _origin(pose), Cylinder(radius=radius, length=height)
    if kind == "Cone":
        return _origin(pose), Cone(radius=radius, length=height)
    if not np.isclose(along[0], along[2], rtol=1e-9):
        raise ShapeError("capsule scaled unevenly along its axis: its caps are no "
                         "hemispheres")
    return _origin(pose), Capsule(radius=radius, length=height)


def _origin(pose: np.ndarray) -> Origin:
    xyz = (float(pose[0, 3]), float(pose[1, 3]), float(pose[2, 3]))
    return Origin(xyz=xyz, rpy=matrix_rpy(pose[:3, :3]))


def _positive(prim: Any, name: str, default: float, *, allow_zero: bool = False) -> Any:
    value = prim.GetAttribute(name).Get()
    value = default if value is None else value
    arr = np.asarray(value, dtype=np.float64)
    ok = np.all(np.isfinite(arr)) and (np.all(arr >= 0) if allow_zero else np.all(arr > 0))
    if not ok:
        raise ShapeError(f"{name} {value!r} is not a positive size", rule=Rule.ZERO_SIZE_PRIMITIVE)
    return arr


def triangles(prim: Any) -> tuple[np.ndarray, np.ndarray]:
    """(n, 3) points and (m, 3) triangles of a `UsdGeom.Mesh` (polygons as fans)."""
    points = np.asarray(prim.GetAttribute("points").Get() or [], dtype=np.float64)
    counts = np.asarray(prim.GetAttribute("faceVertexCounts").Get() or [], dtype=np.int64)
    indices = np.asarray(prim.GetAttribute("faceVertexIndices").Get() or [], dtype=np.int64)
    if points.ndim != 2 or len(points) == 0 or len(counts) == 0:
        raise ShapeError("mesh has no points or faces", rule=Rule.ZERO_SIZE_PRIMITIVE)
    if counts.sum() != len(indices) or np.any(counts < 3):
        raise ShapeError("mesh faceVertexCounts do not match faceVertexIndices")
    if indices.min() < 0 or indices.max() >= len(points):
        raise ShapeError("mesh faceVertexIndices point past its points")
    starts = np.concatenate([[0], np.cumsum(counts)[:-1]])
    fans = [np.stack([np.full(c - 2, s), s + np.arange(1, c - 1), s + np.arange(2, c)], 1)
            for s, c in zip(starts, counts, strict=True)]
    faces = indices[np.concatenate(fans)]
    if str(prim.GetAttribute("orientation").Get() or "rightHanded") == "leftHanded":
        faces = faces[:, ::-1]
    return points, faces


def mesh_file(prim: Any) -> Path:
    """An OBJ of the mesh's triangles in the user cache, named by its content (written
    once; the mesh library caches what it computes from it by the same bytes)."""
    import platformdirs

    from urdfinertia.atomic import atomic_write_bytes

    points, faces = triangles(prim)
    text = "".join(f"v {x:.17g} {y:.17g} {z:.17g}\n" for x, y, z in points)
    text += "".join(f"f {a + 1} {b + 1} {c + 1}\n" for a, b, c in faces)
    data = text.encode("ascii")
    folder = Path(platformdirs.user_cache_dir("urdfinertia")) / "usd-meshes"
    path = folder / f"{hashlib.sha256(data).hexdigest()[:32]}.obj"
    if not path.is_file():
        folder.mkdir(parents=True, exist_ok=True)
        atomic_write_bytes(path, data)
    return path
