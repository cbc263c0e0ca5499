"""check against known totals (UI703 total-mass-mismatch): the written masses held against
``--total-mass`` and the spec's ``total_mass`` / ``[subtree.NAME] mass``; and a real robot
with a published total, before and after ``fix --total-mass``.

The fixture (tests/data/total_mass/arm.urdf): ``base`` 2 kg and ``finger`` 0.1 kg written,
``upper`` (4 kg) and ``hand`` (1 kg) derived from their boxes at 1000 kg/m^3.
"""

from __future__ import annotations

import json
from pathlib import Path

import pytest

import urdfinertia
from urdfinertia.body.options import FixOptions
from urdfinertia.body.spec import parse_spec
from urdfinertia.cli import main
from urdfinertia.plan.fix import fix_file

ARM = Path(__file__).resolve().parents[1] / "data" / "total_mass" / "arm.urdf"


def mismatches(result):
    return [f for f in result.findings if f.code == "total-mass-mismatch"]


def test_written_total_against_the_target():
    result = urdfinertia.check(ARM, total_mass=4.6)
    (found,) = mismatches(result)
    assert found.severity == "warning" and found.rule.id == "UI703" and found.link is None
    text = found.message
    assert "weigh 2.1 kg as written, 2.5 kg (54.35%) under the target 4.6 kg" in text
    assert "fix derives the mass of 2 link(s) (upper, hand) and keeps 2" in text
    # what a plain fix writes (its mass prior for the two links; 7.1 kg at 1000 kg/m^3)
    plain = sum(r.after.mass for r in fix_file(ARM).links if r.after is not None)
    assert 2.1 < plain < 7.1
    assert f"without the target fix would write {plain:g} kg" in text
    assert f"fix with the target scales 2 link(s) x{(4.6 - 2.1) / (plain - 2.1):g}" in text
    # the plan is fix's with the target: one answer
    fixed = fix_file(ARM, FixOptions(total_mass=4.6))
    assert {r.name: r.after.mass for r in result.links} == pytest.approx(
        {r.name: r.after.mass for r in fixed.links}, rel=1e-12)


@pytest.mark.parametrize(("target", "tolerance", "found"), [
    (2.12, 0.01, False),  # 0.94 % under
    (2.2, 0.01, True),  # 4.5 % under
    (2.2, 0.05, False),
])
def test_tolerance(target, tolerance, found):
    result = urdfinertia.check(ARM, total_mass=target, mass_tolerance=tolerance)
    assert bool(mismatches(result)) is found


def test_a_target_fix_refuses_is_reported_not_raised():
    """2 kg is below the kept 2.1 kg: fix refuses; check says so and plans without it."""
    result = urdfinertia.check(ARM, total_mass=2.0)
    (found,) = mismatches(result)
    assert "0.1 kg (5.00%) over the target 2 kg" in found.message
    assert "fix with the target refuses: " in found.message
    assert "kept masses alone weigh 2.1 kg" in found.message
    plain = {r.name: r.after.mass for r in fix_file(ARM).links}
    assert {r.name: r.after.mass for r in result.links} == pytest.approx(plain, rel=1e-12)


def test_spec_subtree_and_total(tmp_path):
    spec = parse_spec("total_mass = 2.1\n[subtree.hand]\nmass = 0.35\n",
                      tmp_path / "spec.toml")
    result = urdfinertia.check(ARM, spec=spec)
    (found,) = mismatches(result)  # the total is met as written; the hand is not
    assert found.link == "hand"
    assert "subtree 'hand' weigh 0.1 kg as written" in found.message
    assert "(the spec; tolerance 1.00%)" in found.message


def test_without_geometry_only_the_written_figures():
    (found,) = mismatches(urdfinertia.check(ARM, geometry=False, total_mass=4.6))
    assert "2.1 kg as written" in found.message and "fix derives" not in found.message


def test_cli(tmp_path, capsys):
    def ui703(*argv: str) -> list[dict]:
        main(["check", str(ARM), "--format", "json", *argv])  # missing inertials: exit 1
        rows = json.loads(capsys.readouterr().out)["files"][0]["findings"]
        return [r for r in rows if r["rule"] == "UI703"]

    (row,) = ui703("--total-mass", "4.6")
    assert row["severity"] == "warning" and row["link"] is None
    assert ui703("--total-mass", "4.6", "--mass-tolerance", "0.6") == []
    assert ui703() == []
    (row,) = ui703("--total-mass", "4.6", "--scale-kept")  # the plan scales kept too
    assert "scales 4 link(s)" in row["message"]
    assert main(["check", str(ARM), str(ARM), "--total-mass", "4.6"]) == 2
    assert "--total-mass takes a single description" in capsys.readouterr().err
    spec = tmp_path / "spec.toml"
    spec.write_text("[subtree.hand]\nmass = 0.35\n")
    assert [r["link"] for r in ui703("--spec", str(spec))] == ["hand"]


def _anymal() -> Path | None:
    from support.corpus import example_robot_data_dir

    root = example_robot_data_dir()
    path = None if root is None else root / "robots" / "anymal_b_simple_description" \
        / "robots" / "anymal.urdf"
    return path if path is not None and path.exists() else None


#: ANYmal's published mass: "the 30 kg, 0.5 m tall robotic dog" (Hutter et al., "ANYmal -
#: A Highly Mobile and Dynamic Quadrupedal Robot", IROS 2016; docs/total-mass.md).
ANYMAL_KG = 30.0


def test_published_total_before_and_after(tmp_path):
    """example-robot-data's ANYmal B weighs 30.4754 kg as written, 1.58 % over the
    published 30 kg: check warns; fix --total-mass 30 --scale-kept writes links that
    weigh 30 kg, and check of the output is silent."""
    path = _anymal()
    if path is None:
        pytest.skip("example-robot-data not installed")
    (before,) = mismatches(urdfinertia.check(path, total_mass=ANYMAL_KG, statics=False))
    assert "weigh 30.4754 kg as written, 0.4754 kg (1.58%) over the target 30 kg" \
        in before.message
    assert "fix with the target refuses" in before.message  # every mass is kept
    out = tmp_path / "anymal.urdf"
    assert main(["fix", str(path), "-o", str(out), "-q", "--total-mass", "30",
                 "--scale-kept", "--package-dir",
                 f"example-robot-data={path.parents[3]}"]) == 0
    written = urdfinertia.check(out, total_mass=ANYMAL_KG, statics=False,
                                geometry=False)
    assert not mismatches(written)
    from urdfinertia.descriptions.formats import read_description
    from urdfinertia.plan.total_mass import written_masses

    robot, _ = read_description(out)
    assert sum(written_masses(robot).values()) == pytest.approx(ANYMAL_KG, rel=1e-9)
