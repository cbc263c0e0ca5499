"""MJCF reading against MuJoCo's own compiler: what ``fix --mass density`` computes for each
body equals the mass, CoM and tensor MuJoCo compiles from the same geoms."""

from __future__ import annotations

import numpy as np
import pytest
from support.mjcf import body_inertia, compiled

from urdfinertia.body.options import FixOptions
from urdfinertia.descriptions.formats import read_description
from urdfinertia.plan.fix import fix_file

mujoco = pytest.importorskip("mujoco")

#: Closed forms against MuJoCo's closed forms: only round-off differs (rtol), and MuJoCo
#: sets tiny products of inertia to exactly 0 after its eigen decomposition (atol).
RTOL = 1e-9


BY_DENSITY = FixOptions(recompute="all", mass="density")


def _check_against_mujoco(path, names=None, options=BY_DENSITY, exact_meshes=False,
                          rtol=RTOL):
    result = fix_file(path, options)
    model = compiled(path, exact_meshes=exact_meshes)
    checked = 0
    for r in result.links:
        if names is not None and r.name not in names:
            continue
        assert r.assembly is not None, (r.name, r.warnings)
        mass, com, tensor = body_inertia(model, r.name)
        ours = r.assembly.total
        scale = float(np.abs(tensor).max())
        np.testing.assert_allclose(ours.mass, mass, rtol=rtol, err_msg=r.name)
        np.testing.assert_allclose(ours.com, com, rtol=rtol, atol=rtol * 1.0, err_msg=r.name)
        np.testing.assert_allclose(ours.inertia, tensor, rtol=rtol, atol=rtol * scale,
                                   err_msg=r.name)
        checked += 1
    return result, checked


PRIMITIVES = """<mujoco model="prims">
  {compiler}
  <worldbody>
    <body name="box" pos="1 0 0"><freejoint/>
      <geom type="box" size="0.1 0.2 0.3" pos="0.1 0.2 0.3" euler="10 20 30"/>
    </body>
    <body name="sphere"><joint type="hinge"/>
      <geom type="sphere" size="0.15" pos="0 0 0.4"/>
      <geom type="box" size="0.05 0.05 0.05" quat="0.9 0.1 0.3 -0.2"/>
    </body>
    <body name="capsule"><joint type="slide"/>
      <geom type="capsule" size="0.05 0.2" axisangle="1 1 0 45"/>
    </body>
    <body name="capsule_fromto"><joint/>
      <geom type="capsule" fromto="0 0 0 0.3 0.4 0.5" size="0.04"/>
      <geom type="capsule" fromto="0 0 0 0 0 -0.3" size="0.02"/>
    </body>
    <body name="cylinder"><joint/>
      <geom type="cylinder" size="0.1 0.25" xyaxes="0 1 0 -1 0 0.2"/>
      <geom type="cylinder" fromto="-0.1 0.2 0 0.3 0.2 0.1" size="0.03"/>
    </body>
    <body name="ellipsoid"><joint/>
      <geom type="ellipsoid" size="0.1 0.2 0.3" zaxis="1 2 3" pos="0 0.1 0"/>
    </body>
    <body name="fromto_box"><joint/>
      <geom type="box" fromto="0 0 0 0.1 0.5 0.2" size="0.05 0.3"/>
      <geom type="ellipsoid" fromto="0 0 0 -0.4 0.1 0" size="0.07"/>
    </body>
    <body name="framed"><joint/>
      <frame pos="0.2 0 0" euler="0 90 0">
        <geom type="box" size="0.1 0.02 0.05" pos="0 0.1 0" euler="30 0 0"/>
      </frame>
    </body>
    <body><joint/><geom type="sphere" size="0.1" pos="0.3 0 0"/></body>
  </worldbody>
</mujoco>
"""


@pytest.mark.parametrize("compiler", ["", '<compiler angle="degree"/>'])
def test_primitives_match_mujoco(tmp_path, compiler):
    path = tmp_path / "prims.xml"
    path.write_text(PRIMITIVES.format(compiler=compiler))
    _, checked = _check_against_mujoco(path)
    assert checked == 9  # the unnamed body is "body#9" and is checked too


