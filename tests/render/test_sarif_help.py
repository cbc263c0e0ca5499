"""SARIF rule descriptors point at the rules page: ``helpUri`` is the section of the rule on
the documentation site, which the site build generates from the same registry."""

from __future__ import annotations

import importlib.util
import json
from pathlib import Path

import jsonschema
import yaml

from urdfinertia.cli import main
from urdfinertia.render.sarif import DOCS_URL, help_uri
from urdfinertia.rules import Rule

ROOT = Path(__file__).resolve().parents[2]
SCHEMA = json.loads((ROOT / "tests" / "data" / "sarif-schema-2.1.0.json").read_text())


def _rules_page() -> str:
    spec = importlib.util.spec_from_file_location("docs_hooks",
                                                  ROOT / "scripts" / "docs_hooks.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module.rules_markdown()


def test_the_docs_url_is_the_sites():
    config = yaml.load((ROOT / "mkdocs.yml").read_text(), Loader=yaml.BaseLoader)
    assert config["site_url"] == DOCS_URL and DOCS_URL.endswith("/")


def test_every_rule_has_a_help_uri_with_an_anchor_on_the_rules_page():
    page = _rules_page()
    for rule in Rule:
        uri = help_uri(rule.id)
        assert uri == f"{DOCS_URL}rules/#{rule.anchor}"
        assert f"{{#{rule.anchor}}}" in page, rule.id
    assert help_uri("UI999") is None


def test_sarif_descriptors_carry_the_help_uri(robots_dir, tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    code = main(["check", str(robots_dir / "nm7mar.urdf"), "--format", "sarif"])
    doc = json.loads(capsys.readouterr().out)
    assert code == 0
    jsonschema.Draft4Validator(SCHEMA).validate(doc)
    descriptors = doc["runs"][0]["tool"]["driver"]["rules"]
    by_id = {d["id"]: d for d in descriptors}
    results = doc["runs"][0]["results"]
    assert results and {r["ruleId"] for r in results} <= set(by_id)
    for result in results:
        descriptor = by_id[result["ruleId"]]
        assert descriptor["helpUri"] == DOCS_URL + "rules/#" + result["ruleId"].lower()
        assert descriptor["fullDescription"]["text"] == Rule.by_id(result["ruleId"]).meaning
