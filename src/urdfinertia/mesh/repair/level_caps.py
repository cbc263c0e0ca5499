"""Caps through the half level set of an open surface's generalized winding number.

The generalized winding number `w` of an open surface (Jacobson et al.
2013) is 1 deep inside and 0 far outside, and varies smoothly across a hole; its level
set `w = 1/2` spans the hole without depending on how the hole's rim is triangulated.
For a planar hole it is the flat cap exactly (the cap subtends half the sphere from any
point on it). For a non-planar one (a hole wrapping around an edge or a thin wall) it
bulges the way the surrounding surface points, which a flat fan cannot.

A cap is built per loop as rings between the loop's perimeter centroid and the loop
(`RINGS - 1` inner rings and an apex); each inner point is moved along the loop's mean
normal to where `w` of the surface, with every other hole capped by its fan, crosses
1/2 (bisection). The rim edges are the loop's own, so the capped surface stays closed.
A point whose search finds no crossing, or only a jump of `w` (a wall of the surface
crossed, not the level set), stays on the fan.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from urdfinertia.mesh.repair.winding import RayCounter, winding_numbers
from urdfinertia.timing import Deadline

RINGS = 4
"""Rings of a level cap, counting the loop itself; the apex is added."""
ITERATIONS = 24
"""Bisection steps of the search for `w = 1/2` along each point's normal line (the bracket shrinks
to 2^-24 of its reach: about 1e-7 of the loop's radius).
"""
REACH = (1 / 16, 1 / 8, 1 / 4, 1 / 2, 1.0)
"""Search distances, as fractions of the loop's radius, tried in turn for a sign change."""
START = 1e-4
"""The search starts this fraction of the loop's radius outside the fan (off the fan's own faces,
where counting along a ray would graze an edge).
"""
LEVEL_ATOL = 1e-6
"""A point whose winding number is within this of 1/2 there stays on the fan."""
JUMP = 0.25
"""Change of `w` across the final bracket above which the crossing is a wall, not the level set
(`w` jumps by 1 through the surface and is continuous elsewhere).
"""


@dataclass(frozen=True, eq=False)
class LevelCaps:
    """Level caps of some loops.

    Attributes
    ----------
    vertices : (q, 3) float
        New vertices (inner rings and apexes), to be appended after the caller's.
    faces : (c, 3) int
        Cap faces; indices below the caller's vertex count are the loops' own vertices,
        the others `n + i` for `vertices[i]`.
    loop : (c,) int
        Loop of each face.
    """

    vertices: np.ndarray
    faces: np.ndarray
    loop: np.ndarray


def level_caps_points(sizes: np.ndarray) -> int:
    """Points whose level the caps of loops of `sizes` edges search for."""
    return int(np.sum((RINGS - 1) * sizes + 1))


def level_caps(n: int, corners: list[tuple[int, np.ndarray]], centre: np.ndarray,
               normal: np.ndarray, closed_vertices: np.ndarray, closed_faces: np.ndarray,
               fan_faces: np.ndarray, fan_loop: np.ndarray,
               deadline: Deadline | None = None) -> LevelCaps:
    """Level caps of the loops in `corners`.

    Parameters
    ----------
    n : int
        Vertex count of the caller's surface (new vertices are numbered from it).
    corners : list of (loop id, (s,) int)
        Each loop's vertices in the order the surface runs along its boundary.
    centre, normal : (k, 3) float
        Per loop id: perimeter centroid and unit mean normal (pointing out of the solid).
    closed_vertices, closed_faces
        The surface with every loop capped by its fan (so its winding numbers are
        integers, counted along rays).
    fan_faces : (f, 3) int
        The fans, indexing `closed_vertices`; `fan_loop` gives each one's loop.
    deadline : Deadline, optional
        Checked before every search step (raises `OverBudget`).
    """
    points, owner, starts = [], [], [0]
    frac = np.arange(1, RINGS) / RINGS  # inner rings, innermost first
    for loop_id, ids in corners:
        c = centre[loop_id]
        ring = c + frac[:, None, None] * (closed_vertices[ids] - c)
        points.append(np.concatenate([ring.reshape(-1, 3), c[None]]))
        owner.append(np.full(len(points[-1]), loop_id))
        starts.append(starts[-1] + len(points[-1]))
    if not points:
        return LevelCaps(np.zeros((0, 3)), np.zeros((0, 3), np.int64), np.zeros(0, np.int64))
    q = np.concatenate(points)
    lid = np.concatenate(owner)
    t = _level_offsets(q, lid, corners, centre, normal, closed_vertices,
                       closed_faces, fan_faces, fan_loop,
                       deadline if deadline is not None else Deadline(None))
    q = q + t[:, None] * normal[lid]
    faces, loops = [], []
    for k, (loop_id, ids) in enumerate(corners):
        s = len(ids)
        idx = n + np.arange(starts[k], starts[k + 1])
        rings = [ids] + [idx[j * s:(j + 1) * s] for j in range(RINGS - 2, -1, -1)]
        for outer, inner in zip(rings[:-1], rings[1:], strict=True):  # loop inwards
            o1, i1 = np.roll(outer, -1), np.roll(inner, -1)
            faces += [np.stack([o1, outer, inner], axis=1), np.stack([o1, inner, i1], axis=1)]
        inner = rings[-1]
        faces.append(np.stack([np.roll(inner, -1), inner, np.full(s, idx[-1])], axis=1))
        loops.append(np.full(s * (2 * RINGS - 1), loop_id))
    return LevelCaps(q, np.concatenate(faces).astype(np.int64), np.concatenate(loops))


