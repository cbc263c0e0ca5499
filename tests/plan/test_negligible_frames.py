"""A placeholder on a frame body (a link under 0.1 % of the robot's mass) with nothing to
derive it from is left as it is without failing the run; one of real mass is left with
exit 1 (listed in ``links_left``)."""

from __future__ import annotations

import pytest

from urdfinertia.body.options import FixOptions
from urdfinertia.cache.library import MeshLibrary
from urdfinertia.descriptions.formats import robot_from_bytes
from urdfinertia.plan.fix import fix_robot
from urdfinertia.plan.results import Status

TEMPLATE = """<robot name="r">
  <link name="base"><inertial><mass value="30"/>
    <inertia ixx="0.5" iyy="0.6" izz="0.7" ixy="0" ixz="0" iyz="0"/></inertial>
    <collision><geometry><box size="0.4 0.3 0.2"/></geometry></collision></link>
  <joint name="j" type="revolute"><parent link="base"/><child link="hip"/>
    <axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="100" velocity="1"/></joint>
  <link name="hip"><inertial><mass value="{mass}"/>
    <inertia ixx="{i}" iyy="{i}" izz="{i}" ixy="0" ixz="0" iyz="0"/></inertial></link>
</robot>
"""


@pytest.mark.parametrize(("mass", "inertia", "status"), [
    (0.001, 1e-6, Status.UNTOUCHED),  # ANYmal C's hips: a frame body
    # a real part with a placeholder and nothing to derive from: no value to keep, the
    # smallest honest body instead (a solid sphere of the mass)
    (2.0, 1.0, Status.REPAIRED),
])
def test_placeholder_without_geometry(tmp_path, mass, inertia, status):
    data = TEMPLATE.format(mass=mass, i=inertia).encode()
    path = tmp_path / "r.urdf"
    path.write_bytes(data)
    result = fix_robot(robot_from_bytes(data, path), data, FixOptions(), MeshLibrary())
    hip = result.link("hip")
    assert hip.status == status, hip.decision
    assert "placeholder" in hip.why
    assert (hip in result.left) == (status == Status.LEFT)


def test_a_mass_whose_sphere_underflows_gets_the_minimal_body(tmp_path):
    """1e-300 kg (a fuzzed value) with a placeholder: the solid sphere of that mass has
    moments that underflow to 0, so the link gets the minimal moving body instead."""
    from urdfinertia.inertia.validity import diagnose_tensor
    from urdfinertia.plan.policy import MIN_BODY_MASS

    data = TEMPLATE.format(mass="1e-300", i=1.0).encode()
    path = tmp_path / "r.urdf"
    path.write_bytes(data)
    hip = fix_robot(robot_from_bytes(data, path), data, FixOptions(), MeshLibrary()).link("hip")
    assert hip.status == Status.REPAIRED, hip.decision
    assert hip.after.mass == MIN_BODY_MASS
    assert diagnose_tensor(hip.after.inertia).valid
