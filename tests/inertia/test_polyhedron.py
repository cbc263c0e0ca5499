"""polyhedron.py: exact integrals against independent implementations.

MuJoCo's ``inertia="exact"`` mesh inertia is an independent exact implementation; it
stores vertices in single precision, which limits agreement to about 1e-7, so 1e-6
relative is asserted. trimesh's own integrator (double precision) agrees to ~1e-10.
"""

from pathlib import Path

import numpy as np
import pytest
import trimesh

from urdfinertia.inertia.polyhedron import mesh_mass_properties, solid_integrals
from urdfinertia.mesh.read.load import load_mesh

mujoco = pytest.importorskip("mujoco")


def mujoco_exact(vertices: np.ndarray, faces: np.ndarray, density: float):
    vs = " ".join(repr(x) for x in vertices.ravel().tolist())
    fs = " ".join(str(i) for i in faces.ravel().tolist())
    xml = (f'<mujoco><asset><mesh name="m" vertex="{vs}" face="{fs}" inertia="exact"/>'
           f'</asset><worldbody><body><freejoint/><geom type="mesh" mesh="m" '
           f'density="{density}"/></body></worldbody></mujoco>')
    model = mujoco.MjModel.from_xml_string(xml)
    return float(model.body_mass[1]), model.body_ipos[1].copy(), np.sort(model.body_inertia[1])


def closed_test_meshes():
    yield "annulus", trimesh.creation.annulus(0.05, 0.1, 0.2, sections=48)
    yield "torus", trimesh.creation.torus(0.2, 0.05, major_sections=48, minor_sections=24)
    box = trimesh.creation.box([0.2, 0.1, 0.4])
    box.apply_transform(trimesh.transformations.random_rotation_matrix(
        np.random.default_rng(7).random(3)))
    box.apply_translation([0.5, -0.2, 1.0])
    yield "offset rotated box", box


@pytest.mark.parametrize("name, mesh", list(closed_test_meshes()))
def test_agrees_with_mujoco_exact(name, mesh):
    ours = mesh_mass_properties(mesh.vertices, mesh.faces, 1000.0)
    mass, com, moments = mujoco_exact(mesh.vertices, mesh.faces, 1000.0)
    assert ours.mass == pytest.approx(mass, rel=1e-6)
    np.testing.assert_allclose(ours.com, com, atol=1e-6 * np.ptp(mesh.vertices, axis=0).max())
    np.testing.assert_allclose(np.sort(ours.principal()[0]), moments, rtol=1e-6)


def real_closed_meshes(erd_dir: Path):
    names = ["ur_description/meshes/ur5/collision/forearm.stl",
             "panda_description/meshes/collision/link3.stl",
             "solo_description/meshes/stl/solo_upper_leg_left_side.stl"]
    for rel in names:
        path = erd_dir / "robots" / rel
        if not path.is_file():
            continue
        m = load_mesh(path)
        tm = trimesh.Trimesh(m.vertices, m.faces, process=True)
        if tm.is_watertight and tm.is_winding_consistent:
            yield rel, tm


def test_real_closed_meshes_agree_with_mujoco(erd_dir):
    found = list(real_closed_meshes(erd_dir))
    assert found, "expected at least one watertight real mesh to compare"
    for rel, tm in found:
        ours = mesh_mass_properties(tm.vertices, tm.faces, 1000.0)
        if ours.mass < 0:
            ours = mesh_mass_properties(tm.vertices, tm.faces[:, ::-1], 1000.0)
        mass, _, moments = mujoco_exact(tm.vertices, tm.faces, 1000.0)
        assert ours.mass == pytest.approx(mass, rel=1e-6), rel
        np.testing.assert_allclose(np.sort(ours.principal()[0]), moments, rtol=1e-6,
                                   err_msg=rel)


def test_agrees_with_trimesh_integrator():
    mesh = trimesh.creation.torus(0.3, 0.1, major_sections=32, minor_sections=16)
    mesh.apply_translation([10.0, -3.0, 2.0])
    ours = mesh_mass_properties(mesh.vertices, mesh.faces, 1.0)
    theirs = mesh.mass_properties
    assert ours.mass == pytest.approx(theirs.mass, rel=1e-10)
    np.testing.assert_allclose(ours.com, theirs.center_mass, rtol=1e-10)
    np.testing.assert_allclose(ours.inertia, theirs.inertia, rtol=1e-8, atol=1e-12)


def test_far_offset_keeps_precision():
    # Centring on the vertex centroid keeps the tensor exact 1 km from the origin.
    box = trimesh.creation.box([0.1, 0.2, 0.3])
    near = mesh_mass_properties(box.vertices, box.faces, 1000.0)
    far = mesh_mass_properties(box.vertices + 1000.0, box.faces, 1000.0)
    np.testing.assert_allclose(far.inertia, near.inertia, rtol=1e-7, atol=1e-9 * near.inertia.max())


def test_inverted_mesh_has_negative_signed_volume():
    box = trimesh.creation.box([1.0, 1.0, 1.0])
    volume, _, _ = solid_integrals(box.vertices, box.faces[:, ::-1])
    assert volume == pytest.approx(-1.0)
    with pytest.raises(ValueError, match="positive"):
        mesh_mass_properties(box.vertices, box.faces[:, ::-1], 1.0)
