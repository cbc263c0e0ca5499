# ruff: noqa: E501 - SDF fixtures are easier to read one element per line
"""SDFormat visuals are the body's shape too: a derived inertial may use them."""

from __future__ import annotations

import numpy as np
import pytest
from support.sdf import sdf_doc

from urdfinertia.body.options import FixOptions
from urdfinertia.plan.fix import fix_file
from urdfinertia.plan.results import Status

MODEL = """<model name="m">
  <link name="base"/>
  <link name="arm">
    <inertial><pose>0.2 0 0 0 0 0</pose><mass>3</mass>
      <inertia><ixx>1</ixx><iyy>1</iyy><izz>1</izz><ixy>0</ixy><ixz>0</ixz><iyz>0</iyz></inertia>
    </inertial>
    {collision}
    <visual name="shell"><pose>0.2 0 0 0 0 0</pose>
      <geometry><box><size>0.4 0.1 0.05</size></box></geometry></visual>
  </link>
  <joint name="j" type="revolute"><parent>base</parent><child>arm</child>
    <axis><xyz>0 0 1</xyz></axis></joint>
</model>"""


def _fix(tmp_path, collision: str):
    path = tmp_path / "m.sdf"
    path.write_bytes(sdf_doc(MODEL.format(collision=collision)))
    return fix_file(path, FixOptions()).link("arm")


def test_a_link_with_only_visuals_is_derived_from_them(tmp_path):
    arm = _fix(tmp_path, "")
    assert arm.status == Status.RECOMPUTED and arm.geometry == "visual"
    # the box's closed form at the kept 3 kg
    a, b, c = 0.4, 0.1, 0.05
    expected = 3.0 / 12 * np.diag([b * b + c * c, a * a + c * c, a * a + b * b])
    np.testing.assert_allclose(arm.assembly.total.inertia, expected, rtol=1e-12)


def test_a_marker_collision_gives_way_to_the_visual_body(tmp_path):
    # 3 kg in a 1 cm cube is 3e6 kg/m^3: a marker, not the body; the visual box is
    marker = ('<collision name="c"><pose>0.2 0 0 0 0 0</pose><geometry><box><size>0.01 0.01 0.01</size>'
              '</box></geometry></collision>')
    arm = _fix(tmp_path, marker)
    assert arm.status == Status.RECOMPUTED and arm.geometry == "visual"
    assert arm.choice is not None and "implied density plausible" in arm.choice.why
    assert arm.choice.density == pytest.approx(3.0 / (0.4 * 0.1 * 0.05))