def _level_offsets(q: np.ndarray, lid: np.ndarray, corners: list[tuple[int, np.ndarray]],
                   centre: np.ndarray, normal: np.ndarray, closed_vertices: np.ndarray,
                   closed_faces: np.ndarray, fan_faces: np.ndarray, fan_loop: np.ndarray,
                   deadline: Deadline) -> np.ndarray:
    """Offset of each point along its loop's normal to `w = 1/2` (0 where not found)."""
    radius = np.zeros(len(centre))
    for loop_id, ids in corners:
        radius[loop_id] = np.linalg.norm(closed_vertices[ids] - centre[loop_id], axis=1).max()
    r, nrm = radius[lid], normal[lid]
    counter = RayCounter(closed_vertices, closed_faces)  # one grid for every step
    fans = [(loop_id, closed_vertices[fan_faces[fan_loop == loop_id]].reshape(-1, 3))
            for loop_id, _ in corners]

    def level(t: np.ndarray, rows: np.ndarray | None = None) -> np.ndarray:
        """`w - 1/2` of the open surface (other holes fan-capped) at offsets `t`."""
        deadline.check()
        sel = np.arange(len(q)) if rows is None else rows
        x = q[sel] + t[:, None] * nrm[sel]
        # a point the bisection drives onto a wall is rejected as a jump anyway
        w = counter(x, exact_on_graze=False)
        for loop_id, corners_xyz in fans:  # remove this loop's own fan
            at = np.flatnonzero(lid[sel] == loop_id)
            if len(at):
                w[at] -= winding_numbers(x[at], corners_xyz,
                                         np.arange(len(corners_xyz)).reshape(-1, 3))
        return w - 0.5

    start = START * r
    f0 = level(start)
    on_level = np.abs(f0) <= LEVEL_ATOL
    side = np.where(f0 > 0, 1.0, -1.0)  # still inside: the level set lies further out
    far = np.zeros(len(q))
    found = on_level.copy()
    for reach in REACH:  # the nearest distance with a sign change brackets the level
        todo = np.flatnonzero(~found)
        if len(todo) == 0:
            break
        t = side[todo] * reach * r[todo]
        crossed = np.sign(level(t, todo)) != np.sign(f0[todo])
        far[todo[crossed]] = t[crossed]
        found[todo[crossed]] = True
    search = np.flatnonzero(found & ~on_level)
    lo, hi = start[search], far[search]
    for _ in range(ITERATIONS):  # bisection, all points at once
        mid = 0.5 * (lo + hi)
        same = np.sign(level(mid, search)) == np.sign(f0[search])
        lo, hi = np.where(same, mid, lo), np.where(same, hi, mid)
    jump = np.abs(level(lo, search) - level(hi, search)) > JUMP
    offset = np.zeros(len(q))
    offset[search[~jump]] = 0.5 * (lo + hi)[~jump]
    return offset
