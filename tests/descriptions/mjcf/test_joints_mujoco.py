"""MJCF joints for whole-robot statics against MuJoCo itself: the compiled ``jnt_axis``,
``jnt_limited``/``jnt_range`` (radians), ``jnt_actfrcrange`` and ``actuator_*`` give the
axis, limits and effort we read, on a hand-made model and a few corpus robots."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from support.corpus import robot_packages

from urdfinertia.descriptions.mjcf.read import robot_from_bytes

mujoco = pytest.importorskip("mujoco")

DATA = Path(__file__).parents[2] / "data" / "joints"
#: small corpus robots with limits and motors (dm_control suite, gymnasium_robotics)
CORPUS = ("dm_control/suite/acrobot.xml", "dm_control/suite/cheetah.xml",
          "dm_control/suite/hopper.xml", "dm_control/suite/humanoid.xml",
          "dm_control/suite/manipulator.xml", "dm_control/third_party/ant/ant.xml",
          "gymnasium_robotics/envs/mujoco/assets/pusher.xml",
          "gymnasium_robotics/envs/mujoco/assets/humanoid.xml")


def _mujoco_effort(m, a: int) -> float | None:
    """An actuator's largest joint torque from the compiled model (None: unbounded)."""
    bounds = []
    plain = (m.actuator_gaintype[a] == int(mujoco.mjtGain.mjGAIN_FIXED)
             and m.actuator_biastype[a] == int(mujoco.mjtBias.mjBIAS_NONE)
             and m.actuator_dyntype[a] == int(mujoco.mjtDyn.mjDYN_NONE))
    if plain and m.actuator_ctrllimited[a]:
        bounds.append(abs(m.actuator_gainprm[a, 0]) * np.max(np.abs(m.actuator_ctrlrange[a])))
    if m.actuator_forcelimited[a]:
        bounds.append(np.max(np.abs(m.actuator_forcerange[a])))
    return abs(m.actuator_gear[a, 0]) * min(bounds) if bounds else None


def _mujoco_joints(path: Path) -> dict[str, dict]:
    m = mujoco.MjModel.from_xml_path(str(path))
    efforts: dict[int, float | None] = {}
    for a in range(m.nu):
        if m.actuator_trntype[a] != int(mujoco.mjtTrn.mjTRN_JOINT):
            continue
        j, f = int(m.actuator_trnid[a, 0]), _mujoco_effort(m, a)
        before = efforts.get(j, 0.0)
        efforts[j] = None if f is None or before is None else before + f
    out = {}
    hinge, slide = int(mujoco.mjtJoint.mjJNT_HINGE), int(mujoco.mjtJoint.mjJNT_SLIDE)
    for j in range(m.njnt):
        if int(m.jnt_type[j]) not in (hinge, slide):
            continue
        effort = efforts.get(j, "none")
        if m.jnt_actfrclimited[j]:
            bound = float(np.max(np.abs(m.jnt_actfrcrange[j])))
            effort = bound if effort == "none" else None if effort is None else min(effort,
                                                                                    bound)
        out[mujoco.mj_id2name(m, mujoco.mjtObj.mjOBJ_JOINT, j)] = {
            "axis": m.jnt_axis[j].copy(), "limited": bool(m.jnt_limited[j]),
            "range": m.jnt_range[j].copy(), "pos": m.jnt_pos[j].copy(),
            "effort": None if effort == "none" else effort,
            "hinge": int(m.jnt_type[j]) == hinge}
    return out


def _compare(path: Path) -> tuple[int, int, int]:
    """Joints compared, of them limited, of them with an effort."""
    theirs = _mujoco_joints(path)
    robot = robot_from_bytes(path.read_bytes(), path)
    counts = [0, 0, 0]
    for j in robot.joints:
        ref = theirs.get(j.name)
        if ref is None:
            continue
        counts[0] += 1
        np.testing.assert_allclose(j.axis, ref["axis"], atol=1e-6, err_msg=j.name)
        assert (j.lower is not None) == ref["limited"], j.name
        if ref["limited"]:
            counts[1] += 1
            np.testing.assert_allclose((j.lower, j.upper), ref["range"], atol=1e-9,
                                       err_msg=j.name)
        # the same axis line: MuJoCo's joint position less our axis point lies along it
        gap, axis = ref["pos"] - np.asarray(j.axis_point), ref["axis"]
        np.testing.assert_allclose(gap - (gap @ axis) * axis, 0, atol=1e-6, err_msg=j.name)
        expected = ref["effort"]
        if expected is None:
            assert j.effort is None, j.name
        else:
            counts[2] += 1
            assert j.effort == pytest.approx(expected, rel=1e-12), j.name
    return counts[0], counts[1], counts[2]


