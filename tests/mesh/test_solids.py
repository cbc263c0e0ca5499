"""Solid / MeshSolids: scaling (mirroring), mass properties and the two-stage API."""

from __future__ import annotations

import pickle

import numpy as np
import pytest
import trimesh

from urdfinertia.mesh.read.load import TriangleMesh
from urdfinertia.mesh.repair.pipeline import repair_mesh
from urdfinertia.mesh.solids import integrate_repaired, mesh_solids


@pytest.fixture
def box_solids():
    box = trimesh.creation.box([0.2, 0.4, 0.6])
    box.apply_translation([0.1, -0.2, 0.3])
    return box, mesh_solids(TriangleMesh(np.asarray(box.vertices), np.asarray(box.faces)))


def test_closed_box_is_exact(box_solids) -> None:
    box, solids = box_solids
    (solid,) = solids.solids
    assert solid.method == "exact (closed mesh)" and solid.error_estimate == 0.0
    mp = solid.mass_properties(1000.0)
    assert mp.mass == pytest.approx(1000.0 * 0.2 * 0.4 * 0.6, rel=1e-12)
    np.testing.assert_allclose(mp.com, [0.1, -0.2, 0.3], atol=1e-12)
    # closed form 1/12 m (b^2 + c^2) ...; round-off only
    m = mp.mass
    np.testing.assert_allclose(np.diag(mp.inertia), [m / 12 * (0.16 + 0.36),
                                                     m / 12 * (0.04 + 0.36),
                                                     m / 12 * (0.04 + 0.16)], rtol=1e-12)


@pytest.mark.parametrize("scale", [[2.0, 1.0, 0.5], [-1.0, 1.0, 1.0], [1.0, -3.0, -1.0]])
def test_scaling_equals_integrating_the_scaled_mesh(box_solids, rng, scale) -> None:
    """``scaled`` after integration equals integrating the scaled (re-oriented) mesh."""
    box, solids = box_solids
    s = np.asarray(scale)
    direct = mesh_solids(TriangleMesh(np.asarray(box.vertices) * s, np.asarray(box.faces)))
    got = solids.scaled(s).solids[0]
    want = direct.solids[0]
    assert got.volume == pytest.approx(want.volume, rel=1e-12) and got.volume > 0
    np.testing.assert_allclose(got.first, want.first, rtol=1e-12, atol=1e-15)
    np.testing.assert_allclose(got.second, want.second, rtol=1e-12, atol=1e-15)


def test_stages_compose_and_results_pickle(box_solids) -> None:
    box, _ = box_solids
    mesh = TriangleMesh(np.asarray(box.vertices), np.asarray(box.faces)[:-1])  # one hole
    repaired = repair_mesh(mesh)
    again = pickle.loads(pickle.dumps(repaired))
    a, b = integrate_repaired(again), mesh_solids(mesh)
    assert a.solids[0].volume == b.solids[0].volume
    assert a.solids[0].method == b.solids[0].method == "exact after closing 1 planar holes"
    c = pickle.loads(pickle.dumps(b))
    np.testing.assert_array_equal(c.solids[0].second, b.solids[0].second)
