"""The passive run calls a joint a runaway only when its inertials make it one: joints stop
at their limits in every engine, and PyBullet's explicit joint damping is left out."""

from __future__ import annotations

import pytest

from urdfinertia.cli import main
from urdfinertia.engines.run import installed

from .test_engines import ALL, DATA, engine, findings


@pytest.mark.skipif(not installed("pinocchio"), reason="pinocchio not installed")
def test_pinocchio_stops_a_joint_at_its_limit():
    from urdfinertia.engines.probe import probe_pinocchio

    r = probe_pinocchio(DATA / "finger.urdf", 2.0)
    # the finger falls its 4 cm of travel: sqrt(2 g 0.04) = 0.89 m/s, then stops (free
    # fall for 2 s would reach 19.6 m/s)
    assert r["accepted"] and r["nan_time"] is None
    assert 0.5 < r["max_speed"] < 1.0


@pytest.mark.skipif(not installed("pybullet"), reason="pybullet not installed")
def test_pybullet_runs_without_the_explicit_damping():
    from urdfinertia.engines.probe import probe_pybullet

    r = probe_pybullet(DATA / "damped.urdf", 2.0)
    # a 0.17 kg jaw swinging 60 degrees at 3 cm: a few rad/s, not the 100 rad/s cap
    assert r["accepted"] and not r["runaway"] and r["max_speed"] < 30.0


@pytest.mark.parametrize("name", ALL)
def test_a_finger_on_its_limit_is_not_a_runaway(name):
    assert findings(name, "finger.urdf") == []


@pytest.mark.parametrize("name", [engine("pybullet"), engine("mujoco")])
def test_a_damped_light_gripper_is_not_a_runaway(name):
    assert findings(name, "damped.urdf") == []


@pytest.mark.parametrize("name", ALL)
def test_a_stiff_robot_still_runs_away(name):
    # the stops do not hide a real runaway (stiff.urdf: a 1 kg bob with a 1e-9 tensor)
    assert {f.code for f in findings(name, "stiff.urdf")} == {"engine-runaway"}


def test_check_engines_exits_0_on_the_finger(capsys):
    assert main(["check", "-q", "--engines", "all", str(DATA / "finger.urdf")]) == 0
    assert "engine-runaway" not in capsys.readouterr().out