def test_handmade_against_mujoco():
    assert _compare(DATA / "arm.xml") == (4, 4, 4)


def test_handmade_values_and_notes():
    path = DATA / "arm.xml"
    robot = robot_from_bytes(path.read_bytes(), path)
    joints = {j.name: j for j in robot.joints}
    # by hand: gear 2 x min(gain 3 x ctrl 10, forcerange 8), under actuatorfrcrange 30
    assert joints["elbow"].effort == 16.0
    assert joints["shoulder"].effort == 50.0  # gear 50 x the class's ctrlrange 1
    assert joints["shoulder"].lower == pytest.approx(np.radians(-45))
    assert joints["pin"].effort == 5.0  # actuatorfrcrange alone
    np.testing.assert_allclose(joints["pin"].axis_point, (0, 0, 0.05), atol=1e-15)
    notes = "\n".join(f.message for f in robot.findings)
    assert "'slider' has 2 joints" in notes and "'twist'" in notes


def test_radian_compiler_and_limited_false():
    doc = b"""<mujoco><compiler angle="radian" autolimits="true"/><worldbody>
      <body name="a"><joint name="j" range="-1 2"/><geom size="0.1"/>
      <body name="b"><joint name="k" limited="false" range="-1 2"/><geom size="0.1"/>
      </body></body></worldbody></mujoco>"""
    joints = {j.name: j for j in robot_from_bytes(doc, "m.xml").joints}
    assert (joints["j"].lower, joints["j"].upper) == (-1.0, 2.0)
    assert joints["k"].lower is None and joints["k"].effort is None


def _corpus() -> list[Path]:
    found = {p.as_posix(): p for files in robot_packages(("mjcf",)).values() for p in files}
    return [p for key, p in found.items() if key.endswith(CORPUS)]


def test_corpus_against_mujoco():
    paths = _corpus()
    if not paths:
        pytest.skip("no dm_control or gymnasium_robotics models installed")
    totals = np.sum([_compare(p) for p in paths], axis=0)
    assert totals[0] > 0 and totals[1] > 0 and totals[2] > 0


def test_fix_does_not_print_what_only_statics_uses(tmp_path, capsys):
    """Joint notes (several joints in a body) concern ``check``'s statics:
    ``fix`` does not repeat them as warnings."""
    from urdfinertia import cli

    path = DATA / "arm.xml"
    assert robot_from_bytes(path.read_bytes(), path).findings  # the fixture has some
    cli.main(["fix", str(path), "-o", str(tmp_path / "arm.xml"), "-q"])
    err = capsys.readouterr().err
    assert "statics" not in err and "has 2 joints" not in err


def test_hinge_away_from_the_body_origin_turns_about_its_pos():
    """A 3 kg point-like body hung 0.4 m below its hinge (the joint's ``pos`` above the
    body's origin), limited to +-100 degrees: the largest load is m g r = 11.77 N m at the
    quarter turn; turned about the body's origin it would need nothing."""
    from urdfinertia.analysis.statics import GRAVITY, robot_statics, written_bodies

    doc = b"""<mujoco><worldbody><body name="base">
      <body name="bob" pos="0 0 -0.4">
        <joint name="hinge" pos="0 0 0.4" axis="0 1 0" range="-100 100"
               actuatorfrcrange="-20 20"/>
        <inertial pos="0 0 0" mass="3" diaginertia="1e-4 1e-4 1e-4"/>
        <geom type="sphere" size="0.02"/>
      </body></body></worldbody></mujoco>"""
    robot = robot_from_bytes(doc, "m.xml")
    (load,) = robot_statics(robot, written_bodies(robot)).loads
    assert load.needed == pytest.approx(3 * GRAVITY * 0.4, rel=1e-4)  # a sampled maximum
    assert load.effort == 20.0 and not load.passive
