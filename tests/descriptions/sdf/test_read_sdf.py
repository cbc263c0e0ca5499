# ruff: noqa: E501 - SDF fixtures are easier to read one element per line
"""SDFormat reading: poses and frames as libsdformat resolves them, names, dropped elements."""

from __future__ import annotations

import math

import numpy as np
import pytest
from support.sdf import sdf_doc

from urdfinertia.descriptions.model import Box, Capsule, Cylinder, Ellipsoid, Mesh, Sphere
from urdfinertia.descriptions.sdf.read import robot_from_bytes
from urdfinertia.inertia.rotation import pose_matrix, rpy_matrix


def read(body: str, version: str = "1.11"):
    return robot_from_bytes(sdf_doc(body, version), "m.sdf")


def test_shapes_in_sdf_conventions():
    robot = read("""<model name="m"><link name="l">
      <collision name="b"><geometry><box><size>1 2 3</size></box></geometry></collision>
      <collision name="c"><geometry><cylinder><radius>0.5</radius><length>2</length></cylinder></geometry></collision>
      <collision name="s"><geometry><sphere><radius>0.25</radius></sphere></geometry></collision>
      <collision name="k"><geometry><capsule><radius>0.1</radius><length>0.4</length></capsule></geometry></collision>
      <collision name="e"><geometry><ellipsoid><radii>0.1 0.2 0.3</radii></ellipsoid></geometry></collision>
      <collision name="m"><geometry><mesh><uri>model://m/x.stl</uri><scale>0.001 0.001 0.001</scale></mesh></geometry></collision>
    </link></model>""")
    shapes = [c.shape for c in robot.links[0].collisions]
    assert shapes == [Box((1.0, 2.0, 3.0)), Cylinder(0.5, 2.0), Sphere(0.25), Capsule(0.1, 0.4),
                      Ellipsoid((0.1, 0.2, 0.3)), Mesh("model://m/x.stl", (0.001,) * 3)]


def test_relative_to_chain_through_frames_and_joints():
    # link b's collision is placed relative to frame g, which is relative to frame f,
    # attached to link a; the joint's pose is relative to its child link by default
    robot = read("""<model name="m">
      <link name="a"><pose>1 0 0 0 0 0.5</pose></link>
      <frame name="f" attached_to="a"><pose>0 1 0 0.2 0 0</pose></frame>
      <frame name="g"><pose relative_to="f">0 0 1 0 0.3 0</pose></frame>
      <link name="b"><pose relative_to="g">0.5 0 0 0 0 0</pose>
        <collision name="c"><pose relative_to="f">0 0 0.1 0 0 0</pose>
          <geometry><sphere><radius>0.1</radius></sphere></geometry></collision>
        <inertial><pose>0.1 0 0 0 0 0</pose><mass>1</mass></inertial>
      </link>
      <joint name="j" type="revolute"><parent>a</parent><child>b</child></joint>
    </model>""")
    x_a = pose_matrix((1, 0, 0), (0, 0, 0.5))
    x_f = x_a @ pose_matrix((0, 1, 0), (0.2, 0, 0))
    x_g = x_f @ pose_matrix((0, 0, 1), (0, 0.3, 0))
    x_b = x_g @ pose_matrix((0.5, 0, 0), (0, 0, 0))
    expected = np.linalg.inv(x_b) @ x_f @ pose_matrix((0, 0, 0.1), (0, 0, 0))
    b = robot.link("b")
    np.testing.assert_allclose(b.collisions[0].origin.matrix(), expected, atol=1e-12)
    assert b.inertial.origin.xyz == (0.1, 0.0, 0.0)  # relative to the link by default
    (joint,) = robot.joints
    np.testing.assert_allclose(joint.origin.matrix(), np.linalg.inv(x_a) @ x_b, atol=1e-12)


def test_rotation_formats_agree():
    rpy = (0.3, -0.4, 1.1)
    q = _quat_xyzw(rpy_matrix(rpy))
    deg = " ".join(str(math.degrees(a)) for a in rpy)
    robot = read(f"""<model name="m"><link name="l">
      <collision name="r"><pose>1 2 3 {rpy[0]} {rpy[1]} {rpy[2]}</pose>
        <geometry><sphere><radius>1</radius></sphere></geometry></collision>
      <collision name="d"><pose degrees="true">1 2 3 {deg}</pose>
        <geometry><sphere><radius>1</radius></sphere></geometry></collision>
      <collision name="q"><pose rotation_format="quat_xyzw">1 2 3 {' '.join(map(str, q))}</pose>
        <geometry><sphere><radius>1</radius></sphere></geometry></collision>
    </link></model>""")
    poses = [c.origin.matrix() for c in robot.links[0].collisions]
    for pose in poses[1:]:
        np.testing.assert_allclose(pose, poses[0], atol=1e-12)


def _quat_xyzw(r: np.ndarray) -> tuple[float, float, float, float]:
    w = math.sqrt(1.0 + np.trace(r)) / 2.0
    return ((r[2, 1] - r[1, 2]) / (4 * w), (r[0, 2] - r[2, 0]) / (4 * w),
            (r[1, 0] - r[0, 1]) / (4 * w), w)


