"""``check --format``, ``--sarif``, ``--baseline`` / ``--write-baseline``: SARIF validated
against the vendored SARIF 2.1.0 schema, GitHub annotations, baselines across edits."""

from __future__ import annotations

import json
import os
from pathlib import Path

import jsonschema
import pytest

from urdfinertia.cli import main
from urdfinertia.render.annotations import escape_data, escape_property
from urdfinertia.rules import Rule

SCHEMA = json.loads((Path(__file__).resolve().parents[1] / "data" /
                     "sarif-schema-2.1.0.json").read_text())
TRIANGLE = ('<inertial><mass value="1"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" '
            'iyz="0" izz="0.05"/></inertial>')
GOOD = ('<inertial><mass value="1"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" '
        'iyz="0" izz="0.01"/></inertial>')


def robot(links: dict[str, str], preamble: str = "") -> str:
    parts = ['<?xml version="1.0"?>', preamble, '<robot name="r">', '  <link name="base"/>']
    for name, body in links.items():
        parts.append(f'  <link name="{name}">\n    {body}\n  </link>')
        parts.append(f'  <joint name="j_{name}" type="continuous"><parent link="base"/>'
                     f'<child link="{name}"/><axis xyz="0 0 1"/></joint>')
    return "\n".join(p for p in parts if p) + "\n</robot>\n"


@pytest.fixture
def repo(tmp_path, monkeypatch):
    """A repository checkout: the working directory, with a robot in a subfolder."""
    monkeypatch.chdir(tmp_path)
    (tmp_path / "urdf").mkdir()
    return tmp_path


def run(capsys, *argv: str) -> tuple[int, str, str]:
    code = main(["check", *argv, "--no-geometry"])
    out = capsys.readouterr()
    return code, out.out, out.err


def test_sarif_is_valid_and_points_at_the_inertial(repo, capsys):
    Path("urdf/r.urdf").write_text(robot({"arm": TRIANGLE, "ok": GOOD}))
    code, out, _ = run(capsys, "urdf/r.urdf", "--format", "sarif")
    doc = json.loads(out)
    jsonschema.Draft4Validator(SCHEMA).validate(doc)
    assert code == 1
    (result,) = doc["runs"][0]["results"]
    assert result["ruleId"] == Rule.TRIANGLE_INEQUALITY.id
    assert result["level"] == "error"
    loc = result["locations"][0]["physicalLocation"]
    assert loc["artifactLocation"]["uri"] == "urdf/r.urdf"
    line = Path("urdf/r.urdf").read_text().splitlines()[loc["region"]["startLine"] - 1]
    assert line[loc["region"]["startColumn"] - 1:].startswith("<inertial>")
    rules = doc["runs"][0]["tool"]["driver"]["rules"]
    assert rules[result["ruleIndex"]]["id"] == result["ruleId"]
    assert "baselineState" not in result


def test_sarif_file_and_stdout_agree_and_json_keeps_working(repo, capsys):
    Path("urdf/r.urdf").write_text(robot({"arm": TRIANGLE}))
    code, out, err = run(capsys, "urdf/r.urdf", "--sarif", "out.sarif", "--json", "out.json",
                         "--format", "json")
    assert code == 1
    assert json.loads(out) == json.loads(Path("out.json").read_text())
    finding = json.loads(out)["files"][0]["findings"][0]
    assert finding["code"] == "triangle-inequality" and finding["known"] is False
    assert finding["rule"] == Rule.TRIANGLE_INEQUALITY.id and finding["line"] > 1
    jsonschema.Draft4Validator(SCHEMA).validate(json.loads(Path("out.sarif").read_text()))
    assert "1 error(s)" in err  # the summary stays off stdout


def test_github_annotations(repo, capsys):
    Path("urdf/r.urdf").write_text(robot({"arm": TRIANGLE, "bare": ""}))
    code, out, _ = run(capsys, "urdf/r.urdf", "--format", "github")
    assert code == 1
    lines = [ln for ln in out.splitlines() if ln.startswith("::")]
    assert len(lines) == 2
    text = Path("urdf/r.urdf").read_text().splitlines()
    for ln in lines:
        command, rest = ln[2:].split(" ", 1)
        props, message = rest.split("::", 1)
        fields = dict(p.split("=", 1) for p in props.split(","))
        assert command == "error" and fields["file"] == "urdf/r.urdf"
        row, col = int(fields["line"]), int(fields["col"])
        assert text[row - 1][col - 1] == "<"
        assert fields["title"].split(" ")[0] in {r.id for r in Rule}
        assert message.startswith("link '")


