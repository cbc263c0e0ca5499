"""Slips on a link, end to end: ``check`` proposes the edit in words, ``fix`` applies it and
keeps every other byte, ``--no-slips`` turns it off, and every command agrees.

Fixture ``one_slip_each.urdf``: the same CAD-like inertial of a turned box, once clean and
once with one slip of each class made in it (``tests/inertia/test_slips.py`` builds the
same values)."""

from __future__ import annotations

import json
import re
from pathlib import Path

import jsonschema
import numpy as np
import pytest

import urdfinertia
from urdfinertia.analysis.check import check_description
from urdfinertia.body.options import FixOptions
from urdfinertia.cache.library import MeshLibrary
from urdfinertia.cli import main
from urdfinertia.descriptions.formats import read_description, robot_from_bytes
from urdfinertia.descriptions.inertial import RawInertial
from urdfinertia.plan.edits import slip_text_edit
from urdfinertia.plan.fix import fix_robot
from urdfinertia.plan.results import Action, Status

DATA = Path(__file__).resolve().parents[1] / "data" / "slips"
EACH = DATA / "one_slip_each.urdf"
#: link -> the edit that undoes its slip (parallel_axis is valid and plausible as slipped:
#: check does not flag it, so nothing is searched)
EXPECTED = {"entry_power": "izz x1e-3", "mass_grams": "mass x1e-3",
            "tensor_mm2": "tensor x1e-6", "inertial_grams": "mass and tensor x1e-3",
            "com_mm": "com x1e-3", "products_sign": "products negated",
            "order": "entries diagonal-first"}


@pytest.fixture(scope="module")
def fixed():
    robot, data = read_description(EACH)
    return fix_robot(robot, data, FixOptions(), MeshLibrary())


def test_each_slip_is_undone_to_the_cad_values(fixed):
    clean = RawInertial.from_inertial(fixed.robot.link("clean").inertial)
    for name, edit in EXPECTED.items():
        r = fixed.link(name)
        assert r.action == Action.CORRECT and r.status == Status.REPAIRED, name
        assert r.slip is not None and r.slip.edit == edit, (name, r.slip)
        assert r.decision.startswith(f"corrected: {edit} (slip: "), r.decision
        after = r.after
        assert after is not None and after.is_physical()
        assert after.mass == clean.mass
        np.testing.assert_array_equal(after.com, clean.com)
        np.testing.assert_allclose(after.inertia, clean.inertia, rtol=1e-12, atol=1e-15)
    assert fixed.link("clean").action == Action.KEEP
    assert fixed.link("parallel_axis").action == Action.KEEP


def test_fix_keeps_every_other_byte(fixed):
    # the output read back: each corrected link now holds the clean link's numbers
    back = robot_from_bytes(fixed.output, EACH)
    clean = back.link("clean").inertial
    for name in EXPECTED:
        i = back.link(name).inertial
        assert (i.mass, i.origin.xyz, i.ixx, i.ixy, i.ixz, i.iyy, i.iyz, i.izz) == (
            clean.mass, clean.origin.xyz, clean.ixx, clean.ixy, clean.ixz, clean.iyy,
            clean.iyz, clean.izz), name
    # only the slipped values' text changed: the lines of the inputs that differ are the
    # slipped ones, and within them only attribute values
    before = EACH.read_bytes().decode().splitlines()
    after = fixed.output.decode().splitlines()
    assert len(before) == len(after)
    changed = [(a, b) for a, b in zip(before, after, strict=True) if a != b]
    assert len(changed) == len(EXPECTED) + 1  # inertial_grams: <mass> and <inertia>
    for a, b in changed:
        assert re.sub(r'"[^"]*"', '""', a) == re.sub(r'"[^"]*"', '""', b)


def test_the_izz_slip_changes_one_attribute_value():
    data = (DATA / "izz_slip.urdf").read_bytes()
    result = urdfinertia.fix(DATA / "izz_slip.urdf")
    assert result.link("arm").slip is not None
    assert result.output == data.replace(b'izz="1.05"', b'izz="0.00105"')
    edit = slip_text_edit(data, result.output)
    assert edit is not None and edit.text == "0.00105"
    line = data.decode().splitlines()[edit.start_line - 1]
    assert line[edit.start_column - 1:edit.end_column - 1] == "1.05"


def test_no_slips_derives_from_the_geometry_as_before():
    result = urdfinertia.fix(EACH, slips=False)
    for name in EXPECTED:
        r = result.link(name)
        assert r.slip is None and r.action != Action.CORRECT
        assert not any(f.code == "slip-proposed" for f in r.findings)


def test_check_says_it_in_words_and_plans_what_fix_does(fixed):
    checked = check_description(read_description(EACH)[0], meshes=MeshLibrary())
    assert [(r.name, r.action, r.why) for r in checked.links] == [
        (r.name, r.action, r.why) for r in fixed.links]
    words = {f.link: f.message for f in checked.findings if f.code == "slip-proposed"}
    assert set(words) == set(EXPECTED)
    assert words["entry_power"].startswith("izz looks 1000x too large: izz x1e-3 (")
    assert "within" in words["entry_power"] and "of the geometry's" in words["entry_power"]
    assert all(f.rule.id == "UI601" for f in checked.findings if f.code == "slip-proposed")


