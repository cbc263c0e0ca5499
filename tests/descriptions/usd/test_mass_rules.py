"""usd/mass.py: SimReady's mass rules on the authored MassAPI, each on the body that
breaks it and nowhere else (rules UI114-UI119 in link/findings.py)."""

from __future__ import annotations

import json
import subprocess
import sys

from descriptions.usd.assets import DATA

from urdfinertia.descriptions.formats import read_description

ASSET = DATA / "handmade" / "bad_mass.usda"
EXPECTED = {
    "negative": {"usd-negative-mass"},
    "negative_density": {"usd-negative-density"},  # not also "density without mass"
    "density_only": {"usd-density-without-mass"},
    "triangle": {"usd-diagonal-inertia-invalid"},
    "quaternion": {"usd-principal-axes-not-unit"},
    "newton": {"usd-newton-mass-disagrees"},
}


def test_each_rule_on_its_body_only():
    robot, _ = read_description(ASSET)
    found: dict[str, set[str]] = {}
    for f in robot.findings:
        found.setdefault(f.link, set()).add(f.code)
    assert found == EXPECTED  # "good" (a cube's tensor, turned 90 deg) has none


def test_check_reports_them_with_their_rule_ids_and_severities():
    done = subprocess.run([sys.executable, "-m", "urdfinertia", "check", str(ASSET),
                           "--format", "json"], capture_output=True, text=True)
    doc = json.loads(done.stdout)
    rows = doc["files"][0]["findings"]
    by_code = {f["code"]: f for f in rows if f["code"].startswith("usd-")}
    assert by_code["usd-negative-mass"]["severity"] == "error"
    assert by_code["usd-diagonal-inertia-invalid"]["severity"] == "error"
    assert by_code["usd-density-without-mass"]["severity"] == "warning"
    assert by_code["usd-negative-mass"]["rule"] == "UI114"
    assert done.returncode != 0
