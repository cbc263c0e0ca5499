"""priors/features.py: robot kind, place in the chain, joint axes, size, on hand-made robots."""

import numpy as np
import pytest

from urdfinertia.descriptions.model import Joint, Link, Origin, Robot
from urdfinertia.inertia.rotation import rpy_matrix
from urdfinertia.priors.features import (
    hints,
    joint_axes,
    link_features,
    part_kind,
    robot_features,
    robot_kind,
    words,
)


def robot(name: str, joints: list[tuple[str, str, str, str]]) -> Robot:
    """A robot of (joint, type, parent, child) rows; every named link exists."""
    names = dict.fromkeys(n for _, _, p, c in joints for n in (p, c))
    return Robot(name, tuple(Link(n) for n in names),
                 tuple(Joint(j, t, p, c, Origin((0.1, 0.0, 0.0))) for j, t, p, c in joints))


def arm(name: str, n: int = 6) -> Robot:
    rows = [(f"joint_{i + 1}", "revolute", "base_link" if i == 0 else f"link_{i}",
             f"link_{i + 1}") for i in range(n)]
    return robot(name, rows)


def legs(prefixes: list[str], root: str = "trunk") -> list[tuple[str, str, str, str]]:
    rows = []
    for p in prefixes:
        rows += [(f"{p}_hip_joint", "revolute", root, f"{p}_hip"),
                 (f"{p}_thigh_joint", "revolute", f"{p}_hip", f"{p}_thigh"),
                 (f"{p}_calf_joint", "revolute", f"{p}_thigh", f"{p}_calf")]
    return rows


def hand() -> Robot:
    rows = []
    for f in ("index", "middle", "ring", "thumb"):
        rows += [(f"{f}_j0", "revolute", "palm", f"{f}_proximal"),
                 (f"{f}_j1", "revolute", f"{f}_proximal", f"{f}_distal")]
    return robot("hand", rows)


@pytest.mark.parametrize(("model", "kind"), [
    (arm("kr6r900sixx"), "industrial arm"),
    (arm("kuka_kr6r900sixx"), "industrial arm"),
    (arm("fanuc_m20ia"), "industrial arm"),
    (arm("kraken"), "cobot"),
    (arm("abb_irb2400"), "industrial arm"),
    (arm("panda", 7), "cobot"),
    (robot("go1", legs(["FL", "FR", "RL", "RR"])), "quadruped"),
    (robot("biped", legs(["left", "right"], "pelvis")
           + [("l_shoulder", "revolute", "pelvis", "left_shoulder_link")]), "humanoid"),
    (hand(), "hand"),
    (robot("parallel", [("left_finger_joint", "prismatic", "base", "left_finger"),
                        ("right_finger_joint", "prismatic", "base", "right_finger")]),
     "gripper"),
    (robot("rover", [("wl", "continuous", "chassis", "left_wheel"),
                     ("wr", "continuous", "chassis", "right_wheel")]), "mobile base"),
    (robot("quad", [(f"p{i}", "continuous", "body", f"propeller_{i}") for i in range(4)]),
     "aerial"),
    (robot("rov", [("t1", "fixed", "frame", "thruster_1")]), "marine"),
    (robot("thing", [("j", "fixed", "a", "b")]), "other"),
])
def test_robot_kind_from_structure_and_names(model, kind):
    got, why = robot_kind(model)
    assert got == kind, why
    assert why


def test_a_hand_of_numbered_links_is_a_hand():
    # allegro-like: four branches of four joints from the palm, links named by number
    rows = [(f"joint_{f}.{k}", "revolute", "palm" if k == 0 else f"link_{f}.{k - 1}",
             f"link_{f}.{k}") for f in range(4) for k in range(4)]
    model = robot("allegro", rows)
    model = Robot("allegro", model.links, tuple(
        Joint(j.name, j.type, j.parent, j.child, Origin((0.0, 0.0, 0.04)))
        for j in model.joints))
    assert robot_kind(model)[0] == "hand"
    # the same branches on a robot a metre across are not a hand
    far = Robot("big", model.links, tuple(
        Joint(j.name, j.type, j.parent, j.child, Origin((0.0, 0.0, 0.3)))
        for j in model.joints))
    assert robot_kind(far)[0] == "cobot"


def test_legs_are_counted_once_through_loops_and_unnamed_links():
    # a biped whose shin hangs below an unnamed rod: still one leg a side
    rows = []
    for side in ("left", "right"):
        rows += [(f"{side}_hip", "revolute", "pelvis", f"{side}-hip-roll"),
                 (f"{side}_rod", "revolute", f"{side}-hip-roll", f"{side}-achilles-rod"),
                 (f"{side}_knee", "revolute", f"{side}-achilles-rod", f"{side}-knee"),
                 (f"{side}_toe", "revolute", f"{side}-knee", f"{side}-toe")]
    kind, why = robot_kind(robot("cassie", rows))
    assert (kind, why) == ("humanoid", "2 legs with arms, a torso or a head")


