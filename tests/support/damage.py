"""Damage a clean mesh the ways real files are damaged, for accuracy tests and benchmarks.

Pure numpy; every function takes a seeded generator where it is random and returns new
``(vertices, faces)`` arrays, leaving its input untouched.
"""

from __future__ import annotations

import numpy as np


def delete_faces(vertices: np.ndarray, faces: np.ndarray, fraction: float,
                 rng: np.random.Generator) -> tuple[np.ndarray, np.ndarray]:
    """Remove ``fraction`` of the faces, chosen uniformly at random."""
    keep = rng.permutation(len(faces))[int(round(fraction * len(faces))):]
    return vertices.copy(), faces[np.sort(keep)].copy()


def flip_faces(vertices: np.ndarray, faces: np.ndarray, fraction: float,
               rng: np.random.Generator) -> tuple[np.ndarray, np.ndarray]:
    """Reverse the orientation of ``fraction`` of the faces, chosen at random."""
    out = faces.copy()
    pick = rng.permutation(len(faces))[: int(round(fraction * len(faces)))]
    out[pick] = out[pick][:, ::-1]
    return vertices.copy(), out


def invert(vertices: np.ndarray, faces: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Every face reversed: the normals point inward."""
    return vertices.copy(), faces[:, ::-1].copy()


def triangle_soup(vertices: np.ndarray, faces: np.ndarray,
                  rng: np.random.Generator) -> tuple[np.ndarray, np.ndarray]:
    """Three private vertices per face, faces shuffled (as an STL file stores them)."""
    order = rng.permutation(len(faces))
    soup = vertices[faces[order]].reshape(-1, 3)
    return soup, np.arange(len(soup)).reshape(-1, 3)


def remove_patch(vertices: np.ndarray, faces: np.ndarray, area_fraction: float,
                 rng: np.random.Generator) -> tuple[np.ndarray, np.ndarray]:
    """Remove a connected patch (grown from a random face) of ``area_fraction`` of the area.

    The patch grows ring by ring over faces sharing a vertex; the last ring is cut in a
    random order so the removed area is just above ``area_fraction``.
    """
    tri = vertices[faces]
    area = 0.5 * np.linalg.norm(np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0]), axis=1)
    target = area_fraction * area.sum()
    removed = np.zeros(len(faces), dtype=bool)
    removed[rng.integers(len(faces))] = True
    while area[removed].sum() < target:  # one iteration per ring of faces
        touched = np.zeros(len(vertices), dtype=bool)
        touched[faces[removed].reshape(-1)] = True
        ring = np.flatnonzero(touched[faces].any(axis=1) & ~removed)
        if len(ring) == 0:
            break
        ring = rng.permutation(ring)
        need = target - area[removed].sum()
        take = np.searchsorted(np.cumsum(area[ring]), need) + 1
        removed[ring[:take]] = True
    return vertices.copy(), faces[~removed].copy()


def duplicate(vertices: np.ndarray, faces: np.ndarray, offset: np.ndarray | None = None,
              ) -> tuple[np.ndarray, np.ndarray]:
    """The mesh and a second copy of it, moved by ``offset`` (default: in place)."""
    shift = np.zeros(3) if offset is None else np.asarray(offset, dtype=np.float64)
    v = np.concatenate([vertices, vertices + shift])
    return v, np.concatenate([faces, faces + len(vertices)])


def seam(vertices: np.ndarray, faces: np.ndarray, gap: float, rng: np.random.Generator,
         ) -> tuple[np.ndarray, np.ndarray]:
    """Cut the surface in two along a plane and move one side by ``gap`` of the diagonal.

    The plane runs through the centroid of the used vertices with a random normal; a face
    belongs to the side its centroid is on, so the cut follows mesh edges. The faces on
    one side get their own copies of their vertices, moved by ``gap`` times the
    bounding-box diagonal in a random direction: no vertex is shared across the cut and
    the two rims of the seam run alongside each other, as when a CAD exporter
    tessellates faces independently.
    """
    used = np.unique(faces)
    diagonal = float(np.linalg.norm(np.ptp(vertices[used], axis=0)))
    normal, direction = rng.normal(size=(2, 3))
    normal /= np.linalg.norm(normal)
    direction /= np.linalg.norm(direction)
    centroid = vertices[faces].mean(axis=1)
    side = (centroid - vertices[used].mean(axis=0)) @ normal > 0
    moved = vertices + gap * diagonal * direction
    out = faces.copy()
    out[side] += len(vertices)  # that side's faces use the moved copies only
    return np.concatenate([vertices, moved]), out


#: The real concave parts (example-robot-data paths) whose undamaged originals are the
#: truth of the damage benchmarks (scripts/bench_meshes.py, scripts/bench_sdf.py).
PARTS = (
    "g1_description/meshes/left_wrist_roll_link.STL",
    "tiago_pro_description/meshes/omni_base/wheels/suspension_front_link.stl",
    "so_arm_description/meshes/so100/Wrist_Pitch_Roll.stl",
    "cassie_description/meshes/tarsus.stl",
)
