"""Rule ids: one per finding code, unique, never renumbered."""

from __future__ import annotations

import ast
import json
from pathlib import Path

import urdfinertia.analysis.check as check_module
from urdfinertia.analysis.check import RULES, SEVERITIES, rule_of

SRC = Path(check_module.__file__).resolve().parents[1]
SNAPSHOT = Path(__file__).resolve().parents[1] / "data" / "rule_ids.json"


def emitted_codes() -> set[str]:
    """Every literal code passed to ``Finding(link, severity, code, ...)`` in the package."""
    codes = set()
    for path in SRC.rglob("*.py"):
        for node in ast.walk(ast.parse(path.read_text())):
            if (isinstance(node, ast.Call) and getattr(node.func, "id", None) == "Finding"
                    and len(node.args) >= 3 and isinstance(node.args[2], ast.Constant)):
                codes.add(node.args[2].value)
    return codes


def test_every_emitted_code_has_a_rule():
    codes = emitted_codes()
    assert len(codes) > 20  # the scan sees the checks and the engines
    assert codes - set(RULES) == set()
    # the reader's problems become findings through a table, not a literal call
    assert {code for _, code in check_module._PROBLEM_FINDINGS.values()} <= set(RULES)


def test_rule_ids_are_unique_and_well_formed():
    ids = [r.id for r in RULES.values()]
    assert len(ids) == len(set(ids))
    for code, rule in RULES.items():
        assert rule.code == code
        assert rule.severity in SEVERITIES
        assert rule.element in ("inertial", "link", "robot")


def test_rule_ids_never_change():
    """Baselines and code-scanning alerts are keyed on these ids: a change here is a
    breaking change (add new codes with new ids, and add them to the snapshot)."""
    recorded = json.loads(SNAPSHOT.read_text())
    current = {code: rule.id for code, rule in RULES.items()}
    assert {c: current.get(c) for c in recorded} == recorded
    assert set(current) <= set(recorded), "a new rule is missing from the snapshot"


def test_an_unregistered_code_still_renders():
    assert rule_of("no-such-code").id == "no-such-code"
