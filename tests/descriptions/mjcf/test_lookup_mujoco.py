"""Where MuJoCo looks things up, and the tool with it: default classes named by assets
that come before the ``<default>`` section, and meshes declared in an included file that
lie beside that file rather than under the main model's folder."""

from __future__ import annotations

import numpy as np
import pytest
import trimesh
from support.mjcf import body_inertia, compiled

from urdfinertia.body.options import FixOptions
from urdfinertia.plan.fix import fix_file

mujoco = pytest.importorskip("mujoco")


def _box(path, size):
    path.parent.mkdir(parents=True, exist_ok=True)
    trimesh.creation.box(extents=[size] * 3).export(path)


def _compare(path):
    result = fix_file(path, FixOptions(recompute="all", mass="density", geometry="collision"))
    model = compiled(path, exact_meshes=True)
    assert result.links, "no link read"
    for r in result.links:
        assert r.assembly is not None, (r.name, r.reason)
        mass, com, _ = body_inertia(model, r.name)
        np.testing.assert_allclose(r.assembly.total.mass, mass, rtol=1e-6, err_msg=r.name)
        np.testing.assert_allclose(r.assembly.total.com, com, atol=1e-7, err_msg=r.name)
    return result


def test_assets_before_defaults_use_the_classes(tmp_path):
    _box(tmp_path / "m" / "a.stl", 100.0)  # millimetres: the class scales them to metres
    path = tmp_path / "model.xml"
    path.write_text("""<mujoco>
  <compiler meshdir="m"/>
  <asset><mesh file="a.stl" class="arm"/></asset>
  <default><default class="arm"><mesh scale="0.001 0.001 0.001"/></default></default>
  <worldbody><body name="b"><freejoint/><geom type="mesh" mesh="a"/></body></worldbody>
</mujoco>""")
    result = _compare(path)
    assert result.links[0].assembly.total.mass == pytest.approx(1.0, rel=1e-6)  # 0.1 m cube


@pytest.mark.parametrize("main_copy", [False, True])
def test_mesh_of_an_included_file_beside_it(tmp_path, main_copy):
    """MuJoCo tries the main model's folder (with meshdir) first, then the included file's
    own folder; with a copy in both places the main folder's wins."""
    _box(tmp_path / "sub" / "m" / "a.stl", 0.1)
    if main_copy:
        _box(tmp_path / "m" / "a.stl", 0.3)
    (tmp_path / "sub" / "assets.xml").write_text(
        '<mujocoinclude><asset><mesh name="a" file="m/a.stl"/></asset></mujocoinclude>')
    path = tmp_path / "model.xml"
    path.write_text("""<mujoco><include file="sub/assets.xml"/>
  <worldbody><body name="b"><freejoint/><geom type="mesh" mesh="a"/></body></worldbody>
</mujoco>""")
    result = _compare(path)
    side = 0.3 if main_copy else 0.1
    assert result.links[0].assembly.total.mass == pytest.approx(1000 * side**3, rel=1e-6)


def test_bodies_inside_replicate_are_read_and_written_once_for_every_copy(tmp_path):
    """``<replicate>`` copies a body template; its written inertial serves every copy."""
    path = tmp_path / "model.xml"
    path.write_text("""<mujoco>
  <worldbody>
    <body name="base"><joint/>
      <geom type="box" size="0.1 0.1 0.1"/>
      <replicate count="3" offset="0.3 0 0">
        <body name="arm" pos="0 0 0.2"><joint/>
          <inertial pos="0 0 0" mass="2" diaginertia="1 1 5"/>
          <geom type="box" size="0.05 0.05 0.2"/>
        </body>
      </replicate>
    </body>
  </worldbody>
</mujoco>""")
    result = fix_file(path)
    arm = next(r for r in result.links if r.name == "arm")
    assert arm.changed, arm.decision  # 1 + 1 < 5: invalid, recomputed from the box
    out = tmp_path / "out.xml"
    result.save(out)
    model = compiled(out)
    new = arm.assembly.total
    copies = [i for i in range(model.nbody) if model.body(i).name.startswith("arm")]
    assert len(copies) == 3
    for i in copies:
        mass, com, tensor = body_inertia(model, model.body(i).name)
        np.testing.assert_allclose(mass, new.mass, rtol=1e-9)
        np.testing.assert_allclose(tensor, new.inertia, rtol=1e-5, atol=1e-12)
