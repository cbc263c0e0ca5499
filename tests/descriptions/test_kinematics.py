"""descriptions/kinematics.py: zero-configuration poses and fixed groups of the joint tree."""

import numpy as np

from urdfinertia.descriptions.kinematics import Kinematics, zero_configuration_poses
from urdfinertia.descriptions.model import Joint, Link, Origin, Robot
from urdfinertia.inertia.rotation import pose_matrix


def chain_robot(origins) -> Robot:
    links = tuple(Link(f"l{i}") for i in range(len(origins) + 1))
    joints = tuple(Joint(f"j{i}", "revolute", f"l{i}", f"l{i + 1}", o)
                   for i, o in enumerate(origins))
    return Robot("chain", links, joints)


def test_zero_configuration_is_the_product_of_joint_origins(rng):
    origins = [Origin(tuple(rng.normal(size=3)), tuple(rng.uniform(-3, 3, 3)))
               for _ in range(4)]
    poses, notes = zero_configuration_poses(chain_robot(origins))
    assert notes == ()
    expected = np.eye(4)
    np.testing.assert_array_equal(poses["l0"], np.eye(4))
    for i, o in enumerate(origins):
        expected = expected @ pose_matrix(o.xyz, o.rpy)
        np.testing.assert_allclose(poses[f"l{i + 1}"], expected, atol=1e-12)


def test_joints_listed_before_their_parents_still_chain():
    origins = [Origin((1.0, 0.0, 0.0)), Origin((0.0, 2.0, 0.0))]
    robot = chain_robot(origins)
    robot = Robot("r", robot.links, robot.joints[::-1])
    poses, _ = zero_configuration_poses(robot)
    np.testing.assert_allclose(poses["l2"][:3, 3], [1.0, 2.0, 0.0])


def test_odd_trees_are_noted_not_fatal():
    links = (Link("a"), Link("b"), Link("c"))
    joints = (Joint("j", "fixed", "a", "nowhere"),)
    poses, notes = zero_configuration_poses(Robot("r", links, joints))
    assert set(poses) == {"a", "b", "c"}
    assert any("unknown link" in n for n in notes)
    assert any("root links" in n for n in notes)


def test_fixed_groups_compose_the_fixed_joint_origins():
    links = (Link("base"), Link("frame"), Link("sensor"), Link("arm"))
    joints = (Joint("f1", "fixed", "base", "frame", Origin((0.1, 0.0, 0.0))),
              Joint("f2", "fixed", "frame", "sensor", Origin((0.0, 0.2, 0.0), (0, 0, 1.0))),
              Joint("r", "revolute", "base", "arm", Origin((0.0, 0.0, 0.3))))
    kin = Kinematics(Robot("r", links, joints))
    group = kin.group_of("sensor")
    assert group.root == "base" and group.members == ("base", "frame", "sensor")
    expected = pose_matrix((0.1, 0, 0), (0, 0, 0)) @ pose_matrix((0, 0.2, 0), (0, 0, 1.0))
    np.testing.assert_allclose(group.poses[2], expected, atol=1e-15)
    assert kin.moves("arm") and not kin.moves("sensor") and not kin.moves("base")
    assert kin.group_of("arm").members == ("arm",)