def test_radian_and_euler_sequences_match_mujoco(tmp_path):
    body = """<body name="{n}"><joint/>
      <geom type="box" size="0.1 0.2 0.3" euler="0.3 -0.5 1.1" pos="0.1 0 0"/>
      <geom type="capsule" size="0.02 0.1" axisangle="0 1 1 0.7"/></body>"""
    for seq in ("xyz", "XYZ", "zyx", "ZYX", "xYz", "zxz"):
        path = tmp_path / f"{seq}.xml"
        path.write_text(f'<mujoco><compiler angle="radian" eulerseq="{seq}"/><worldbody>'
                        + body.format(n="b") + "</worldbody></mujoco>")
        _check_against_mujoco(path)
    # the same numbers read as degrees give a different (and still matching) body
    deg = tmp_path / "deg.xml"
    deg.write_text("<mujoco><worldbody>" + body.format(n="b") + "</worldbody></mujoco>")
    rad = tmp_path / "xyz.xml"
    a = fix_file(deg, FixOptions(recompute="all", mass="density")).links[0].assembly.total
    b = fix_file(rad, FixOptions(recompute="all", mass="density")).links[0].assembly.total
    assert not np.allclose(a.inertia, b.inertia)
    _check_against_mujoco(deg)


DEFAULTS = """<mujoco>
  <default>
    <geom type="box" size="0.1 0.1 0.1" density="500"/>
    <default class="arm">
      <geom type="capsule" size="0.03 0.2" euler="90 0 0"/>
      <default class="heavy"><geom density="7800"/></default>
    </default>
    <default class="visual"><geom contype="0" conaffinity="0" group="2" density="0"/></default>
    <default class="hidden"><geom group="7"/></default>
  </default>
  <worldbody>
    <body name="base"><freejoint/>
      <geom/>
      <geom class="arm" pos="0 0 0.3"/>
      <geom class="visual" type="sphere" size="0.5"/>
      <geom class="hidden" type="sphere" size="0.5"/>
      <body name="child" childclass="arm" pos="0 0 0.5"><joint/>
        <geom/>
        <geom class="heavy" size="0.01 0.05"/>
        <geom class="main" pos="0.2 0 0"/>
        <body name="grandchild" pos="0.1 0 0"><joint/>
          <geom type="sphere" size="0.05"/>
          <geom mass="2" type="box" size="0.02 0.02 0.2"/>
        </body>
      </body>
    </body>
  </worldbody>
</mujoco>
"""


def test_default_classes_and_childclass_match_mujoco(tmp_path):
    path = tmp_path / "defaults.xml"
    path.write_text(DEFAULTS)
    result, checked = _check_against_mujoco(path, options=FixOptions(recompute="all"))
    assert checked == 3
    robot, _ = read_description(path)
    base = robot.link("base")
    # the visual geom counts in MuJoCo (group 2) but states density 0; group 7 is outside
    # inertiagrouprange: neither is a part
    assert len(base.inertia_geometry) == 2
    assert [g.role for g in base.visuals] == ["visual"]
    assert {r.name: r.geometry for r in result.links} == {
        "base": "geom", "child": "geom", "grandchild": "geom"}


def test_inertiagrouprange_is_honoured(tmp_path):
    path = tmp_path / "groups.xml"
    path.write_text('<mujoco><compiler inertiagrouprange="1 2"/><worldbody><body name="b">'
                    '<joint/><geom type="box" size="0.1 0.1 0.1" group="1"/>'
                    '<geom type="sphere" size="0.3" pos="1 0 0"/></body></worldbody></mujoco>')
    _check_against_mujoco(path)


def test_existing_inertials_read_as_mujoco_compiles_them(tmp_path):
    path = tmp_path / "inertials.xml"
    path.write_text("""<mujoco><worldbody>
      <body name="full"><joint/><geom size="0.1"/>
        <inertial pos="0.1 -0.2 0.3" mass="2" fullinertia="0.3 0.4 0.5 0.01 -0.02 0.03"/>
      </body>
      <body name="diag"><joint/><geom size="0.1"/>
        <inertial pos="0 0 0.1" euler="10 20 30" mass="1.5" diaginertia="0.1 0.2 0.25"/>
      </body>
      <body name="quat"><joint/><geom size="0.1"/>
        <inertial pos="0 0 0.1" quat="0.5 0.5 0.5 0.5" mass="1" diaginertia="0.1 0.2 0.25"/>
      </body>
    </worldbody></mujoco>""")
    robot, _ = read_description(path)
    model = compiled(path)
    for link in robot.links:
        mass, com, tensor = body_inertia(model, link.name)
        assert link.inertial.mass == mass
        np.testing.assert_allclose(link.inertial.origin.xyz, com, atol=1e-12)
        np.testing.assert_allclose(link.inertial.tensor_in_link(), tensor, atol=1e-12)


