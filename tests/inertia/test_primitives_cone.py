"""primitives.cone: the closed form against a finely meshed cone (trimesh.creation.cone)."""

import numpy as np
import pytest
import trimesh

from urdfinertia.inertia import primitives
from urdfinertia.inertia.polyhedron import mesh_mass_properties

RHO = 1234.0
SECTIONS = 512


def test_cone_converges_to_closed_form():
    r, h = 0.07, 0.3
    closed = primitives.cone(r, h, RHO)
    # trimesh's cone has its base at z = 0 and apex at z = h: shift to USD's centring
    mesh = trimesh.creation.cone(radius=r, height=h, sections=SECTIONS)
    mesh.apply_translation([0.0, 0.0, -h / 2.0])
    meshed = mesh_mass_properties(mesh.vertices, mesh.faces, RHO)
    # an inscribed 512-gon loses 1 - sin(2 pi / n) n / (2 pi) ~ 2.5e-5 of the base area;
    # second moments about the axis lose about twice that
    shortfall = 1.0 - np.sin(2.0 * np.pi / SECTIONS) * SECTIONS / (2.0 * np.pi)
    tol = 4.0 * shortfall
    assert meshed.mass < closed.mass
    assert meshed.mass == pytest.approx(closed.mass, rel=tol)
    np.testing.assert_allclose(meshed.com, closed.com, atol=1e-12)
    np.testing.assert_allclose(np.diag(meshed.inertia), np.diag(closed.inertia), rtol=tol)


def test_cone_centre_of_mass_is_a_quarter_above_the_base():
    c = primitives.cone(1.0, 2.0, 1.0)
    assert c.com[2] == pytest.approx(-0.5)  # base at -1, a quarter of 2 above it
    assert c.mass == pytest.approx(2.0 * np.pi / 3.0)


def test_cone_refuses_a_zero_height():
    with pytest.raises(ValueError, match="cone"):
        primitives.cone(0.1, 0.0, RHO)
