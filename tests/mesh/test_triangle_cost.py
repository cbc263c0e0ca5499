"""The hole triangulation's dynamic programme against a plain one, triangle by triangle.

The reference below costs each candidate triangle on its own (one cross product, one
norm, the rim angles of its polygon edges) and fills the interval table with three nested
loops, taking the first smallest split (the first NaN, as ``np.argmin`` does). The
vectorised programme must choose exactly the same triangles: its costs are the same
floating-point operations in the same order, whatever the batch and its padding.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from urdfinertia.mesh.repair import triangulation
from urdfinertia.mesh.repair.triangulation import best_triangulations, size_bands


def triangle_cost(points, rim, i, k, j, scale):
    """One candidate's cost: area term, plus the rim angle across each polygon edge."""
    s = len(points)
    a, b = points[k] - points[j], points[i] - points[j]
    cross = [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]
    norm = math.sqrt(cross[0] * cross[0] + cross[1] * cross[1] + cross[2] * cross[2])
    area_scale = scale ** 2
    degenerate = norm <= 1e-12 * area_scale
    # IEEE division (0 / 0 is NaN, not an exception)
    cost = float(np.divide(triangulation.AREA_WEIGHT * 0.5 * norm, area_scale))
    den = max(norm, 1e-300)
    for on, edge in ((k == i + 1, i), (j == k + 1, k), (i == 0 and j == s - 1, s - 1)):
        if on:
            cos = cross[0] / den * rim[edge][0] + cross[1] / den * rim[edge][1] \
                + cross[2] / den * rim[edge][2]
            # np.arccos, as the programme takes it (its last bit may differ from libm's)
            angle = float(np.arccos(np.array([min(max(cos, -1.0), 1.0)]))[0])
            cost = cost + (math.pi if degenerate else angle)
    return cost


def reference(points, rim):
    """Triangles (j, k, i) of the plain O(s^3) programme, breadth-first."""
    s = len(points)
    points, rim = points.tolist(), rim.tolist()
    scale = float(np.sum(np.linalg.norm(np.diff(np.array(points), axis=0), axis=1)))
    scale = max(scale, 1e-300)
    pts = [np.array(p) for p in points]
    cost = {(i, i + 1): 0.0 for i in range(s - 1)}
    split = {}
    for gap in range(2, s):
        for i in range(s - gap):
            j = i + gap
            best, best_k = None, None
            for k in range(i + 1, j):
                c = (cost[i, k] + cost[k, j]) + triangle_cost(pts, rim, i, k, j, scale)
                if math.isnan(c):
                    best, best_k = c, k
                    break
                if best is None or c < best:
                    best, best_k = c, k
            cost[i, j], split[i, j] = best, best_k
    out, level = [], [(0, s - 1)]
    while level:
        level = [(lo, hi) for lo, hi in level if hi - lo >= 2]
        out += [(hi, split[lo, hi], lo) for lo, hi in level]
        level = [(lo, split[lo, hi]) for lo, hi in level] + [(split[lo, hi], hi)
                                                              for lo, hi in level]
    return np.array(out, dtype=np.int64).reshape(-1, 3)


def polygons(rng, s):
    """Random and degenerate polygons of ``s`` corners with unit rim normals."""
    out = []
    out.append(rng.normal(size=(s, 3)))  # generic
    planar = rng.normal(size=(s, 3))
    planar[:, 2] = 0.0  # planar: many candidates in one plane
    out.append(planar)
    repeated = np.round(rng.normal(size=(s, 3)))
    repeated[1] = repeated[0]  # a repeated corner: a degenerate triangle
    out.append(repeated)
    out.append(np.linspace(0.0, 1.0, s)[:, None] * np.array([1.0, 2.0, 3.0]))  # collinear
    angle = 2.0 * np.pi * np.arange(s) / s
    out.append(np.stack([np.cos(angle), np.sin(angle), np.zeros(s)], axis=1))  # ties
    rims = []
    for k in range(len(out)):
        rim = rng.normal(size=(s, 3))
        if k >= 3:  # symmetric cases: the same rim everywhere, so costs tie
            rim[:] = [0.0, 0.0, 1.0]
        rims.append(rim / np.linalg.norm(rim, axis=1, keepdims=True))
    return np.array(out), np.array(rims)


@pytest.mark.parametrize("s", [3, 4, 5, 6, 7, 9, 12, 17, 41])
def test_programme_chooses_the_reference_triangles(s):
    rng = np.random.default_rng(s)
    points, rim = polygons(rng, s)
    tris, poly = best_triangulations(points, rim, np.full(len(points), s))
    assert tris.shape == (len(points) * (s - 2), 3)
    assert np.array_equal(poly, np.repeat(np.arange(len(points)), s - 2))
    for p in range(len(points)):
        np.testing.assert_array_equal(tris[poly == p], reference(points[p], rim[p]))


def test_every_corner_at_one_place_chooses_as_argmin_does():
    """Zero perimeter: every cost is NaN (0 / 0) and the first split is taken."""
    points, rim = np.zeros((1, 6, 3)), np.tile([0.0, 0.0, 1.0], (1, 6, 1))
    with np.errstate(invalid="ignore", divide="ignore"):
        tris, _ = best_triangulations(points, rim, np.array([6]))
        np.testing.assert_array_equal(tris, reference(points[0], rim[0]))


def test_mixed_sizes_padding_and_batches_change_nothing(monkeypatch):
    rng = np.random.default_rng(7)
    sizes = np.array([4, 9, 5, 12, 3, 12, 7])
    s = int(sizes.max())
    points = rng.normal(size=(len(sizes), s, 3)) * 1e3  # the padding: arbitrary values
    rim = rng.normal(size=(len(sizes), s, 3))
    rim /= np.linalg.norm(rim, axis=2, keepdims=True)
    tris, poly = best_triangulations(points, rim, sizes)
    assert np.array_equal(poly, np.repeat(np.arange(len(sizes)), sizes - 2))
    for p, size in enumerate(sizes):
        alone, _ = best_triangulations(points[p:p + 1, :size], rim[p:p + 1, :size],
                                       np.array([size]))
        np.testing.assert_array_equal(tris[poly == p], alone)
        np.testing.assert_array_equal(alone, reference(points[p, :size], rim[p, :size]))
    monkeypatch.setattr(triangulation, "ALL_AT_ONCE_MAX", 3)
    monkeypatch.setattr(triangulation, "BATCH_CANDIDATES", 1)  # one polygon per batch
    again, again_poly = best_triangulations(points, rim, sizes)
    np.testing.assert_array_equal(again, tris)
    np.testing.assert_array_equal(again_poly, poly)


def test_sizes_are_checked():
    with pytest.raises(ValueError, match="sizes"):
        best_triangulations(np.zeros((2, 5, 3)), np.zeros((2, 5, 3)), np.array([5, 6]))
    with pytest.raises(ValueError, match="shape"):
        best_triangulations(np.zeros((2, 5)), np.zeros((2, 5)), np.array([5, 5]))


@pytest.mark.parametrize("sizes, counts", [
    ([4, 5, 6, 40, 41, 200], [1000, 3, 1, 1, 1, 1]),
    ([4], [1]),
    ([], []),
    (list(range(4, 201)), [1] * 197),
])
def test_size_bands_cover_every_group_once_in_order(sizes, counts):
    bands = size_bands(sizes, counts)
    assert [g for band in bands for g in band] == list(range(len(sizes)))
    assert all(len(band) > 0 for band in bands)
