"""The mass prior in ``fix``: a link with no usable mass gets the density the prior
predicts for it, with its band in the table, the JSON and ``explain``, and the robot's
total beside what 1000 kg/m^3 gives; a density asked for, a written mass and a target mass
win over it."""

from __future__ import annotations

import json

import numpy as np
import pytest

import urdfinertia
from urdfinertia.cli import main
from urdfinertia.priors.features import link_features, robot_features
from urdfinertia.priors.model import mass_prior

ARM = """<robot name="arm">
  <link name="base"><inertial><mass value="4"/><inertia ixx="0.02" ixy="0" ixz="0"
    iyy="0.02" iyz="0" izz="0.01"/></inertial>
    <collision><geometry><box size="0.2 0.2 0.1"/></geometry></collision></link>
{links}
</robot>
"""
LINK = """  <link name="l{i}"><collision><origin xyz="0 0 0.15"/><geometry>
    <cylinder radius="0.05" length="0.3"/></geometry></collision></link>
  <joint name="j{i}" type="revolute"><parent link="{parent}"/><child link="l{i}"/>
    <origin xyz="0 0 0.3"/><axis xyz="0 1 0"/>
    <limit lower="-1" upper="1" effort="50" velocity="1"/></joint>"""


@pytest.fixture
def arm(tmp_path):
    links = "\n".join(LINK.format(i=i, parent="base" if i == 1 else f"l{i - 1}")
                      for i in range(1, 5))
    path = tmp_path / "arm.urdf"
    path.write_text(ARM.format(links=links))
    return path


def _volume() -> float:
    import math
    return math.pi * 0.05 ** 2 * 0.3


def test_a_link_without_mass_gets_the_prior_and_its_band(arm):
    result = urdfinertia.fix(arm)
    robot, _ = urdfinertia.read_description(arm)
    rf = robot_features(robot)
    for name in ("l1", "l2", "l3", "l4"):
        r = result.link(name)
        assert r.status == "recomputed"
        band = r.error_bar.mass
        # the prior's own prediction over the geometry fix integrates
        box = (np.array([-0.05, -0.05, 0.0]), np.array([0.05, 0.05, 0.3]))
        f = link_features(name, rf, volume=_volume(), box=box, geometry="primitive",
                          role="collision", others=(_volume(),))
        assert r.after.mass == pytest.approx(band.density * _volume(), rel=1e-9)
        assert band.low < r.after.mass < band.high and band.level == pytest.approx(0.8)
        assert band.water == pytest.approx(1000 * _volume(), rel=1e-9)
        assert r.after.mass != pytest.approx(1000 * _volume(), rel=1e-3)
        assert band.density == pytest.approx(mass_prior(f).density, rel=1e-9)
    assert result.link("base").status == "kept"  # a written mass wins
    said = [f.message for f in result.robot_findings if f.code == "mass-prior"]
    assert len(said) == 1 and said[0].startswith("4 link(s) with no mass: ")
    assert "at 1000 kg/m³; the prior gives" in said[0]


def test_the_band_is_in_the_table_the_json_and_explain(arm, tmp_path, capsys):
    out, doc = tmp_path / "out.urdf", tmp_path / "out.json"
    assert main(["fix", str(arm), "-o", str(out), "--json", str(doc)]) == 0
    text = capsys.readouterr()
    assert "mass prior " in text.out and "4 link(s) with no mass" in text.err
    row = next(r for r in json.loads(doc.read_text())["links"] if r["link"] == "l2")
    assert row["error_bar"]["mass"]["low"] < row["error_bar"]["mass"]["high"]
    assert main(["explain", str(arm), "--link", "l2"]) == 0
    assert "mass " in capsys.readouterr().out.split("error bar: ")[1]


def test_a_density_asked_for_is_constant(arm, tmp_path):
    for result in (urdfinertia.fix(arm, density=1000.0),):
        r = result.link("l2")
        assert r.after.mass == pytest.approx(1000 * _volume(), rel=1e-9)
        assert r.error_bar.mass is None
        assert not [f for f in result.robot_findings if f.code == "mass-prior"]
    out = tmp_path / "out.urdf"
    assert main(["fix", str(arm), "-o", str(out), "--density", "1000", "-q"]) == 0
    robot, _ = urdfinertia.read_description(out)
    assert robot.link("l2").inertial.mass == pytest.approx(1000 * _volume(), rel=1e-6)


def test_a_target_mass_wins_over_the_prior(arm):
    result = urdfinertia.fix(arm, total_mass=20.0)
    derived = sum(result.link(f"l{i}").after.mass for i in range(1, 5))
    assert derived + 4 == pytest.approx(20.0, rel=1e-9)
    assert all(result.link(f"l{i}").error_bar.mass is None for i in range(1, 5))
    assert not [f for f in result.robot_findings if f.code == "mass-prior"]


def test_check_of_the_output_is_clean_and_a_second_fix_changes_nothing(arm, tmp_path):
    out = tmp_path / "out.urdf"
    assert main(["fix", str(arm), "-o", str(out), "-q"]) == 0
    checked = urdfinertia.check(out)
    assert checked.exit_code(strict=True) == 0 and checked.would_change == ()