def test_rotors_on_the_base_make_an_aerial_robot_but_motor_rotors_do_not():
    iris = robot("iris", [(f"rotor_{i}_joint", "continuous", "base_link", f"rotor_{i}")
                          for i in range(4)])
    assert robot_kind(iris)[0] == "aerial"
    motors = robot("wheeled", [(f"{s}_stator", "fixed", "torso", f"{s}_stator")
                               for s in ("l", "r", "f")]
                   + [(f"{s}_spin", "continuous", f"{s}_stator", f"{s}_rotor")
                      for s in ("l", "r", "f")])
    assert robot_kind(motors)[0] != "aerial"


def test_an_arm_with_a_hand_is_an_arm():
    model = arm("tiago", 7)
    rows = [(f"hand_{f}_j{k}", "revolute", "link_7" if k == 0 else f"hand_{f}_finger_{k}",
             f"hand_{f}_finger_{k + 1}") for f in ("index", "middle", "thumb") for k in range(3)]
    extra = robot("h", rows)
    model = Robot("tiago", model.links + extra.links[1:], model.joints + extra.joints)
    assert robot_kind(model)[0] == "cobot"


def test_a_gripper_on_an_arm_is_an_arm():
    model = arm("ur5e")
    model = Robot("ur5e", model.links + (Link("gripper_finger"),),
                  model.joints + (Joint("finger", "prismatic", "link_6", "gripper_finger"),))
    assert robot_kind(model)[0] == "cobot"


def test_place_in_the_chain():
    # base - l1 - l2 - l3 with a fixed tool on l3 and a second branch on l1
    model = robot("r", [("j1", "revolute", "base", "l1"), ("j2", "revolute", "l1", "l2"),
                        ("j3", "revolute", "l2", "l3"), ("tool", "fixed", "l3", "tool"),
                        ("jb", "prismatic", "l1", "b1")])
    rf = robot_features(model)
    assert rf.depth == {"base": 0, "l1": 1, "l2": 2, "l3": 3, "tool": 3, "b1": 2}
    assert rf.max_depth == 3
    assert rf.below["base"] == pytest.approx(5 / 5)
    assert rf.below["l1"] == pytest.approx(4 / 5)
    assert rf.below["l3"] == pytest.approx(1 / 5)
    assert rf.below["tool"] == 0.0
    assert rf.joints == {"base": 1, "l1": 3, "l2": 2, "l3": 1, "tool": 0, "b1": 1}
    # every joint origin is 0.1 m along x: the tool, four joints out, is 0.4 m away
    assert rf.extent == pytest.approx(0.4)
    assert part_kind("base", rf) == "base"
    assert part_kind("l2", rf) == "other"
    assert part_kind("b1", rf) == "end"


def test_link_features_size_and_fill():
    rf = robot_features(arm("panda", 7))
    box = (np.array([-0.1, -0.05, 0.0]), np.array([0.1, 0.05, 0.4]))
    f = link_features("link_3", rf, volume=0.002, box=box, geometry="mesh", role="visual",
                      others=(0.004, 0.001))
    assert f.robot_kind == "cobot"
    assert f.fill == pytest.approx(0.002 / (0.2 * 0.1 * 0.4))
    assert f.diagonal == pytest.approx(np.sqrt(0.2 ** 2 + 0.1 ** 2 + 0.4 ** 2))
    assert f.depth_share == pytest.approx(3 / 7)
    assert f.joints == 2
    assert f.excess == pytest.approx(2.0)  # twice the smallest of its geometries
    with pytest.raises(ValueError, match="volume"):
        link_features("link_3", rf, volume=0.0, box=box, geometry="mesh", role="visual")


def test_material_hints_and_words():
    assert words("rh_FFKnuckle2") == {"rh", "ff", "knuckle"}
    assert hints("left_hip_motor") == "dense"
    assert hints("carbon_shell_cover") == "light"
    assert hints("servo_cover") == "dense"  # dense wins
    assert hints("forearm") == ""


def test_joint_axes_in_the_link_frame():
    rpy = (0.0, np.pi / 2, 0.0)
    links = (Link("a"), Link("b"), Link("c"))
    joints = (Joint("ab", "revolute", "a", "b", Origin((0.0, 0.0, 0.5)), axis=(0.0, 0.0, 2.0),
                    axis_point=(0.01, 0.0, 0.0)),
              Joint("bc", "revolute", "b", "c", Origin((0.3, 0.0, 0.0), rpy),
                    axis=(0.0, 0.0, 1.0), axis_point=(0.0, 0.02, 0.0)),
              Joint("fix", "fixed", "b", "a"))
    axes = joint_axes(Robot("r", links, joints), "b")
    assert [(a.name, a.end) for a in axes] == [("ab", "parent"), ("bc", "child")]
    np.testing.assert_allclose(axes[0].point, (0.01, 0.0, 0.0))
    np.testing.assert_allclose(axes[0].direction, (0.0, 0.0, 1.0))  # normalised
    r = rpy_matrix(rpy)
    np.testing.assert_allclose(axes[1].point, np.array([0.3, 0.0, 0.0]) + r @ [0, 0.02, 0])
    np.testing.assert_allclose(axes[1].direction, r @ [0.0, 0.0, 1.0], atol=1e-12)
