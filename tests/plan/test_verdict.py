"""The per-link verdict: geometry that is not the body is never derived from, invalid
values are never left invalid, and what could not be verified is said."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import urdfinertia
from urdfinertia.cli import main
from urdfinertia.descriptions.formats import read_description
from urdfinertia.plan.fix import fix_file
from urdfinertia.plan.results import Action, Status

JOINT = """<joint name="j" type="revolute"><parent link="base"/><child link="{child}"/>
  <axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>"""


def robot(tmp_path: Path, inertia: str, geometry: str, name: str = "r.urdf") -> Path:
    """A base and one moving link "motor" of 0.15 kg, CoM 27 mm below its frame."""
    text = f"""<robot name="r"><link name="base"/>
  <link name="motor">
    <inertial><origin xyz="0 0 -0.027"/><mass value="0.15"/>
      <inertia {inertia}/></inertial>
    <visual><geometry>{geometry}</geometry></visual>
  </link>
  {JOINT.format(child="motor")}
</robot>"""
    path = tmp_path / name
    path.write_text(text)
    return path


VALID = 'ixx="1.1e-4" ixy="0" ixz="0" iyy="1.1e-4" iyz="0" izz="6e-5"'
#: principal moments 1e-4, 1e-4, 3e-4: A + B < C
TRIANGLE = 'ixx="1e-4" ixy="0" ixz="0" iyy="1e-4" iyz="0" izz="3e-4"'
MARKER = '<box size="0.01 0.01 0.01"/>'  # 0.15 kg in 1 cm^3: 1.5e5 kg/m^3


def test_a_marker_box_leaves_a_valid_inertial_as_written(tmp_path):
    path = robot(tmp_path, VALID, MARKER)
    result = fix_file(path)
    r = result.link("motor")
    assert (r.status, r.action) == (Status.KEPT, Action.KEEP)
    assert r.why == ("geometry is a marker, not the body (implied density 1.5e+05 kg/m^3, "
                     "denser than any material)")
    assert result.output == result.original
    # check says the same in the same words, and the density warning is the one left
    found = urdfinertia.check(path)
    assert [v.decision for v in found.links if v.name == "motor"] == ["kept: " + r.why]
    assert "implausible-density" in {f.code for f in found.findings}


def test_a_marker_box_gives_an_invalid_inertial_the_minimal_repair(tmp_path):
    path = robot(tmp_path, TRIANGLE, MARKER)
    r = fix_file(path).link("motor")
    assert (r.status, r.action) == (Status.REPAIRED, Action.REPAIR)
    assert r.why.startswith("triangle-inequality; geometry is a marker, not the body")
    assert r.kept == ("mass", "com") and r.derived == ("tensor",)
    # mass and CoM as written; the tensor lifted just enough (--repair-only's lift)
    assert r.after.mass == 0.15
    np.testing.assert_array_equal(r.after.com, [0.0, 0.0, -0.027])
    assert r.after.is_physical()
    moments = np.sort(np.linalg.eigvalsh(r.after.inertia))
    assert moments[0] + moments[1] >= moments[2] * (1 - 1e-12)
    assert moments[2] == pytest.approx(3e-4, rel=1e-9)  # the largest is not lowered


def test_unreadable_geometry_gives_an_invalid_inertial_the_minimal_repair(tmp_path):
    path = robot(tmp_path, TRIANGLE, '<mesh filename="not_shipped.stl"/>')
    result = fix_file(path)
    r = result.link("motor")
    assert (r.status, r.action) == (Status.REPAIRED, Action.REPAIR)
    assert r.why == "triangle-inequality; geometry could not be read"
    assert r.after.is_physical() and r.after.mass == 0.15
    assert r.unverified and "not_shipped.stl" in r.unverified[0].message
    assert not result.left  # nothing left invalid


def test_unreadable_geometry_keeps_a_valid_inertial_and_says_it_was_not_verified(
        tmp_path, capsys):
    path = robot(tmp_path, VALID, '<mesh filename="not_shipped.stl"/>')
    r = fix_file(path).link("motor")
    assert (r.status, r.action) == (Status.KEPT, Action.KEEP)
    assert "not verified" in r.why
    # check could not do what it was asked: exit 1, one summary line with the way out
    assert main(["check", "-q", str(path)]) == 1
    out = capsys.readouterr().out
    assert "not verified: 1 mesh unresolved or unreadable in 1 link: pass --package-dir " \
        "NAME=PATH" in out
    assert main(["check", "-q", "--no-geometry", str(path)]) == 0  # values only: verified


def test_status_and_action_are_string_enums():
    assert Status("recomputed") is Status.RECOMPUTED and str(Action.KEEP) == "keep"
    assert Status.KEPT == "kept"  # old string comparisons keep working


def test_decisions_carry_no_command_line_flags(tmp_path):
    # a floating base and every-link mode: plain words in the library
    path = tmp_path / "f.urdf"
    path.write_text('<robot name="f"><link name="base"><collision><geometry>'
                    '<box size="1 1 1"/></geometry></collision></link></robot>')
    (r,) = fix_file(path).links
    assert "--" not in r.decision
    (r,) = urdfinertia.fix(path, recompute="all").links
    assert r.why == "every link asked for" and "--" not in r.decision


def test_explain_names_the_three_nearest_links(tmp_path, capsys):
    path = robot(tmp_path, VALID, '<box size="0.05 0.05 0.08"/>')
    assert main(["explain", str(path), "--link", "motr"]) == 2
    err = capsys.readouterr().err
    assert "no link named 'motr' (did you mean: motor, base?)" in err


def test_explain_plot_says_where_the_png_went(tmp_path, capsys):
    path = robot(tmp_path, TRIANGLE, '<box size="0.05 0.05 0.08"/>')
    png = tmp_path / "motor.png"
    assert main(["explain", str(path), "--link", "motor", "--plot", str(png)]) == 0
    assert f"urdf-inertia: wrote {png}" in capsys.readouterr().err
    assert png.read_bytes()[:4] == b"\x89PNG"


def test_library_check_reads_geometry_like_the_cli(tmp_path):
    # geometry findings come without handing the library a mesh library
    path = robot(tmp_path, VALID, MARKER)
    model, _ = read_description(path)
    codes = {f.code for f in urdfinertia.check_robot(model)}
    assert "implausible-density" in codes
    assert "implausible-density" not in {
        f.code for f in urdfinertia.check_robot(model, geometry=False)}


def test_json_and_sarif_carry_the_same_decision(tmp_path):
    import json

    path = robot(tmp_path, VALID, MARKER)
    js, sarif = tmp_path / "c.json", tmp_path / "c.sarif"
    assert main(["check", "-q", str(path), "--json", str(js), "--sarif", str(sarif)]) == 0
    why = fix_file(path).link("motor").why
    rows = json.loads(js.read_text())["files"][0]["findings"]
    (density,) = [f for f in rows if f["code"] == "implausible-density"]
    assert density["fix"] == "would be kept: " + why
    results = json.loads(sarif.read_text())["runs"][0]["results"]
    (density,) = [r for r in results if r["ruleId"] == "UI202"]
    assert density["properties"]["fix"] == "would be kept: " + why
