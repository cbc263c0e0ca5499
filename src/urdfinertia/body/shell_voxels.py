"""The wall of a mesh where the exact vertex offset fails: a voxel estimate.

Real printed parts have fillets, ribs and screw bosses thinner than two walls; there the
offset surface of :func:`urdfinertia.inertia.shell.mesh_shell` inverts faces and is
refused. A slicer fills such places solid, and so does this estimate: the interior is
the set of voxel centres at least ``t`` inside the surface (the solid eroded by a ball
of radius ``t``), found by ray parity along x and a Euclidean distance transform, and
the wall is the exact solid minus it.

The transform gives, for an inside centre at depth ``d``, the distance ``e`` to the
nearest outside centre, with ``d <= e <= d + h sqrt(3) / 2`` (voxel size ``h``): ``d`` is
taken as ``e - 0.43 h``, within ``0.43 h``. A voxel counts for the share of it inside
the interior by a ramp one voxel wide across the interior's boundary (which integrates
like the step it replaces, exactly for a plane, without the staircase of whole voxels).
The stated error of the wall volume is the depth's band over the surface,
``0.43 h area / wall volume``; the tests measure the actual error against exact shells.
"""

from __future__ import annotations

import numpy as np

from urdfinertia.inertia.polyhedron import solid_integrals
from urdfinertia.inertia.shell import Moments, Shell, ShellError

#: Voxels in the grid, at most (the distance transform takes ~1 s a million): a box
#: larger than about 60 mm cubed gets voxels larger than a sixth of a 2 mm wall, and says so
#: in its stated error.
MAX_VOXELS = 6_000_000
#: Half the spread of the transform's distance over the true depth, in voxels.
_BAND = np.sqrt(3) / 4
#: Voxels across the wall thickness, at most.
VOXELS_PER_WALL = 6
#: Grid offset in voxels: irrational, so that rays miss the axis-aligned edges of CAD parts.
_SHIFT = np.array([0.5 * np.sqrt(2) - 0.2, 0.5 * np.sqrt(3) - 0.3, np.pi / 10])


def voxel_shell(vertices: np.ndarray, faces: np.ndarray, t: float,
                max_voxels: int = MAX_VOXELS) -> Shell:
    """Wall and interior of a closed, outward-oriented mesh, estimated on voxels.

    Raises
    ------
    ShellError
        No voxel is ``t`` deep: the part is wall throughout.
    """
    v = np.asarray(vertices, dtype=np.float64)
    f = np.asarray(faces, dtype=np.int64)
    low, high = v.min(axis=0), v.max(axis=0)
    extent = high - low
    h = max(t / VOXELS_PER_WALL, float(np.cbrt(np.prod(extent + 4 * t) / max_voxels)))
    fine = _interior(v, f, t, h)
    if fine[0] <= 0:
        raise ShellError(f"no point of the part is {t * 1e3:.4g} mm deep: it is all wall")
    outer = solid_integrals(v, f)
    wall: Moments = (outer[0] - fine[0], outer[1] - fine[1], outer[2] - fine[2])
    if not wall[0] > 0:
        raise ShellError("the voxel interior is larger than the part")
    tri = v[f]
    area = 0.5 * float(np.linalg.norm(np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0]),
                                      axis=1).sum())
    error = _BAND * h * area / wall[0]
    return Shell(wall, fine, error, f"mesh shell (voxel estimate, {h * 1e3:.3g} mm voxels)")


