"""An invalid inertial is never left as it was: when no geometry of the link is its body
(every candidate implies a density no material has), it gets the minimal repair."""

from __future__ import annotations

from urdfinertia.body.options import FixOptions
from urdfinertia.cache.library import MeshLibrary
from urdfinertia.descriptions.formats import robot_from_bytes
from urdfinertia.descriptions.inertial import RawInertial
from urdfinertia.plan.fix import fix_robot
from urdfinertia.plan.results import Action, Status

# 2 kg in two 1 cm boxes: 1e6 kg/m^3 either way (markers); the tensor breaks A + B >= C
URDF = b"""<robot name="r">
  <link name="base"/>
  <joint name="j" type="revolute"><parent link="base"/><child link="hand"/>
    <axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="100" velocity="1"/></joint>
  <link name="hand">
    <inertial><mass value="2"/>
      <inertia ixx="0.001" iyy="0.001" izz="0.005" ixy="0" ixz="0" iyz="0"/></inertial>
    <collision><geometry><box size="0.01 0.01 0.01"/></geometry></collision>
    <visual><origin xyz="0.001 0 0"/><geometry><box size="0.01 0.01 0.01"/></geometry></visual>
  </link>
</robot>
"""


def test_invalid_inertial_with_only_marker_geometry_is_repaired(tmp_path):
    path = tmp_path / "r.urdf"
    path.write_bytes(URDF)
    robot = robot_from_bytes(URDF, path)
    result = fix_robot(robot, URDF, FixOptions(), MeshLibrary())
    hand = result.link("hand")
    assert hand.status == Status.REPAIRED, (hand.status, hand.decision)
    assert hand.action == Action.REPAIR
    assert "marker" in hand.decision
    after = RawInertial.from_mass_properties(hand.after)
    assert after.diagnosis().valid
    assert hand.after.mass == 2.0  # the written mass is kept
