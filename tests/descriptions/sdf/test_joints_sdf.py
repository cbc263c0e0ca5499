"""SDFormat joints for whole-robot statics: axis (turned into the child link frame), limits,
effort and mimic, checked by hand on small cases and against Drake's parser (in-process,
skipped where ``pydrake`` is not installed) on hand-made fixtures and the corpus."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from support.corpus import robot_packages
from support.sdf import sdf_doc

from urdfinertia.analysis.statics import GRAVITY, robot_statics, written_bodies
from urdfinertia.descriptions.sdf.read import robot_from_bytes

DATA = Path(__file__).parents[2] / "data" / "joints"
FIXTURES = ("arm_1_9.sdf", "arm_1_6.sdf")
_LINKS = """<link name="a"/><link name="b"><pose>{pose}</pose></link>"""


def _joint(body: str, version: str = "1.11", pose: str = "0 0 0 0 0 0"):
    doc = sdf_doc(f'<model name="m">{_LINKS.format(pose=pose)}{body}</model>', version)
    robot = robot_from_bytes(doc, "m.sdf")
    return {j.name: j for j in robot.joints}, [f"{f.element}: {f.message}" for f in robot.findings]


def _revolute(axis: str, pose: str = "", limit: str = "", name: str = "j") -> str:
    return (f'<joint name="{name}" type="revolute">{pose}<parent>a</parent><child>b</child>'
            f"<axis>{axis}<limit>{limit}</limit></axis></joint>")


def test_axis_in_the_joint_frame_is_turned_into_the_child_frame():
    # the joint frame is the child's turned a quarter about z: its x is the child's y
    joints, _ = _joint(_revolute("<xyz>1 0 0</xyz>", "<pose>0 0 0 0 0 1.5707963267948966</pose>"))
    np.testing.assert_allclose(joints["j"].axis, (0, 1, 0), atol=1e-15)


@pytest.mark.parametrize(("version", "axis"), [
    ("1.11", '<xyz expressed_in="__model__">1 0 0</xyz>'),
    ("1.6", "<xyz>1 0 0</xyz><use_parent_model_frame>true</use_parent_model_frame>"),
    ("1.4", "<xyz>1 0 0</xyz>"),  # up to 1.4 the axis was always in the model frame
])
def test_axis_in_the_model_frame(version, axis):
    # child b is turned a quarter about z in the model: the model's x is b's -y
    joints, _ = _joint(_revolute(axis), version, pose="0 0 1 0 0 1.5707963267948966")
    np.testing.assert_allclose(joints["j"].axis, (0, -1, 0), atol=1e-15)


def test_use_parent_model_frame_false_and_newer_versions_keep_the_joint_frame():
    for version, flag in (("1.6", "false"), ("1.11", "true")):  # 1.7 dropped the flag
        joints, _ = _joint(_revolute(f"<xyz>1 0 0</xyz><use_parent_model_frame>{flag}"
                                     "</use_parent_model_frame>"), version,
                           pose="0 0 1 0 0 1.5707963267948966")
        np.testing.assert_allclose(joints["j"].axis, (1, 0, 0), atol=1e-15)


def test_limits_and_effort():
    joints, _ = _joint(
        _revolute("<xyz>0 0 2</xyz>", limit="<lower>-1.5</lower><upper>0.5</upper>"
                  "<effort>40</effort>", name="set")
        + _revolute("", limit="<lower>-1e16</lower><upper>1e16</upper><effort>-1</effort>",
                    name="unset").replace("<child>b", "<child>c") + '<link name="c"/>'
        + _revolute("", limit="<effort>0</effort>", name="passive").replace(
            "<child>b", "<child>d") + '<link name="d"/>')
    j = joints["set"]
    assert (j.axis, j.lower, j.upper, j.effort) == ((0.0, 0.0, 1.0), -1.5, 0.5, 40.0)
    u = joints["unset"]  # SDFormat's defaults: no limits, no effort; the default axis z
    assert (u.axis, u.lower, u.upper, u.effort) == ((0.0, 0.0, 1.0), None, None, None)
    assert joints["passive"].effort == 0.0


def test_mimic_and_unreadable_values():
    body = (_revolute("<xyz>1 0 0</xyz>", limit="<effort>9</effort>", name="lead")
            + '<link name="c"/><joint name="follow" type="revolute"><parent>a</parent>'
            "<child>c</child><axis><xyz>1 zero 0</xyz><limit><effort>lots</effort></limit>"
            '<mimic joint="lead"><multiplier>-2</multiplier><offset>0.1</offset></mimic>'
            "</axis></joint>")
    joints, notes = _joint(body)
    f = joints["follow"]
    assert f.mimic == ("lead", -2.0, 0.1)
    assert (f.axis, f.effort) == ((0.0, 0.0, 1.0), None)
    assert any("follow" in n and "<xyz>" in n for n in notes)
    assert any("follow" in n and "<effort>" in n for n in notes)


def test_off_axis_joint_keeps_where_its_axis_passes():
    joints, notes = _joint(_revolute("<xyz>0 1 0</xyz>", "<pose>0 0 0.5 0 0 0</pose>",
                                     "<effort>10</effort>"))
    assert joints["j"].effort == 10.0 and not notes
    np.testing.assert_allclose(joints["j"].axis_point, (0, 0, 0.5), atol=1e-15)


def test_pendulum_hung_below_an_off_origin_axis():
    """A 2 kg bob at its link's origin, the hinge's axis (y) 0.5 m above it (the joint's
    <pose>): swung a quarter turn it needs m g r = 9.81 N m; turned about its own origin,
    as when the axis point is dropped, it would need nothing."""
    doc = sdf_doc("""<model name="m"><link name="a"/>
      <link name="b"><pose>0 0 1 0 0 0</pose><inertial><mass>2</mass></inertial></link>
      <joint name="j" type="revolute"><pose>0 0 0.5 0 0 0</pose>
        <parent>a</parent><child>b</child>
        <axis><xyz>0 1 0</xyz>
        <limit><lower>-2</lower><upper>2</upper><effort>30</effort></limit></axis></joint>
      <joint name="w" type="fixed"><parent>world</parent><child>a</child></joint>
    </model>""")
    robot = robot_from_bytes(doc, "m.sdf")
    (load,) = robot_statics(robot, written_bodies(robot)).loads
    assert load.needed == pytest.approx(2 * GRAVITY * 0.5, rel=1e-4)  # a sampled maximum
    assert not load.passive and load.effort == 30.0


def test_pendulum_torque_uses_the_axis():
    """A 2 kg bob 0.5 m out along x of a link turned about z; the hinge's axis is given in
    the model frame as y: the worst torque is m g r = 9.81 N m (a wrong axis gives less)."""
    doc = sdf_doc("""<model name="m"><link name="a"/>
      <link name="b"><pose>0 0 1 0 0 0.7</pose><inertial><pose>0.5 0 0 0 0 0</pose>
        <mass>2</mass></inertial></link>
      <frame name="f"><pose>0 0 0 0 0 -0.7</pose></frame>
      <joint name="j" type="revolute"><parent>a</parent><child>b</child>
        <axis><xyz expressed_in="f">0.6 0.8 0</xyz>
        <limit><lower>-2</lower><upper>2</upper><effort>30</effort></limit></axis></joint>
      <joint name="w" type="fixed"><parent>world</parent><child>a</child></joint>
    </model>""")
    robot = robot_from_bytes(doc, "m.sdf")
    (load,) = robot_statics(robot, written_bodies(robot)).loads
    # in the model: the axis is f's (0.6, 0.8, 0) turned by -0.7 about z, horizontal; the
    # bob's arm is its offset less the part along the axis, horizontal at the zero pose
    c, s = math.cos(-0.7), math.sin(-0.7)
    a = np.array([0.6 * c - 0.8 * s, 0.6 * s + 0.8 * c, 0.0])
    bob = 0.5 * np.array([math.cos(0.7), math.sin(0.7), 0.0])
    radial = float(np.linalg.norm(bob - (bob @ a) * a))
    assert radial > 0.1  # the check can fail: an axis along the arm gives no torque
    assert load.needed == pytest.approx(2 * GRAVITY * radial, rel=1e-9)
    assert not load.passive and load.effort == 30.0


# ---- against Drake -------------------------------------------------------------------

def _drake_joints(path: Path) -> dict[str, dict]:
    pytest.importorskip("pydrake")
    from pydrake.multibody.parsing import Parser
    from pydrake.multibody.plant import MultibodyPlant
    from pydrake.multibody.tree import JointActuatorIndex, JointIndex

    plant = MultibodyPlant(0.0)
    Parser(plant).AddModels(str(path))
    plant.Finalize()
    efforts = {}
    for i in range(plant.num_actuators()):
        act = plant.get_joint_actuator(JointActuatorIndex(i))
        efforts[int(act.joint().index())] = act.effort_limit()
    out = {}
    for i in range(plant.num_joints()):
        j = plant.get_joint(JointIndex(i))
        if j.type_name() not in ("revolute", "prismatic"):
            continue
        axis = j.revolute_axis() if j.type_name() == "revolute" else j.translation_axis()
        x_cj = j.frame_on_child().GetFixedPoseInBodyFrame()  # joint frame in the child's
        out[j.name()] = {"axis": x_cj.rotation().matrix() @ axis,
                         "lower": j.position_lower_limits()[0],
                         "upper": j.position_upper_limits()[0],
                         "effort": efforts.get(int(j.index())),
                         "point": x_cj.translation(), "revolute": j.type_name() == "revolute"}
    return out


def _limit(value: float) -> float | None:
    return value if math.isfinite(value) and abs(value) < 1e16 else None


def _compare(path: Path, theirs: dict[str, dict]) -> int:
    """Every revolute and prismatic joint Drake reads: the same axis (child frame), limits
    and effort (Drake: no actuator for effort 0, an infinite one for no limit); returns how
    many were compared."""
    robot = robot_from_bytes(path.read_bytes(), path)
    compared = 0
    for j in robot.joints:
        ref = theirs.get(j.name.split("::")[-1])
        if ref is None:
            continue
        compared += 1
        np.testing.assert_allclose(j.axis, ref["axis"], atol=1e-12, err_msg=j.name)
        if j.type != "continuous":
            assert (j.lower, j.upper) == (_limit(ref["lower"]), _limit(ref["upper"])), j.name
        axis = np.asarray(ref["axis"])
        point = np.asarray(ref["point"])
        # the same axis line: Drake's point less ours lies along the axis
        gap = point - np.asarray(j.axis_point)
        np.testing.assert_allclose(gap - (gap @ axis) * axis, 0, atol=1e-9, err_msg=j.name)
        effort = ref["effort"]
        assert (j.effort or None) == (effort if effort is not None
                                      and math.isfinite(effort) else None), j.name
    return compared


@pytest.mark.parametrize("name", FIXTURES)
def test_handmade_against_drake(name):
    assert _compare(DATA / name, _drake_joints(DATA / name)) >= 2


def test_corpus_against_drake():
    """The corpus SDFs Drake itself reads (it refuses loops, a link named ``world``, ...)."""
    pytest.importorskip("pydrake")
    compared = 0
    for path in (p for files in robot_packages(("sdf",)).values() for p in files):
        try:
            theirs = _drake_joints(path)
        except RuntimeError:
            continue  # Drake refuses the file: nothing to compare
        compared += _compare(path, theirs)
    if compared == 0:
        pytest.skip("no SDFormat robot with joints that Drake reads is installed")
