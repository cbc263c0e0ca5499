# ruff: noqa: E501 - SDF fixtures are easier to read one element per line
"""SDFormat fix: closed forms in SDF's conventions, only inertial bytes change, idempotence,
automatic inertia."""

from __future__ import annotations

import math

import numpy as np
import pytest
from support.sdf import sdf_doc, without_inertials

from urdfinertia.body.options import FixOptions
from urdfinertia.descriptions.sdf.read import robot_from_bytes
from urdfinertia.plan.fix import fix_robot

RHO = 1000.0


def fix(data: bytes, **options):
    robot = robot_from_bytes(data, "m.sdf")
    return fix_robot(robot, data, FixOptions(recompute="all", density_prior=False, **options))


def written(output: bytes, name: str):
    """(mass, com, tensor about the CoM in link axes) as the output states them."""
    inertial = robot_from_bytes(output, "out.sdf").link(name).inertial
    return inertial.mass, np.array(inertial.origin.xyz), inertial.tensor_in_link()


def one_shape(shape: str) -> bytes:
    return sdf_doc(f"""<model name="m">
  <link name="l">
    <collision name="c">
      <geometry>{shape}</geometry>
    </collision>
  </link>
</model>""")


def _box(a, b, c):
    m = RHO * a * b * c
    return m, m / 12 * np.diag([b * b + c * c, a * a + c * c, a * a + b * b])


def _cylinder(r, h):
    m = RHO * math.pi * r * r * h
    side = m * (3 * r * r + h * h) / 12
    return m, np.diag([side, side, m * r * r / 2])


def _capsule(r, h):
    mc = RHO * math.pi * r * r * h
    ms = RHO * 4 / 3 * math.pi * r ** 3
    side = mc * (3 * r * r + h * h) / 12 + ms * (2 * r * r / 5 + h * h / 4 + 3 * h * r / 8)
    return mc + ms, np.diag([side, side, mc * r * r / 2 + ms * 2 * r * r / 5])


def _ellipsoid(a, b, c):
    m = RHO * 4 / 3 * math.pi * a * b * c
    return m, m / 5 * np.diag([b * b + c * c, a * a + c * c, a * a + b * b])


CLOSED_FORMS = {  # SDF sizes are full box sides and full cylinder/capsule lengths
    "<box><size>0.2 0.4 0.6</size></box>": _box(0.2, 0.4, 0.6),
    "<cylinder><radius>0.1</radius><length>0.5</length></cylinder>": _cylinder(0.1, 0.5),
    "<sphere><radius>0.3</radius></sphere>": (RHO * 4 / 3 * math.pi * 0.027,
                                              np.eye(3) * 0.4 * RHO * 4 / 3 * math.pi
                                              * 0.3 ** 5),
    "<capsule><radius>0.1</radius><length>0.3</length></capsule>": _capsule(0.1, 0.3),
    "<ellipsoid><radii>0.1 0.2 0.3</radii></ellipsoid>": _ellipsoid(0.1, 0.2, 0.3),
}


@pytest.mark.parametrize("shape", list(CLOSED_FORMS))
def test_primitives_match_closed_forms(shape):
    mass, tensor = CLOSED_FORMS[shape]
    result = fix(one_shape(shape))
    m, com, inertia = written(result.output, "l")
    assert m == pytest.approx(mass, rel=1e-12)
    np.testing.assert_allclose(com, 0, atol=1e-15)
    np.testing.assert_allclose(inertia, tensor, rtol=1e-12, atol=1e-15 * tensor.max())


def test_rotated_offset_box_products_in_sdf_convention():
    """A box turned 30 degrees about z: ixy = -(Ia - Ib) sin cos / ... as -m x y."""
    data = sdf_doc("""<model name="m"><link name="l"><collision name="c">
      <pose degrees="true">0.1 0.2 0.3 0 0 30</pose>
      <geometry><box><size>0.4 0.2 0.1</size></box></geometry></collision></link></model>""")
    m, com, inertia = written(fix(data).output, "l")
    mass, local = _box(0.4, 0.2, 0.1)
    c, s = math.cos(math.pi / 6), math.sin(math.pi / 6)
    r = np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]])
    np.testing.assert_allclose(com, (0.1, 0.2, 0.3), atol=1e-15)
    np.testing.assert_allclose(inertia, r @ local @ r.T, rtol=1e-12, atol=1e-18)
    # -sum(m x y) is negative for a body stretched along the +x+y diagonal
    assert inertia[0, 1] < 0


