"""statics.py: gravity loads against closed forms, mimic and passive joints, the band of
derived links, and check's findings on a hand-made arm."""

from pathlib import Path

import numpy as np
import pytest

import urdfinertia
from urdfinertia.analysis.statics import (
    GRAVITY,
    Body,
    robot_statics,
    statics_findings,
    written_bodies,
)
from urdfinertia.descriptions.formats import read_description
from urdfinertia.descriptions.model import Joint, Link, Origin, Robot

FIXTURE = Path(__file__).resolve().parents[1] / "data" / "statics" / "weak_arm.urdf"


def arm(effort=(100.0, 100.0), lower=-np.pi / 2, upper=np.pi / 2, mimic=None):
    """A base and two links along x from y-axis joints: link1 CoM 0.2 m out, link2 mounted
    0.4 m out with its CoM 0.15 m further."""
    links = (Link("base"), Link("l1"), Link("l2"))
    joints = (Joint("j1", "revolute", "base", "l1", Origin((0, 0, 0.5)), axis=(0, 1, 0),
                    lower=lower, upper=upper, effort=effort[0]),
              Joint("j2", "revolute", "l1", "l2", Origin((0.4, 0, 0)), axis=(0, 1, 0),
                    lower=lower, upper=upper, effort=effort[1], mimic=mimic))
    return Robot("arm", links, joints)


BODIES = {"base": Body(10.0, np.zeros(3)), "l1": Body(2.0, np.array([0.2, 0, 0])),
          "l2": Body(1.0, np.array([0.15, 0, 0]))}


def test_two_link_arm_in_closed_form():
    # the arm horizontal (q = 0) is the worst pose for both joints
    s = robot_statics(arm(), BODIES)
    loads = {ld.joint.name: ld for ld in s.loads}
    assert loads["j1"].needed == pytest.approx(GRAVITY * (2.0 * 0.2 + 1.0 * 0.55), rel=1e-9)
    assert loads["j2"].needed == pytest.approx(GRAVITY * 1.0 * 0.15, rel=1e-9)
    assert s.mass == pytest.approx(13.0)
    np.testing.assert_allclose(s.com, [(0.4 + 0.55) / 13, 0, 3 * 0.5 / 13], atol=1e-12)


def test_a_range_that_avoids_horizontal_gives_the_range_end():
    """j1 only from 60 to 90 degrees: the worst is at 60 (the range's corner is sampled);
    j2 over +-90 degrees can tilt l2 back to horizontal, adding 1 kg x 0.15 m."""
    # effort 6 N m: near the load, so the samples are refined
    robot = arm(effort=(6.0, 100.0), lower=np.pi / 3, upper=np.pi / 2)
    robot = Robot("arm", robot.links, (robot.joints[0], Joint(
        "j2", "revolute", "l1", "l2", Origin((0.4, 0, 0)), axis=(0, 1, 0), lower=-np.pi / 2,
        upper=np.pi / 2, effort=100.0)))
    j1 = next(ld for ld in robot_statics(robot, BODIES).loads if ld.joint.name == "j1")
    # at q1 = 60 deg the lever of l1 and of l2's mount is cos(60) = 1/2; l2's own 0.15 m is
    # horizontal when q2 = -60 deg, inside its range
    best = GRAVITY * (2.0 * 0.2 * 0.5 + 1.0 * (0.4 * 0.5 + 0.15))
    assert j1.needed <= best * (1 + 1e-9)
    assert j1.needed >= best * 0.98  # sampled and refined one joint at a time


def test_mimic_joint_is_folded_into_its_master():
    s = robot_statics(arm(mimic=("j1", 1.0, 0.0)), BODIES)
    names = [ld.joint.name for ld in s.loads]
    assert names == ["j1"]
    (j1,) = s.loads
    assert j1.mimics == ("j2",)


def test_passive_joint_is_not_judged():
    robot = arm(effort=(0.0, 0.1))
    found = statics_findings(robot, robot_statics(robot, BODIES))
    assert [(f.link, f.code, f.severity) for f in found] == [("l2", "joint-cannot-hold",
                                                             "error")]