def test_check_on_the_output_finds_nothing_to_correct(fixed):
    after = check_description(robot_from_bytes(fixed.output, EACH),
                              meshes=MeshLibrary())
    assert after.would_change == ()
    assert not any(f.code == "slip-proposed" for f in after.findings)


def test_json_and_sarif_carry_the_proposal(tmp_path):
    js, sarif = tmp_path / "c.json", tmp_path / "c.sarif"
    code = main(["check", str(DATA / "izz_slip.urdf"), "--json", str(js), "--sarif",
                 str(sarif), "-q"])
    assert code == 1  # the triangle inequality is an error as written
    plan = json.loads(js.read_text())["files"][0]["fix_plan"]
    slip = next(p["slip"] for p in plan if p["link"] == "arm")
    assert slip["edit"] == "izz x1e-3" and slip["slip"] == "entry-power"
    assert slip["runner_up"]["edit"] == "izz x1e-2" and slip["margin"] >= 9
    assert slip["score"] < slip["runner_up"]["score"]
    doc = json.loads(sarif.read_text())
    schema = json.loads((DATA.parent / "sarif-schema-2.1.0.json").read_text())
    jsonschema.validate(doc, schema)
    result = next(r for r in doc["runs"][0]["results"] if r["ruleId"] == "UI601")
    change = result["fixes"][0]["artifactChanges"][0]
    rep = change["replacements"][0]
    assert rep["insertedContent"]["text"] == "0.00105"
    assert rep["deletedRegion"]["startLine"] == rep["deletedRegion"]["endLine"] == 18
    # --no-slips: no proposal, no fix object
    main(["check", str(DATA / "izz_slip.urdf"), "--sarif", str(sarif), "-q", "--no-slips"])
    assert not any(r["ruleId"] == "UI601" or "fixes" in r
                   for r in json.loads(sarif.read_text())["runs"][0]["results"])


def test_fix_json_has_the_slip(tmp_path):
    out, js = tmp_path / "out.urdf", tmp_path / "fix.json"
    assert main(["fix", str(DATA / "izz_slip.urdf"), "-o", str(out), "--json", str(js),
                 "-q"]) == 0
    arm = next(x for x in json.loads(js.read_text())["links"] if x["link"] == "arm")
    assert arm["action"] == "correct" and arm["slip"]["edit"] == "izz x1e-3"
    assert arm["kept"] == ["mass", "com"] and arm["derived"] == ["tensor"]
    assert main(["fix", str(DATA / "izz_slip.urdf"), "-o", str(out), "--no-slips",
                 "-q"]) == 0
    assert b'izz="0.00105"' not in out.read_bytes()


@pytest.mark.corpus
def test_slips_planted_into_a_real_robot_are_undone_or_left():
    """example-robot-data's Panda: into each link's CAD inertial one slip of three classes
    is planted; the search gives back the CAD values or proposes nothing, never another
    edit (scripts/bench_slips.py measures this over the whole corpus)."""
    import dataclasses

    from support.corpus import example_robot_data_dir

    from urdfinertia.inertia.slips import decimal_shift
    from urdfinertia.plan.fix import verdicts

    erd = example_robot_data_dir()
    path = None if erd is None else erd / "robots/panda_description/urdf/panda.urdf"
    if path is None or not path.is_file():
        pytest.skip("example-robot-data is not installed")
    robot, _ = read_description(path)
    meshes = MeshLibrary()
    clean = {r.name: r for r in verdicts(robot, FixOptions(), meshes).links}
    right = tried = 0
    for k, link in enumerate(robot.links):
        i = link.inertial
        if i is None or not link.collisions or clean[link.name].why != "plausible":
            continue
        for slipped in (dataclasses.replace(i, mass=decimal_shift(i.mass, 3)[0]),
                        dataclasses.replace(i, izz=decimal_shift(i.izz, 3)[0]),
                        dataclasses.replace(i, **{k: decimal_shift(getattr(i, k), 6)[0]
                                                  for k in ("ixx", "ixy", "ixz", "iyy",
                                                            "iyz", "izz")})):
            links = list(robot.links)
            links[k] = dataclasses.replace(link, inertial=slipped)
            planted = dataclasses.replace(robot, links=tuple(links))
            d = next(r for r in verdicts(planted, FixOptions(), meshes).links
                     if r.name == link.name)
            tried += 1
            if d.slip is None:
                continue
            truth = RawInertial.from_inertial(i)
            assert d.slip.after.mass == truth.mass, (link.name, d.slip.edit)
            np.testing.assert_allclose(d.slip.after.inertia, truth.inertia, rtol=1e-12)
            right += 1
    assert tried >= 15 and right >= tried // 2, (right, tried)