STYLED = b"""<?xml version='1.0' encoding='UTF-8'?>
<!-- a comment with <link name="fake"> inside -->
<sdf version="1.11">
\t<model name="m">
\t\t<link name="kept">
\t\t\t<pose relative_to="__model__">1 0 0 0 0 0</pose>
\t\t\t<inertial>
\t\t\t\t<!-- measured -->
\t\t\t\t<mass>2.5</mass>
\t\t\t\t<pose>0 0 0 0 0 0</pose>
\t\t\t\t<inertia><ixx>1</ixx><iyy>1</iyy><izz>1</izz></inertia>
\t\t\t\t<fluid_added_mass><xx>0.1</xx></fluid_added_mass>
\t\t\t</inertial>
\t\t\t<collision name='c'><geometry><box><size>0.1 0.2 0.3</size></box></geometry></collision>
\t\t</link>
\t\t<link name="added">
\t\t\t<visual name="v"><geometry><sphere><radius>0.1</radius></sphere></geometry></visual>
\t\t</link>
\t\t<link name="empty"/>
\t\t<link name="one_line"><inertial><mass>3</mass></inertial><collision name="c"><geometry><sphere><radius>0.1</radius></sphere></geometry></collision></link>
\t</model>
</sdf>
"""


def test_only_inertials_change_and_others_children_stay():
    result = fix(STYLED)
    assert without_inertials(result.output) == without_inertials(STYLED)
    out = result.output.decode()
    assert "<!-- measured -->" in out and "<fluid_added_mass><xx>0.1</xx>" in out
    assert "\t\t\t<inertial>\n\t\t\t\t<pose>0 0 0 0 0 0</pose>\n\t\t\t\t<mass>2.5</mass>" in out
    # the added inertial is indented like its sibling <visual>
    assert '<link name="added">\n\t\t\t<inertial>\n\t\t\t\t<pose>' in out
    assert '<link name="empty"/>' in out  # no geometry: untouched
    kept = written(result.output, "kept")
    assert kept[0] == 2.5  # mass kept, as for URDF
    assert written(result.output, "one_line")[0] == 3.0


def test_fix_is_idempotent():
    once = fix(STYLED).output
    assert fix(once).output == once


def test_auto_inertia_written_from_densities_and_attribute_removed():
    data = sdf_doc("""<model name="m">
  <link name="l">
    <inertial auto="true">
      <density>2000</density>
    </inertial>
    <collision name="a"><pose>0.5 0 0 0 0 0</pose><density>500</density>
      <geometry><box><size>1 1 1</size></box></geometry></collision>
    <collision name="b"><pose>-0.5 0 0 0 0 0</pose>
      <geometry><box><size>1 1 1</size></box></geometry></collision>
  </link>
</model>""")
    result = fix(data)
    out = result.output.decode()
    assert 'auto="true"' not in out and "<density>2000</density>" in out
    m, com, _ = written(result.output, "l")
    # collision density overrides the inertial's, which stands for collisions without one
    assert m == pytest.approx(2500.0)
    assert com[0] == pytest.approx((500 * 0.5 - 2000 * 0.5) / 2500)
    assert fix(result.output).output == result.output  # the weights survive the rewrite


def test_auto_with_stated_mass_keeps_the_mass():
    data = sdf_doc("""<model name="m"><link name="l"><inertial auto="true"><mass>7</mass>
      </inertial><collision name="a"><geometry><sphere><radius>0.1</radius></sphere>
      </geometry></collision></link></model>""")
    assert written(fix(data).output, "l")[0] == 7.0


def test_keep_auto_leaves_the_inertial():
    data = sdf_doc("""<model name="m"><link name="l"><inertial auto="true"/>
      <collision name="a"><geometry><sphere><radius>0.1</radius></sphere></geometry>
      </collision></link></model>""")
    result = fix(data, keep_auto=True)
    assert result.output == data
    assert result.links[0].status == "untouched"


def test_nested_models_patch_the_right_link():
    data = sdf_doc("""<model name="outer">
  <link name="l"><collision name="c"><geometry><sphere><radius>0.1</radius></sphere></geometry></collision></link>
  <model name="inner">
    <link name="l"><collision name="c"><geometry><sphere><radius>0.2</radius></sphere></geometry></collision></link>
  </model>
</model>""")
    out = fix(data).output
    small, big = written(out, "l")[0], written(out, "inner::l")[0]
    assert big / small == pytest.approx(8.0)


def test_a_link_that_cannot_be_computed_is_left_and_reported(tmp_path):
    data = sdf_doc("""<model name="m">
  <link name="lost"><inertial><mass>1</mass></inertial>
    <collision name="c"><geometry><mesh><uri>missing.stl</uri></mesh></geometry></collision></link>
  <link name="ok"><collision name="c"><geometry><sphere><radius>0.1</radius></sphere></geometry></collision></link>
</model>""")
    result = fix(data)
    assert [r.name for r in result.left] == ["lost"]
    assert b"<mass>1</mass></inertial>" in result.output  # left as written
    assert written(result.output, "ok")[0] > 0
