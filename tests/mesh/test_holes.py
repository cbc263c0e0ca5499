"""Hole caps, boundary cycles and winding numbers on small constructed cases."""

from __future__ import annotations

import numpy as np
import pytest
import trimesh

from urdfinertia.inertia.polyhedron import solid_integrals
from urdfinertia.mesh.repair.graph import (
    boundary_edges,
    cancel_duplicate_faces,
    consistent_orientation,
    edge_table,
)
from urdfinertia.mesh.repair.holes import close_holes
from urdfinertia.mesh.repair.loops import boundary_cycles
from urdfinertia.mesh.repair.winding import winding_numbers


def cube() -> tuple[np.ndarray, np.ndarray]:
    box = trimesh.creation.box([1.0, 1.0, 1.0])
    return np.asarray(box.vertices), np.asarray(box.faces)


def test_winding_number_inside_outside_and_inverted(rng) -> None:
    sphere = trimesh.creation.icosphere(3, 1.0)
    pts = rng.uniform(-1.5, 1.5, (200, 3))
    r = np.linalg.norm(pts, axis=1)
    pts = pts[np.abs(r - 1.0) > 0.05]  # away from the faceted surface
    w = winding_numbers(pts, sphere.vertices, sphere.faces)
    np.testing.assert_allclose(w, (np.linalg.norm(pts, axis=1) < 1.0).astype(float),
                               atol=1e-9)
    w_inv = winding_numbers(pts, sphere.vertices, sphere.faces[:, ::-1])
    np.testing.assert_allclose(w_inv, -w, atol=1e-12)


def test_missing_cube_faces_are_closed_exactly() -> None:
    """Holes on a cube: one missing triangle is planar; larger ones are re-triangulated."""
    v, f = cube()
    for drop in ([0], [0, 1]):
        keep = np.delete(f, drop, axis=0)
        cv, cf, caps = close_holes(v, keep)
        assert len(boundary_edges(cf)) == 0
        assert solid_integrals(cv, cf)[0] == pytest.approx(1.0, rel=1e-12)
        assert caps.planar.all() == (len(drop) == 1)


def test_lost_corner_vertex_is_estimated_not_claimed_exact() -> None:
    """All faces of a cube corner gone: the corner vertex is lost, so is 1/6 of the volume."""
    v, f = cube()
    corner = np.flatnonzero((f == 0).any(axis=1))
    cv, cf, caps = close_holes(v, np.delete(f, corner, axis=0))
    assert solid_integrals(cv, cf)[0] == pytest.approx(5 / 6, rel=1e-12)
    assert not caps.planar.any() and caps.uncertainty.sum() > 0


def test_triangulation_restores_a_pair_across_a_sharp_edge() -> None:
    """Two faces meeting at a cube edge go missing: a fan would cut the corner off."""
    v, f = cube()
    edge_id = edge_table(f).edge_id
    order = np.argsort(edge_id, kind="stable")
    pairs = order.reshape(-1, 2) // 3  # the two faces of each edge of a closed mesh
    n = np.cross(v[f[:, 1]] - v[f[:, 0]], v[f[:, 2]] - v[f[:, 0]])
    sharp = pairs[np.abs(np.einsum("ij,ij->i", n[pairs[:, 0]], n[pairs[:, 1]])) < 1e-12]
    cv, cf, caps = close_holes(v, np.delete(f, sharp[0], axis=0))
    assert solid_integrals(cv, cf)[0] == pytest.approx(1.0, rel=1e-12)
    assert caps.loops == 1


def test_bowtie_hole_splits_into_two_cycles() -> None:
    """Two missing triangles sharing only a corner are two holes, not one."""
    sphere = trimesh.creation.icosphere(2, 1.0)
    f = np.asarray(sphere.faces)
    v = np.asarray(sphere.vertices)
    corner = f[0, 0]
    touching = np.flatnonzero((f == corner).any(axis=1))
    # two faces at the corner that share no edge
    a = touching[0]
    b = next(t for t in touching[1:] if len(set(f[a]) & set(f[t])) == 1)
    keep = np.delete(f, [a, b], axis=0)
    edges = boundary_edges(keep)
    _, cycle = boundary_cycles(v, keep, edges)
    assert len(edges) == 6 and cycle.max() + 1 == 2


def test_orientation_propagation_and_duplicates(rng) -> None:
    v, f = cube()
    flipped = f.copy()
    pick = rng.permutation(len(f))[:5]
    flipped[pick] = flipped[pick][:, ::-1]
    flip, patch, non_orientable = consistent_orientation(flipped)
    fixed = np.where(flip[:, None], flipped[:, ::-1], flipped)
    assert abs(solid_integrals(v, fixed)[0]) == pytest.approx(1.0, rel=1e-12)
    assert patch.max() == 0 and not non_orientable.any()
    out, repeats, cancelled = cancel_duplicate_faces(np.concatenate([f, f]))
    assert (len(out), repeats, cancelled) == (len(f), len(f), 0)  # exported twice
    out, repeats, cancelled = cancel_duplicate_faces(np.concatenate([f, f[:2, ::-1]]))
    assert (len(out), repeats, cancelled) == (len(f) - 2, 0, 2)  # a shared inner wall