def test_band_of_derived_links_gives_warning_then_error():
    needed = GRAVITY * 1.0 * 0.15  # j2 holds l2 only
    bodies = dict(BODIES, l2=Body(1.0, np.array([0.15, 0, 0]), band=0.3))
    for effort, code, severity in ((needed * 1.1, "joint-may-not-hold", "warning"),
                                   (needed * 0.6, "joint-cannot-hold", "error")):
        robot = arm(effort=(100.0, effort))
        found = [f for f in statics_findings(robot, robot_statics(robot, bodies))
                 if f.link == "l2"]
        assert [(f.code, f.severity) for f in found] == [(code, severity)]
    robot = arm(effort=(100.0, needed * 1.5))  # 1.3 needed of 1.5: within 20 % margin
    found = statics_findings(robot, robot_statics(robot, bodies))
    assert [(f.code, f.severity) for f in found] == [("joint-effort-margin", "warning")]


def test_weak_arm_fixture_through_check():
    result = urdfinertia.check(FIXTURE)
    found = {(f.link, f.code, f.severity) for f in result.findings}
    assert ("upper_arm", "joint-cannot-hold", "error") in found  # shoulder: 5 of 6.50 N m
    assert ("forearm", "joint-effort-margin", "warning") in found  # elbow: 1.60 of 1.9 N m
    loads = {ld.joint.name: ld.needed for ld in result.statics.loads}
    assert loads["shoulder"] == pytest.approx(GRAVITY * (0.7 * 0.25 + 0.5 * 0.7 + 0.15 * 0.92))
    assert loads["elbow"] == pytest.approx(GRAVITY * (0.5 * 0.2 + 0.15 * 0.42))
    assert not any(f.link == "finger_b" for f in result.findings)  # mimic: folded
    assert not any(f.link == "wheel" for f in result.findings)  # passive: not judged
    assert result.statics is not None and result.statics.mass == pytest.approx(3.65)
    assert urdfinertia.check(FIXTURE, statics=False).statics is None


def test_written_bodies_skip_massless_links():
    robot, _ = read_description(FIXTURE)
    assert "world_frame" not in written_bodies(robot)


def chain(links: int, effort: float = 1.0) -> tuple[Robot, dict[str, Body]]:
    """A serial chain of 1 kg links 0.1 m apart on y-axis joints; every load is above
    ``effort``, so every joint asks for refinement (the statics' worst case)."""
    names = [f"l{i}" for i in range(links)]
    joints = tuple(Joint(f"j{i}", "revolute", names[i - 1], names[i], Origin((0, 0, 0.1)),
                         axis=(0, 1, 0), lower=-1.0, upper=1.0, effort=effort)
                   for i in range(1, links))
    bodies = {n: Body(1.0, np.array([0.0, 0.0, 0.05])) for n in names}
    return Robot("chain", tuple(Link(n) for n in names), joints), bodies


def test_a_long_chain_is_sampled_within_the_budget():
    """Found by a scale test: 100 links took 25 s and 1.5 GB, 200 ran out of memory
    (338,499 configurations). The sampling is now bounded and says it was coarsened."""
    from urdfinertia.analysis.statics import MAX_WORK
    from urdfinertia.rules import Rule

    robot, bodies = chain(300)
    s = robot_statics(robot, bodies)
    per_config = 300 + 300 * 301 // 2  # every link placed, plus every joint's subtree
    assert s.configurations <= max(MAX_WORK // per_config, 3 + 16)
    assert "statics sampled" in s.note and "300 links" in s.note
    assert len(s.loads) == 299
    # the root joint holds the whole chain: below its weight at full reach, and the
    # samples still find a large part of it
    reach = sum(0.1 * i - 0.05 for i in range(1, 300))
    assert 0.1 * GRAVITY * reach < s.loads[0].needed <= GRAVITY * reach
    found = statics_findings(robot, s)
    assert [f.rule for f in found if f.rule is Rule.STATICS_COARSENED] == [
        Rule.STATICS_COARSENED]


def test_a_small_robot_is_not_coarsened():
    s = robot_statics(*chain(5))
    assert s.note == "" and s.configurations > 259
