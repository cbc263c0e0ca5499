"""Mesh geoms against MuJoCo's ``inertia="exact"``: MuJoCo re-centres and re-orients each
mesh for itself, the tool integrates the file where it lies in the geom frame; the body
must come out the same."""

from __future__ import annotations

import numpy as np
import pytest
import trimesh
from support.mjcf import body_inertia, compiled

from urdfinertia.body.options import FixOptions
from urdfinertia.plan.fix import fix_file

mujoco = pytest.importorskip("mujoco")

#: MuJoCo stores mesh vertices as float32: relative agreement to about 1e-6.
RTOL = 2e-6


def _write_meshes(folder):
    folder.mkdir()
    ring = trimesh.creation.annulus(r_min=0.03, r_max=0.06, height=0.02)  # not convex
    ring.apply_translation([0.1, 0.02, -0.03])
    ring.export(folder / "ring.stl")
    box = trimesh.creation.box(extents=[0.2, 0.1, 0.05])
    box.apply_transform(trimesh.transformations.euler_matrix(0.3, 0.2, 0.1))
    box.apply_translation([0.3, 0.0, 0.05])
    box.export(folder / "part.obj")


MODEL = """<mujoco model="meshes">
  <compiler meshdir="assets" angle="radian"/>
  <asset>
    <mesh name="ring" file="ring.stl"/>
    <mesh name="ring_scaled" file="ring.stl" scale="2 1 0.5"/>
    <mesh name="ring_ref" file="ring.stl" refpos="0.05 0 0.01" refquat="0.9 0.1 0.2 0.3"/>
    <mesh file="part.obj"/>
  </asset>
  <worldbody>
    <body name="ring"><joint/>
      <geom type="mesh" mesh="ring" pos="0.1 0 0" euler="0.1 0.2 0.3"/>
    </body>
    <body name="scaled"><joint/><geom type="mesh" mesh="ring_scaled"/></body>
    <body name="ref"><joint/><geom type="mesh" mesh="ring_ref" quat="0 1 0 0"/></body>
    <body name="mixed"><joint/>
      <geom type="mesh" mesh="part"/>
      <geom type="mesh" mesh="ring" density="3000"/>
      <geom type="sphere" size="0.02" pos="0 0 0.2"/>
    </body>
  </worldbody>
</mujoco>
"""


def test_mesh_bodies_match_mujoco_exact(tmp_path):
    _write_meshes(tmp_path / "assets")
    path = tmp_path / "meshes.xml"
    path.write_text(MODEL)
    result = fix_file(path, FixOptions(recompute="all", mass="density"))
    model = compiled(path, exact_meshes=True)
    for r in result.links:
        mass, com, tensor = body_inertia(model, r.name)
        total = r.assembly.total
        np.testing.assert_allclose(total.mass, mass, rtol=RTOL, err_msg=r.name)
        np.testing.assert_allclose(total.com, com, atol=RTOL * 0.3, err_msg=r.name)
        np.testing.assert_allclose(total.inertia, tensor, rtol=RTOL,
                                   atol=RTOL * float(np.abs(tensor).max()), err_msg=r.name)


def test_mujoco_default_mesh_inertia_overcounts_a_concave_mesh(tmp_path):
    """The reason to use the tool: MuJoCo's legacy mode fills the ring's hole."""
    _write_meshes(tmp_path / "assets")
    path = tmp_path / "meshes.xml"
    path.write_text(MODEL)
    ours = fix_file(path, FixOptions(recompute="all", mass="density")).links[0].assembly.total.mass
    legacy = body_inertia(compiled(path), "ring")[0]
    assert legacy > 1.2 * ours


def _write_msh(path, vertices, faces):
    v = np.asarray(vertices, dtype="<f4")
    f = np.asarray(faces, dtype="<i4")
    header = np.array([len(v), 0, 0, len(f)], dtype="<i4")
    path.write_bytes(header.tobytes() + v.tobytes() + f.tobytes())


def test_msh_meshes_match_mujoco_exact(tmp_path):
    """MuJoCo's own binary format, with faces and without (the hull of the vertices)."""
    folder = tmp_path / "assets"
    folder.mkdir()
    box = trimesh.creation.box(extents=[0.2, 0.1, 0.05])
    box.apply_translation([0.05, 0.0, 0.1])
    _write_msh(folder / "box.msh", box.vertices, box.faces)
    rng = np.random.default_rng(7)
    _write_msh(folder / "cloud.msh", rng.normal(size=(40, 3)) * [0.1, 0.05, 0.02], [])
    path = tmp_path / "msh.xml"
    path.write_text('<mujoco><compiler meshdir="assets"/><asset><mesh file="box.msh"/>'
                    '<mesh file="cloud.msh"/></asset><worldbody>'
                    '<body name="box"><joint/><geom type="mesh" mesh="box"/></body>'
                    '<body name="cloud"><joint/><geom type="mesh" mesh="cloud"/></body>'
                    "</worldbody></mujoco>")
    result = fix_file(path, FixOptions(recompute="all", mass="density"))
    model = compiled(path, exact_meshes=True)
    for r in result.links:
        mass, com, tensor = body_inertia(model, r.name)
        total = r.assembly.total
        np.testing.assert_allclose(total.mass, mass, rtol=RTOL, err_msg=r.name)
        np.testing.assert_allclose(total.com, com, atol=RTOL * 0.3, err_msg=r.name)
        np.testing.assert_allclose(total.inertia, tensor, rtol=RTOL,
                                   atol=RTOL * float(np.abs(tensor).max()), err_msg=r.name)