def test_joints_from_nesting(tmp_path):
    path = tmp_path / "tree.xml"
    path.write_text("""<mujoco><worldbody>
      <body name="a" pos="0 0 1"><freejoint/><geom size="0.1"/>
        <body name="b" pos="0.5 0 0" euler="0 0 90"><geom size="0.1"/>
          <body name="c"><joint type="slide" name="j"/><geom size="0.1"/></body>
        </body>
      </body></worldbody></mujoco>""")
    robot, _ = read_description(path)
    assert robot.format == "mjcf"
    joints = {j.child: j for j in robot.joints}
    assert (joints["a"].type, joints["a"].parent) == ("floating", "world")
    assert (joints["b"].type, joints["b"].parent) == ("fixed", "a")
    assert (joints["c"].type, joints["c"].name) == ("prismatic", "j")
    np.testing.assert_allclose(joints["b"].origin.rpy, (0, 0, np.pi / 2), atol=1e-15)


def test_geom_problems_drop_the_geom_with_a_note(tmp_path):
    path = tmp_path / "bad.xml"
    path.write_text("""<mujoco><worldbody>
      <body name="b"><joint/>
        <geom type="box" size="0 0.1 0.1"/>
        <geom type="sphere" size="0.1"/>
        <geom type="plane" size="1 1 1"/>
      </body></worldbody></mujoco>""")
    result = fix_file(path, FixOptions(recompute="all", mass="density"))
    (link,) = result.links
    assert link.status == "recomputed"
    assert any("bad.xml:3" in (f.element or "") and "dropped" in f.message and "size" in
               f.message for f in link.findings)
    assert len(link.assembly.parts) == 1


def test_geom_materials_weigh_a_kept_mass(tmp_path):
    """A body with an <inertial> keeps its mass; its geoms' unequal densities and masses
    still say where it is: MuJoCo's geom-derived body, scaled to the kept mass."""
    body = """<body name="b"><joint/>{inertial}
      <geom type="box" size="0.1 0.1 0.1" density="7800"/>
      <geom type="sphere" size="0.1" pos="0.5 0 0" density="200"/>
      <geom type="capsule" size="0.02 0.1" pos="0 0.3 0" mass="0.7"/>
      <geom type="sphere" size="0.05" pos="0 0 -0.3"/></body>"""
    with_inertial = tmp_path / "kept.xml"
    with_inertial.write_text("<mujoco><worldbody>" + body.format(
        inertial='<inertial pos="0 0 0" mass="5" diaginertia="1 1 1"/>')
        + "</worldbody></mujoco>")
    from_geoms = tmp_path / "geoms.xml"
    from_geoms.write_text("<mujoco><worldbody>" + body.format(inertial="")
                          + "</worldbody></mujoco>")
    total = fix_file(with_inertial, FixOptions(recompute="all")).links[0].assembly.total
    mass, com, tensor = body_inertia(compiled(from_geoms), "b")
    assert total.mass == pytest.approx(5.0, rel=1e-12)
    np.testing.assert_allclose(total.com, com, atol=1e-12)
    np.testing.assert_allclose(total.inertia, tensor * 5.0 / mass, rtol=1e-9)


def test_mass_density_uses_stated_densities_of_bodies_with_inertials(tmp_path):
    """--mass density ignores the kept mass, not the geoms' stated densities."""
    path = tmp_path / "dens.xml"
    path.write_text('<mujoco><default><geom density="1"/></default><worldbody>'
                    '<body name="b"><joint/><inertial pos="0 0 0" mass="9" diaginertia="1 1 1"/>'
                    '<geom type="box" size=".1 .2 .3"/></body></worldbody></mujoco>')
    total = fix_file(path, FixOptions(recompute="all", mass="density")).links[0].assembly.total
    assert total.mass == pytest.approx(0.2 * 0.4 * 0.6, rel=1e-12)
    kept = fix_file(path, FixOptions(recompute="all")).links[0].assembly.total
    assert kept.mass == 9.0
