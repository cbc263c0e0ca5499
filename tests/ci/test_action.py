"""The GitHub Action's check step: action.yml runs scripts/action_check.sh, so does this."""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

import jsonschema
import pytest

ROOT = Path(__file__).resolve().parents[2]
SCRIPT = ROOT / "scripts" / "action_check.sh"
DATA = ROOT / "tests" / "data"


def run_action(cwd: Path, **inputs: str) -> tuple[int, str, dict[str, str]]:
    env = dict(os.environ)
    env["PYTHONPATH"] = os.pathsep.join([str(ROOT / "src"), env.get("PYTHONPATH", "")])
    env["URDF_INERTIA"] = f"{sys.executable} -m urdfinertia"
    env["GITHUB_OUTPUT"] = str(cwd / "github_output.txt")
    for key, value in inputs.items():
        env[f"INPUT_{key.upper()}"] = value
    proc = subprocess.run(["bash", str(SCRIPT)], cwd=cwd, env=env, capture_output=True,
                          text=True, timeout=300)
    outputs = dict(line.split("=", 1) for line in
                   (cwd / "github_output.txt").read_text().splitlines()) if (
        cwd / "github_output.txt").exists() else {}
    return proc.returncode, proc.stdout, outputs


@pytest.fixture
def checkout(tmp_path):
    (tmp_path / "robots" / "arm").mkdir(parents=True)
    shutil.copy(DATA / "engines" / "tri.urdf", tmp_path / "robots" / "arm" / "tri.urdf")
    shutil.copy(DATA / "engines" / "fine.urdf", tmp_path / "robots" / "fine.urdf")
    (tmp_path / "robots" / "package.xml").write_text("<package><name>x</name></package>")
    return tmp_path


def test_action_annotates_writes_sarif_and_fails_on_new_findings(checkout):
    code, out, outputs = run_action(checkout, paths="robots", options="--no-geometry")
    assert code == 1
    assert outputs == {"sarif": "urdf-inertia.sarif", "exit-code": "1"}
    assert out.startswith("::error file=robots/arm/tri.urdf,line=")
    assert "package.xml" not in out  # found in the folder, not a description: skipped
    schema = json.loads((DATA / "sarif-schema-2.1.0.json").read_text())
    sarif = json.loads((checkout / "urdf-inertia.sarif").read_text())
    jsonschema.Draft4Validator(schema).validate(sarif)
    assert [r["ruleId"] for r in sarif["runs"][0]["results"]] == ["UI110"]


def test_action_with_a_baseline_passes_and_globs_expand(checkout):
    cmd = [sys.executable, "-m", "urdfinertia", "check", "robots/arm/tri.urdf",
           "--no-geometry", "--write-baseline", "baseline.json"]
    env = dict(os.environ, PYTHONPATH=str(ROOT / "src"))
    subprocess.run(cmd, cwd=checkout, env=env, check=True, capture_output=True)
    code, out, outputs = run_action(checkout, paths="robots/**/*.urdf",
                                    options="--no-geometry", baseline="baseline.json",
                                    sarif="x.sarif")
    assert code == 0 and outputs["exit-code"] == "0"
    assert out.startswith("::notice file=robots/arm/tri.urdf")
    assert "fine.urdf: 3 links, 0 error(s)" in out


def test_action_with_nothing_to_check_is_an_error(checkout):
    code, out, _ = run_action(checkout, paths="nowhere/*.urdf")
    assert code == 2 and out.startswith("::error")


def test_action_yml_runs_the_script():
    text = (ROOT / "action.yml").read_text()
    assert 'bash "${GITHUB_ACTION_PATH}/scripts/action_check.sh"' in text
    assert "github/codeql-action/upload-sarif" in text
