"""The rule registry (:mod:`urdfinertia.rules`): one row per code, stable ids, docs."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from urdfinertia.rules import FixAction, Rule, Scope, Severity

IDS = json.loads((Path(__file__).parent / "data" / "rule_ids.json").read_text())


def test_ids_never_change() -> None:
    """Every id recorded once keeps its code (baselines and code-scanning alerts use it)."""
    for code, rule_id in IDS.items():
        assert Rule(code).id == rule_id


def test_ids_are_unique_and_well_formed() -> None:
    ids = [r.id for r in Rule]
    assert len(set(ids)) == len(ids)
    assert all(len(i) == 5 and i.startswith("UI") and i[2:].isdigit() for i in ids)


@pytest.mark.parametrize("rule", list(Rule), ids=lambda r: r.id)
def test_every_rule_is_documented(rule: Rule) -> None:
    assert isinstance(rule.severity, Severity) and isinstance(rule.scope, Scope)
    assert isinstance(rule.fix, FixAction)
    assert rule.summary and rule.meaning and rule.example and rule.silence
    assert Rule.by_id(rule.id) is rule


def test_rules_are_strings() -> None:
    """A code compares equal to its text: JSON, SARIF and baselines keep the strings."""
    assert Rule.PLACEHOLDER_INERTIA == "placeholder-inertia"
    assert json.dumps(Rule.TRIANGLE_INEQUALITY) == '"triangle-inequality"'


def test_every_rule_is_recorded() -> None:
    """A new rule's id is recorded in tests/data/rule_ids.json, from then on fixed."""
    assert set(IDS) == {r.value for r in Rule}
