"""The hole triangulation's cost evaluates rim angles on boundary edges only: the costs
must be bit for bit those of evaluating every candidate triangle (the plain form below)."""

from __future__ import annotations

import numpy as np
import pytest

from urdfinertia.mesh.repair import holes


def every_triangle_cost(points, rim, i, k, j, scale, s):
    """The cost with every candidate's rim angles evaluated, then masked (the oracle)."""
    pi, pk, pj = points[:, i], points[:, k], points[:, j]
    cross = np.cross(pk - pj, pi - pj)
    norm = np.linalg.norm(cross, axis=-1)
    unit = cross / np.maximum(norm, 1e-300)[..., None]
    area_scale = scale.reshape((-1,) + (1,) * i.ndim) ** 2
    degenerate = norm <= 1e-12 * area_scale
    cost = holes.AREA_WEIGHT * 0.5 * norm / area_scale

    def angle(edge_start):
        cos = np.sum(unit * rim[:, edge_start], axis=-1)
        return np.where(degenerate, np.pi, np.arccos(np.clip(cos, -1.0, 1.0)))

    cost = cost + np.where(k == i + 1, angle(i), 0.0) + np.where(j == k + 1, angle(k), 0.0)
    closing = (i == 0) & (j == s - 1)
    if closing.any():
        cost = cost + np.where(closing, angle(np.full_like(j, s - 1)), 0.0)
    return cost


@pytest.mark.parametrize("s", [4, 5, 9, 40, 41, 90])
def test_boundary_edge_angles_only_give_the_same_costs(s):
    rng = np.random.default_rng(s)
    points = rng.normal(size=(3, s, 3))
    points[0, :, 2] = 0.0  # a planar polygon: degenerate candidates
    points[1, 3] = points[1, 2]  # a repeated corner
    rim = rng.normal(size=(3, s, 3))
    rim /= np.linalg.norm(rim, axis=2, keepdims=True)
    i, k, j, _ = holes._plan(s)
    scale = np.sum(np.linalg.norm(np.diff(points, axis=1), axis=2), axis=1)
    got = holes._triangle_cost(points, rim, i, k, j, scale, s)
    want = every_triangle_cost(points, rim, i, k, j, scale, s)
    assert got.shape == want.shape
    np.testing.assert_array_equal(got, want)  # bit for bit: adding zeros is exact


def every_slot_plan(s):
    """The interval programme's index arrays with an (s, s, s) table of candidate ranks
    (the plain form :func:`holes._plan` computes by formula)."""
    r = np.arange(s)
    tri_i, tri_k, tri_j = (t.astype(np.int64) for t in np.nonzero(
        (r[:, None, None] < r[None, :, None]) & (r[None, :, None] < r[None, None, :])))
    slot = np.zeros((s, s, s), dtype=np.int64)
    slot[tri_i, tri_k, tri_j] = np.arange(len(tri_i))
    plan = []
    for gap in range(2, s):
        i = np.arange(s - gap)[:, None]
        j = i + gap
        k = i + np.arange(1, gap)[None, :]
        i, j, k = np.broadcast_arrays(i, j, k)
        plan.append((i * s + k, k * s + j, slot[i, k, j], i[:, 0] * s + j[:, 0],
                     i[:, 0][None, :] + 1))
    return tri_i, tri_k, tri_j, plan


@pytest.mark.parametrize("s", [3, 4, 5, 8, 13, 40, 41, 77])
def test_plan_ranks_by_formula_equal_the_table(s):
    want, got = every_slot_plan(s), holes._plan(s)
    for a, b in zip(want[:3], got[:3], strict=True):
        assert a.dtype == b.dtype and np.array_equal(a, b)
    assert len(want[3]) == len(got[3])
    for step_a, step_b in zip(want[3], got[3], strict=True):
        for a, b in zip(step_a, step_b, strict=True):
            assert a.shape == b.shape and np.array_equal(a, b)