def test_nested_and_several_models_are_scoped():
    one = read("""<model name="outer"><link name="base"/>
      <model name="inner"><pose>0 0 1 0 0 0</pose><link name="tip"><pose>0 0 1 0 0 0</pose></link></model>
      <joint name="j" type="fixed"><parent>base</parent><child>inner::tip</child></joint>
    </model>""")
    assert [link.name for link in one.links] == ["base", "inner::tip"]
    np.testing.assert_allclose(one.joints[0].origin.xyz, (0, 0, 2))
    two = read('<world name="w"><model name="a"><link name="l"/></model>'
               '<model name="b"><link name="l"/></model></world>')
    assert [link.name for link in two.links] == ["a::l", "b::l"]


def test_includes_are_reported_not_followed():
    robot = read('<world name="w"><include><uri>model://table</uri></include>'
                 '<model name="a"><link name="l"/><include><uri>model://cup</uri></include>'
                 '</model></world>')
    assert [link.name for link in robot.links] == ["l"]
    notes = [f.message for f in robot.findings_of(None)]
    assert any("model://table" in n and "not processed" in n for n in notes)
    assert any("model://cup" in n for n in notes)


def test_bad_elements_are_dropped_with_a_note():
    robot = read("""<model name="m"><link name="l">
      <collision name="ground"><geometry><plane><normal>0 0 1</normal></plane></geometry></collision>
      <collision name="bad"><geometry><box><size>1 x 1</size></box></geometry></collision>
      <collision name="lost"><pose relative_to="nowhere">0 0 0 0 0 0</pose>
        <geometry><sphere><radius>1</radius></sphere></geometry></collision>
      <collision name="ok"><geometry><sphere><radius>1</radius></sphere></geometry></collision>
      <visual name="v"><geometry><mesh><uri>a.dae</uri><submesh><name>arm</name></submesh></mesh></geometry></visual>
    </link></model>""")
    link = robot.links[0]
    assert [c.name for c in link.collisions] == ["ok"]
    assert link.collisions[0].index == 3  # numbered as in the file
    text = " | ".join(f"{f.element} {f.message}" for f in robot.findings_of(link.name))
    for expected in ("'ground' dropped", "plane has no volume", "'bad' dropped",
                     "'lost' dropped", "nowhere", "submesh> 'arm' not honoured"):
        assert expected in text


def test_cycle_is_reported():
    robot = read("""<model name="m"><link name="l"><pose relative_to="f"/></link>
      <frame name="f" attached_to="l"/></model>""")
    assert "cycle" in " ".join(f.message for f in robot.findings_of(robot.links[0].name))


def test_sdf_defaults_and_auto():
    robot = read("""<model name="m">
      <link name="d"><inertial><pose>0 0 0 0 0 0</pose></inertial></link>
      <link name="a"><inertial auto="true"/><collision name="c"><density>500</density>
        <geometry><box><size>1 1 1</size></box></geometry></collision>
        <collision name="c2"><geometry><box><size>1 1 1</size></box></geometry></collision></link>
    </model>""")
    d = robot.link("d").inertial
    assert (d.mass, d.ixx, d.iyy, d.izz, d.ixy) == (1.0, 1.0, 1.0, 1.0, 0.0)
    a = robot.link("a")
    assert a.auto_inertial and a.inertial is None
    assert [c.density for c in a.collisions] == [500.0, 1000.0]


def test_undeclared_prefix_and_late_declaration():
    data = (b"\n  <?xml version='1.0'?>\n<sdf version='1.7'><model name='m'><link name='l'>"
            b"<collision name='c'><geometry><box><size>1 1 1</size></box></geometry>"
            b"<drake:proximity_properties><drake:mu_static>1</drake:mu_static>"
            b"</drake:proximity_properties></collision></link></model></sdf>")
    robot = robot_from_bytes(data, "m.sdf")
    assert robot.links[0].collisions[0].shape == Box((1.0, 1.0, 1.0))


def test_one_reading_keeps_non_finite_inertials():
    """One reading, as written: the judgement, not the reader, finds a NaN mass."""
    body = '<model name="m"><link name="l"><inertial><mass>nan</mass></inertial></link></model>'
    robot = robot_from_bytes(sdf_doc(body), "m.sdf")
    assert math.isnan(robot.links[0].inertial.mass)
    assert robot.findings == ()


@pytest.mark.parametrize("version", ["1.6", "1.5"])
def test_old_pose_frame_attribute_is_relative_to(version):
    robot = read("""<model name="m"><link name="a"><pose>0 0 1 0 0 0</pose></link>
      <link name="b"><pose frame="a">0 0 1 0 0 0</pose></link>
      <joint name="j" type="fixed"><parent>a</parent><child>b</child></joint></model>""", version)
    np.testing.assert_allclose(robot.joints[0].origin.xyz, (0, 0, 1))
