"""MJCF geoms MuJoCo does not count for inertia are still the body's shape: a placeholder
inertial is derived from them rather than left."""

from __future__ import annotations

import shutil
from pathlib import Path

import pytest

from urdfinertia.body.options import FixOptions
from urdfinertia.descriptions.formats import read_description
from urdfinertia.plan.fix import fix_file
from urdfinertia.plan.results import Status

DATA = Path(__file__).parents[2] / "data" / "geometry"

MODEL = """<mujoco model="groups">
  <compiler inertiagrouprange="0 2"/>
  <asset><mesh name="bar" file="bar.stl"/></asset>
  <worldbody>
    <body name="arm"><joint name="j"/>
      <inertial pos="0.15 0 0" mass="2" diaginertia="1 1 1"/>
      <geom type="mesh" mesh="bar" group="{group}" {extra}/>
    </body>
  </worldbody>
</mujoco>
"""


@pytest.mark.parametrize(("group", "extra"), [
    (3, ""),                           # a display group outside inertiagrouprange
    (5, 'contype="0" conaffinity="0"'),  # and not colliding either
    (1, 'mass="0"'),                   # counted group, stated massless
])
def test_uncounted_geoms_make_the_inertial(tmp_path, group, extra):
    shutil.copy(DATA / "bar.stl", tmp_path / "bar.stl")
    path = tmp_path / "groups.xml"
    path.write_text(MODEL.format(group=group, extra=extra))
    robot, _ = read_description(path)
    assert robot.link("arm").inertia_geometry == ()  # MuJoCo counts none of them
    arm = fix_file(path, FixOptions()).link("arm")
    assert arm.status == Status.RECOMPUTED
    assert arm.choice is not None and arm.choice.kind == "mesh"
    assert arm.assembly.total.mass == pytest.approx(2.0)  # the kept mass, spread by volume
    assert arm.kept == ("mass", "com")