def _interior(v: np.ndarray, f: np.ndarray, t: float, h: float) -> Moments:
    """Volume integrals of the interior: voxels weighted by their share of it."""
    origin = v.min(axis=0) - 2 * h + _SHIFT * h
    shape = np.ceil((v.max(axis=0) + 2 * h - origin) / h).astype(np.int64) + 1
    inside = _inside(v, f, origin, h, shape)
    # distance from each inside centre to the nearest outside centre (module docstring)
    from scipy import ndimage  # here: a run that voxelises nothing does not import it

    depth = ndimage.distance_transform_edt(inside, sampling=h) - _BAND * h
    # each voxel's share of the interior, ramping over one voxel across its boundary
    # (a ramp integrates like the step it replaces, without the staircase)
    ix = np.nonzero(depth > t - h / 2)
    if not len(ix[0]):
        return 0.0, np.zeros(3), np.zeros((3, 3))
    share = np.clip((depth[ix] - t) / h + 0.5, 0.0, 1.0) * h**3
    centres = origin + h * np.column_stack(ix).astype(np.float64)
    volume = float(share.sum())
    first = share @ centres
    second = (centres * share[:, None]).T @ centres + volume * h * h / 12 * np.eye(3)
    return volume, first, second


def _inside(v: np.ndarray, f: np.ndarray, origin: np.ndarray, h: float,
            shape: np.ndarray) -> np.ndarray:
    """Boolean grid: voxel centres inside the closed surface, by the parity of the
    crossings of rays along +x through each (y, z) column."""
    tri = (v[f] - origin) / h  # in voxel units: centre k at coordinate k
    y, z = tri[:, :, 1], tri[:, :, 2]
    # signed double area of each triangle's (y, z) shadow; edge-on triangles are skipped
    area = (y[:, 1] - y[:, 0]) * (z[:, 2] - z[:, 0]) - (y[:, 2] - y[:, 0]) * (z[:, 1] - z[:, 0])
    keep = area != 0
    tri, y, z, area = tri[keep], y[keep], z[keep], area[keep]
    y0, y1 = np.ceil(y.min(axis=1)).astype(np.int64), np.floor(y.max(axis=1)).astype(np.int64)
    z0, z1 = np.ceil(z.min(axis=1)).astype(np.int64), np.floor(z.max(axis=1)).astype(np.int64)
    ny, nz = np.maximum(y1 - y0 + 1, 0), np.maximum(z1 - z0 + 1, 0)
    toggles = np.zeros(tuple(shape), dtype=np.int8)
    counts = ny * nz
    # candidate columns of each triangle, in batches of about a million
    order = np.cumsum(counts)
    start = 0
    while start < len(tri):
        stop = int(np.searchsorted(order, order[start] - counts[start] + 1_000_000,
                                   side="right"))
        stop = max(stop, start + 1)
        sel = np.arange(start, stop)
        rep = np.repeat(sel, counts[sel])
        if len(rep):
            local = np.arange(len(rep)) - np.repeat(np.cumsum(counts[sel]) - counts[sel],
                                                   counts[sel])
            cy = y0[rep] + local // np.maximum(nz[rep], 1)
            cz = z0[rep] + local % np.maximum(nz[rep], 1)
            _toggle(toggles, tri[rep], y[rep], z[rep], area[rep], cy, cz, shape)
        start = stop
    inside: np.ndarray = (np.cumsum(toggles, axis=0, dtype=np.int32) % 2).astype(bool)
    return inside


def _toggle(toggles: np.ndarray, tri: np.ndarray, y: np.ndarray, z: np.ndarray,
            area: np.ndarray, cy: np.ndarray, cz: np.ndarray, shape: np.ndarray) -> None:
    """Mark where each column's ray crosses its triangle (barycentric in the shadow)."""
    py, pz = cy.astype(np.float64), cz.astype(np.float64)
    w0 = (y[:, 1] - py) * (z[:, 2] - pz) - (y[:, 2] - py) * (z[:, 1] - pz)
    w1 = (y[:, 2] - py) * (z[:, 0] - pz) - (y[:, 0] - py) * (z[:, 2] - pz)
    w2 = area - w0 - w1
    sign = np.sign(area)
    hit = (w0 * sign >= 0) & (w1 * sign >= 0) & (w2 * sign > 0)
    if not hit.any():
        return
    x = (w0 * tri[:, 0, 0] + w1 * tri[:, 1, 0] + w2 * tri[:, 2, 0]) / area
    ix = np.clip(np.ceil(x[hit]).astype(np.int64), 0, shape[0] - 1)
    np.add.at(toggles, (ix, cy[hit], cz[hit]), 1)
