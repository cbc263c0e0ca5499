"""``check --engines``: hand-made robots that each engine refuses, blows up on, or runs
calmly (tests/data/engines, each file says why in its first comment)."""

from __future__ import annotations

from pathlib import Path

import pytest

from urdfinertia.cli import main
from urdfinertia.descriptions.formats import read_description
from urdfinertia.engines.run import EngineCheck, Outcome, installed, outcome_findings

DATA = Path(__file__).resolve().parents[1] / "data" / "engines"


def engine(name: str, *more):
    return pytest.param(name, *more, marks=pytest.mark.skipif(
        not installed(name), reason=f"{name} not installed"))


ALL = [engine("mujoco"), engine("pinocchio"), engine("pybullet")]


def findings(name: str, file: str):
    path = DATA / file
    robot, _ = read_description(path)
    return EngineCheck((name,), seconds=2.0, timeout=120).findings(path, robot)


def codes(found) -> set[tuple[str | None, str]]:
    return {(f.link, f.code) for f in found}


@pytest.mark.parametrize("name", ALL)
def test_fine_robot_loads_and_stays_calm(name):
    assert findings(name, "fine.urdf") == []


@pytest.mark.parametrize("name", ALL)
def test_stiff_robot_runs_away(name):
    found = findings(name, "stiff.urdf")
    assert codes(found) == {("bob", "engine-runaway")}
    assert "hinge" in found[0].message


@pytest.mark.parametrize("name, file, link", [
    engine("mujoco", "tri.urdf", "arm"),
    engine("pinocchio", "nolimit.urdf", None),
    engine("pybullet", "nolimit.urdf", None),
])
def test_refusal_quotes_the_engine(name, file, link):
    found = findings(name, file)
    assert [(f.link, f.code, f.severity) for f in found] == [(link, "engine-refused", "error")]
    quote = {"mujoco": "A + B >= C", "pinocchio": "does not specify limits",
             "pybullet": "does not specify limits"}[name]
    assert quote in found[0].message
    assert "engine_copy" not in found[0].message  # names the user's file, not the copy


@pytest.mark.skipif(not installed("pybullet"), reason="pybullet not installed")
def test_a_crashing_engine_is_a_finding_not_a_crash():
    # PyBullet 3.2.7 segfaults on a second root link; a later version may refuse it instead
    found = findings("pybullet", "tworoots.urdf")
    assert [f.code for f in found] in (["engine-crashed"], ["engine-refused"])


@pytest.mark.skipif(not installed("pybullet"), reason="pybullet not installed")
def test_pybullet_silent_defaults_and_zeroed_tensor():
    found = findings("pybullet", "tri.urdf")
    (changed,) = [f for f in found if f.code == "engine-changes-inertial"]
    assert changed.link == "arm" and "(0, 0, 0)" in changed.message
    text = (DATA / "fine.urdf").read_text()
    bare = text.replace(text[text.index("<inertial><mass value=\"0.5\""):
                             text.index("</inertial>", text.index("0.5")) + 11], "")
    path = Path(__file__).parent / "_bare.urdf"
    try:
        path.write_text(bare)
        robot, _ = read_description(path)
        got = EngineCheck(("pybullet",)).findings(path, robot)
    finally:
        path.unlink()
    assert ("nomass", "engine-default-inertial") in codes(got)
    assert "1 kg" in next(f.message for f in got if f.code == "engine-default-inertial")


@pytest.mark.skipif(not installed("mujoco"), reason="mujoco not installed")
def test_mujoco_compiler_options_that_change_inertials(tmp_path):
    text = (DATA / "tri.urdf").read_text().replace(
        "</robot>", '<mujoco><compiler balanceinertia="true" boundmass="2"/></mujoco>\n</robot>')
    path = tmp_path / "balanced.urdf"
    path.write_text(text)
    robot, _ = read_description(path)
    found = EngineCheck(("mujoco",)).findings(path, robot)
    messages = [f.message for f in found if f.code == "engine-changes-inertial"]
    assert any("balanceinertia" in m for m in messages)
    assert sum("boundmass=2" in m for m in messages) == 2  # arm 1 kg, nomass 0.5 kg
    assert not any(f.code == "engine-refused" for f in found)  # MuJoCo balanced it


def test_a_missing_engine_is_a_note_with_the_install_command():
    robot, _ = read_description(DATA / "fine.urdf")
    (note,) = outcome_findings(Outcome("pinocchio", missing=True), robot, b"", DATA)
    assert note.severity == "info" and "pip install pin" in note.message


def test_check_cli_exit_codes(capsys):
    if not installed("mujoco"):
        pytest.skip("mujoco not installed")
    fine, tri = str(DATA / "fine.urdf"), str(DATA / "tri.urdf")
    assert main(["check", fine, "--no-geometry", "--engines", "mujoco", "-q"]) == 0
    assert main(["check", tri, "--no-geometry", "--engines", "mujoco", "--format",
                 "github"]) == 1
    assert "engine-refused" in capsys.readouterr().out


@pytest.mark.skipif(not installed("mujoco"), reason="mujoco not installed")
def test_fix_engines_reports_no_regression(tmp_path, capsys):
    out = tmp_path / "fixed.urdf"
    code = main(["fix", str(DATA / "tri.urdf"), "-o", str(out), "-q", "--engines", "mujoco"])
    err = capsys.readouterr().err
    assert code == 0
    assert "mujoco: input refused, output stable" in err
