"""descriptions/inertial.py: a written inertial is judged as written, computed with only when
its values are within the readers' range."""

from __future__ import annotations

import numpy as np
import pytest

from urdfinertia import cli
from urdfinertia.descriptions.inertial import RawInertial


def raw(mass: float, com: float = 0.0, moment: float = 0.1) -> RawInertial:
    return RawInertial(mass, np.full(3, com), np.eye(3) * moment)


@pytest.mark.parametrize(("value", "ok"), [(1.0, True), (1e9, True), (1e307, False),
                                           (1e-320, False), (float("nan"), False),
                                           (-1.0, False), (0.0, False)])
def test_a_mass_to_compute_with_is_finite_positive_and_in_range(value, ok):
    assert raw(value).mass_ok is ok
    assert (raw(value).mass_properties() is not None) is ok


def test_a_com_or_tensor_past_the_range_is_not_computed_with():
    assert not raw(1.0, com=1e300).com_ok
    assert not raw(1.0, moment=1e308).tensor_in_range
    assert raw(1.0, moment=1e308).diagnosis().valid  # a valid tensor, if a useless one
    assert raw(1.0, moment=1e308).mass_properties() is None


ROBOT = """<robot name="r">
  <link name="base"><inertial><mass value="{mass}"/>
    <inertia ixx="{i}" ixy="{p}" ixz="{p}" iyy="{i}" iyz="{p}" izz="{i}"/></inertial>
    <collision><geometry><box size="0.1 0.2 0.3"/></geometry></collision></link>
  <link name="arm"><inertial><mass value="1e8"/>
    <inertia ixx="1e8" ixy="0" ixz="0" iyy="1e8" iyz="0" izz="1e8"/></inertial>
    <collision><geometry><box size="0.1 0.2 0.3"/></geometry></collision></link>
  <joint name="j" type="revolute"><parent link="base"/><child link="arm"/>
    <limit effort="1" velocity="1" lower="0" upper="1"/></joint>
  <link name="tool"><inertial><mass value="1"/>
    <inertia ixx="{i}" ixy="{p}" ixz="{p}" iyy="{i}" iyz="{p}" izz="{i}"/></inertial></link>
  <joint name="t" type="fixed"><parent link="arm"/><child link="tool"/></joint>
  <link name="tool2"><inertial><mass value="1"/>
    <inertia ixx="{i}" ixy="{p}" ixz="{p}" iyy="{i}" iyz="{p}" izz="{i}"/></inertial></link>
  <joint name="t2" type="fixed"><parent link="arm"/><child link="tool2"/></joint>
</robot>
"""


@pytest.mark.parametrize(("mass", "i", "p", "code"), [
    ("1e307", "1", "0", "mass-absurd"),  # check's density and scale tests overflowed
    ("10", "1e308", "1e308", "inertia-absurd"),  # the lumped body of fixed links did
])
def test_check_judges_absurd_written_values_without_crashing(tmp_path, capsys, mass, i, p,
                                                             code):
    """Found by fuzzing: ``check`` exit 3, "ValueError: mass properties must be finite",
    on a kept mass of 1e307 (20 mutants) and moments of 1e308."""
    path = tmp_path / "r.urdf"
    path.write_text(ROBOT.format(mass=mass, i=i, p=p))
    code_ = cli.main(["check", str(path), "--format", "json", "--no-cache"])
    out = capsys.readouterr()
    assert code_ == 1, out.err
    assert "internal error" not in out.err
    assert f'"{code}"' in out.out