def test_annotation_escaping():
    assert escape_data("50% a\nb\r") == "50%25 a%0Ab%0D"
    assert escape_property("a:b,c") == "a%3Ab%2Cc"


def test_baseline_survives_unrelated_edits_and_new_findings_fail(repo, capsys):
    path = Path("urdf/r.urdf")
    path.write_text(robot({"arm": TRIANGLE, "ok": GOOD}))
    code, _, _ = run(capsys, str(path), "--write-baseline", "inertia-baseline.json")
    assert code == 0
    entries = json.loads(Path("inertia-baseline.json").read_text())["findings"]
    assert [(e["rule"], e["file"], e["link"]) for e in entries] == [
        (Rule.TRIANGLE_INEQUALITY.id, "urdf/r.urdf", "arm")]
    # an unrelated edit: lines inserted above, another link changed, numbers in the message
    # of the known finding changed too (izz 0.05 -> 0.06)
    path.write_text(robot({"extra": GOOD, "arm": TRIANGLE.replace("0.05", "0.06"),
                           "ok": GOOD.replace("0.01", "0.02")},
                          preamble="<!--\n moved\n down\n-->"))
    code, out, _ = run(capsys, str(path), "--baseline", "inertia-baseline.json",
                       "--format", "sarif")
    assert code == 0
    (result,) = json.loads(out)["runs"][0]["results"]
    assert result["baselineState"] == "unchanged"
    # a new finding fails the run; the known one stays known
    path.write_text(robot({"arm": TRIANGLE, "ok": TRIANGLE}))
    code, out, _ = run(capsys, str(path), "--baseline", "inertia-baseline.json",
                       "--format", "sarif")
    assert code == 1
    doc = json.loads(out)
    jsonschema.Draft4Validator(SCHEMA).validate(doc)
    states = {r["message"]["text"].split("'")[1]: r["baselineState"]
              for r in doc["runs"][0]["results"]}
    assert states == {"arm": "unchanged", "ok": "new"}


def test_baseline_works_from_another_directory(repo, capsys):
    Path("urdf/r.urdf").write_text(robot({"arm": TRIANGLE}))
    assert run(capsys, "urdf/r.urdf", "--write-baseline", "b.json")[0] == 0
    baseline = Path("b.json").read_bytes()
    os.chdir("urdf")
    code, out, _ = run(capsys, "r.urdf", "--baseline", "../b.json", "--format", "github")
    assert code == 0 and out.startswith("::notice ") and "triangle-inequality" in out
    code, out, _ = run(capsys, "r.urdf", "--format", "github")
    assert code == 1 and out.startswith("::error ") and "triangle-inequality" in out
    assert Path("../b.json").read_bytes() == baseline  # reading a baseline never rewrites it


def test_known_findings_are_notices_in_annotations(repo, capsys):
    Path("urdf/r.urdf").write_text(robot({"arm": TRIANGLE}))
    run(capsys, "urdf/r.urdf", "--write-baseline", "b.json")
    code, out, _ = run(capsys, "urdf/r.urdf", "--baseline", "b.json", "--format", "github")
    assert code == 0
    assert out.startswith("::notice ") and "known" in out.splitlines()[0]


def test_a_bad_baseline_is_a_one_line_error(repo, capsys):
    Path("urdf/r.urdf").write_text(robot({"arm": GOOD}))
    Path("b.json").write_text('{"findings": []}')
    code, out, err = run(capsys, "urdf/r.urdf", "--baseline", "b.json")
    assert code == 2 and "baseline" in err and len(err.strip().splitlines()) == 1
    assert err.startswith("urdf-inertia: error: ") and "b.json" in err
    assert out == "" and Path("b.json").read_text() == '{"findings": []}'


def test_skip_unknown_formats(repo, capsys):
    Path("package.xml").write_text('<?xml version="1.0"?><package><name>x</name></package>')
    Path("urdf/r.urdf").write_text(robot({"arm": GOOD}))
    code, out, _ = run(capsys, "package.xml", "urdf/r.urdf", "--skip-unknown-formats")
    assert code == 0 and "package.xml" not in out and "urdf/r.urdf" in out
    # named explicitly without the flag: an error naming the file and its root element
    code, out, err = run(capsys, "package.xml")
    assert code == 2 and out == ""
    (line,) = err.splitlines()
    assert line.startswith("urdf-inertia: error: package.xml:1: ") and "<package>" in line
