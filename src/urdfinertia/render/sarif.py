"""SARIF 2.1.0 for code scanning (GitHub, GitLab, VS Code's SARIF viewer).

One run, one result per finding: ``ruleId`` from the rule registry (:mod:`urdfinertia.rules`),
the start tag of the offending element as region, the link as logical location, and with
a baseline ``baselineState`` ("unchanged" for known findings, "new" otherwise). The
``partialFingerprints`` use the baseline's key (rule, file, link), so code scanning also
tracks an alert across edits that move it.
"""

from __future__ import annotations

import hashlib
import os
from pathlib import Path

from urdfinertia import __version__
from urdfinertia.analysis.locate import CheckedFile
from urdfinertia.plan.edits import TextEdit
from urdfinertia.rules import Rule

SARIF_SCHEMA = ("https://docs.oasis-open.org/sarif/sarif/v2.1.0/errata01/os/schemas/"
                "sarif-schema-2.1.0.json")
#: The documentation site (mkdocs.yml's ``site_url``): each rule's ``helpUri`` is its section
#: of the rules page there, ``{DOCS_URL}rules/#ui111``.
DOCS_URL = "https://OWNER.github.io/urdfinertia/"
#: our severities -> SARIF levels
LEVELS = {"error": "error", "warning": "warning", "info": "note"}


def display_path(path: Path) -> str:
    """Relative to the working directory when inside it (code scanning and annotations
    resolve it against the checkout), else absolute; POSIX separators."""
    absolute = Path(os.path.abspath(path))
    try:
        return absolute.relative_to(Path.cwd()).as_posix()
    except ValueError:
        return absolute.as_posix()


def artifact_uri(path: Path) -> str:
    """:func:`display_path`, as a file URI when it is absolute."""
    shown = display_path(path)
    return Path(shown).as_uri() if Path(shown).is_absolute() else shown


def help_uri(rule: Rule | str) -> str | None:
    """The rules page's section of ``rule``, a rule or its id (``{DOCS_URL}rules/#ui111``;
    None for an id no rule has)."""
    if not isinstance(rule, Rule):
        try:
            rule = Rule.by_id(rule)
        except (KeyError, ValueError):
            return None
    return f"{DOCS_URL}rules/#{rule.anchor}"


def _rule_json(rule: Rule) -> dict:
    descriptor = {"id": rule.id, "name": rule.value,
                  "shortDescription": {"text": rule.summary},
                  "fullDescription": {"text": rule.meaning},
                  "helpUri": help_uri(rule),
                  "defaultConfiguration": {"level": LEVELS[rule.severity]},
                  "properties": {"scope": rule.scope.value, "fix": rule.fix.value}}
    return descriptor


def sarif_document(files: list[CheckedFile], *, with_baseline: bool = False,
                   include_info: bool = False) -> dict:
    """The SARIF log of a check run over ``files``."""
    rules = list(Rule)
    index = {r.id: i for i, r in enumerate(rules)}
    results = []
    for cf in files:
        uri = artifact_uri(cf.path)
        for finding, loc, known in zip(cf.findings, cf.locations, cf.known, strict=True):
            if finding.severity == "info" and not include_info:
                continue
            rule = finding.rule
            result = {
                "ruleId": rule.id, "ruleIndex": index[rule.id],
                "level": LEVELS[finding.severity],
                "message": {"text": (f"link '{finding.link}': " if finding.link else "")
                            + finding.message},
                "locations": [{
                    "physicalLocation": {
                        "artifactLocation": {"uri": uri},
                        "region": {"startLine": loc.line, "startColumn": loc.column},
                    },
                    "logicalLocations": ([{"name": finding.link, "kind": "member"}]
                                         if finding.link else []),
                }],
                "partialFingerprints": {"urdfInertiaKey/v1": _fingerprint(
                    rule.id, uri, finding.link)},
            }
            edit = cf.fixes.get(finding.link or "") if finding.rule == Rule.SLIP_PROPOSED \
                else None
            if edit is not None:  # the slip undone, as fix writes it
                result["fixes"] = [_fix_json(uri, edit, cf.decision_of(finding.link))]
            decision = cf.decision_of(finding.link)
            if decision is not None:  # what fix would do, as every command says it
                result["properties"] = {"fix": decision}
            if with_baseline:
                result["baselineState"] = "unchanged" if known else "new"
            results.append(result)
    return {
        "$schema": SARIF_SCHEMA,
        "version": "2.1.0",
        "runs": [{
            "tool": {"driver": {"name": "urdf-inertia", "version": __version__,
                                "rules": [_rule_json(r) for r in rules]}},
            "columnKind": "unicodeCodePoints",
            "results": results,
        }],
    }


def _fix_json(uri: str, edit: TextEdit, decision: str | None) -> dict:
    """A SARIF ``fix``: one artifactChange replacing the slipped text with fix's."""
    return {"description": {"text": decision or "undo the slip"},
            "artifactChanges": [{
                "artifactLocation": {"uri": uri},
                "replacements": [{
                    "deletedRegion": {"startLine": edit.start_line,
                                      "startColumn": edit.start_column,
                                      "endLine": edit.end_line,
                                      "endColumn": edit.end_column},
                    "insertedContent": {"text": edit.text}}]}]}


def _fingerprint(rule_id: str, uri: str, link: str | None) -> str:
    return hashlib.sha256(f"{rule_id}\0{uri}\0{link or ''}".encode()).hexdigest()[:32]
