"""explain.py and cli_explain.py: the per-element / per-part breakdown of one link."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from urdfinertia.analysis.explain import explain_link
from urdfinertia.body.options import FixOptions
from urdfinertia.body.spec import load_spec
from urdfinertia.cli import main
from urdfinertia.descriptions.urdf.read import read_urdf
from urdfinertia.plan.fix import fix_file

ROOT = Path(__file__).resolve().parents[2]
NM7MAR, NM7MAR_SPEC = ROOT / "robots" / "nm7mar.urdf", ROOT / "robots" / "nm7mar.inertia.toml"
#: Sums of a handful of tensors: round-off only, relative to the link tensor's size.
RTOL = 1e-12

URDF = """<robot name="r">
  <link name="base">
  </link>
  <link name="body">
    <collision name="shell">
      <origin xyz="0.1 0.02 -0.05" rpy="0.3 -0.2 0.9"/>
      <geometry><box size="0.3 0.12 0.1"/></geometry>
    </collision>
  </link>
  <joint name="j" type="fixed"><parent link="base"/><child link="body"/></joint>
</robot>
"""

SPEC = """
[links.body]
mass = 3.0
[links.body.elements.housing.parts.shell]
collision = "shell"
[links.body.elements.housing.parts.bore]
cylinder = { radius = 0.03, length = 0.3 }
xyz = [0.1, 0.02, -0.05]
rpy = [0.0, 1.5707963267948966, 0.0]
cavity = true
[links.body.elements.drive]
xyz = [0.2, 0.0, 0.0]
rpy = [0.1, 0.2, 0.3]
[links.body.elements.drive.parts.motor]
cylinder = { radius = 0.025, length = 0.07 }
xyz = [0.0, 0.05, 0.02]
mass = 0.6
[links.body.elements.drive.parts.encoder]
sphere = { radius = 0.015 }
xyz = [0.0, 0.0, 0.06]
material = "brass"
"""


@pytest.fixture
def breakdown(tmp_path):
    urdf, spec = tmp_path / "r.urdf", tmp_path / "r.toml"
    urdf.write_text(URDF)
    spec.write_text(SPEC)
    robot, _ = read_urdf(urdf)
    return explain_link(robot, "body", FixOptions(spec=load_spec(spec)))


def test_contributions_add_up_to_the_link(breakdown):
    b = breakdown
    total = b.total
    scale = np.abs(total.inertia).max()
    assert sum(e.element.mass for e in b.elements) == pytest.approx(total.mass, rel=RTOL)
    i_sum = sum(e.element.inertia_link for e in b.elements)  # eq. 44
    np.testing.assert_allclose(i_sum, total.inertia, atol=RTOL * scale)
    np.testing.assert_allclose(sum(e.element.share for e in b.elements), 1.0, atol=1e-9)
    for e in b.elements:  # parts add up to their element
        np.testing.assert_allclose(sum(p.inertia_link for p in e.parts), e.element.inertia_link,
                                   atol=RTOL * scale)
        np.testing.assert_allclose(sum(p.share for p in e.parts), e.element.share, atol=1e-9)


def test_each_contribution_obeys_huygens_steiner(breakdown):
    b = breakdown
    scale = np.abs(b.total.inertia).max()
    for c in [e.element for e in b.elements] + [p for e in b.elements for p in e.parts]:
        d = c.com - b.total.com  # eq. 43: own-CoM tensor + m (|d|^2 E - d d^T)
        expected = c.inertia_own + c.mass * (d @ d * np.eye(3) - np.outer(d, d))
        np.testing.assert_allclose(c.inertia_link, expected, atol=RTOL * scale)


def test_share_is_projection_on_principal_axes(breakdown):
    b = breakdown
    moments, axes = np.linalg.eigh(b.total.inertia)  # ascending, like the tool
    for e in b.elements:
        expected = np.array([axes[:, k] @ e.element.inertia_link @ axes[:, k] / moments[k]
                             for k in range(3)])
        np.testing.assert_allclose(e.element.share, expected, atol=1e-9)


def test_cavity_contributes_negatively(breakdown):
    housing = breakdown.elements[0]
    bore = next(p for p in housing.parts if p.name == "housing/bore")
    assert bore.cavity and bore.mass < 0 and bore.volume < 0
    assert np.all(bore.share < 0)
    motor = breakdown.elements[1].parts[0]
    assert motor.mass == pytest.approx(0.6, rel=RTOL)
    encoder = breakdown.elements[1].parts[1]
    assert encoder.density == 8500.0  # brass from the built-in table


def test_cli_table_and_json_agree_with_fix(tmp_path, capsys, monkeypatch):
    monkeypatch.setenv("COLUMNS", "250")  # piped output wraps at COLUMNS (default 100)
    assert main(["explain", str(NM7MAR), "--link", "link1", "--spec", str(NM7MAR_SPEC)]) == 0
    table = capsys.readouterr().out
    for word in ("r/housing", "k/body", "l/housing", "link total", "I_p,s", "pinned 14.4 kg"):
        assert word in table
    assert main(["explain", str(NM7MAR), "--link", "link1", "--spec", str(NM7MAR_SPEC),
                 "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    fixed = fix_file(NM7MAR, FixOptions(spec=load_spec(NM7MAR_SPEC)))
    total = next(r for r in fixed.links if r.name == "link1").assembly.total
    assert data["total"]["mass"] == pytest.approx(total.mass, rel=RTOL)
    assert data["total"]["inertia"]["ixy"] == pytest.approx(total.inertia[0, 1], rel=RTOL)
    assert [e["name"] for e in data["elements"]] == ["r", "k", "l"]
    assert [p["name"] for p in data["elements"][1]["parts"]] == ["k/body"]
    shares = np.array([e["share_of_principal_moments"] for e in data["elements"]])
    np.testing.assert_allclose(shares.sum(axis=0), 1.0, atol=1e-9)


def test_cli_without_spec_uses_geometry_elements(capsys, monkeypatch):
    monkeypatch.setenv("COLUMNS", "250")  # piped output wraps at COLUMNS (default 100)
    assert main(["explain", str(NM7MAR), "--link", "link2"]) == 0
    out = capsys.readouterr().out
    assert "collision[0] 'link2_r'" in out and "kept 5 kg" in out


@pytest.mark.parametrize("link, words", [("nope", "no link named 'nope'"),
                                         ("base", "nothing to explain")])
def test_cli_errors(tmp_path, capsys, link, words):
    urdf = tmp_path / "r.urdf"
    urdf.write_text(URDF)
    assert main(["explain", str(urdf), "--link", link]) == 2
    err = capsys.readouterr().err
    assert words in err and err.count("\n") == 1
