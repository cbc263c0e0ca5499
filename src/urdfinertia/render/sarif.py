"""SARIF 2.1.0 for code scanning (GitHub, GitLab, VS Code's SARIF viewer).

One run, one result per finding: ``ruleId`` from :data:`analysis.check.RULES` (stable),
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
from urdfinertia import rules as registry
from urdfinertia.analysis.check import RULES, Rule
from urdfinertia.analysis.locate import CheckedFile
from urdfinertia.link.slips import TextEdit

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


def help_uri(rule_id: str) -> str | None:
    """The rules page's section of the rule ``rule_id`` ("UI111"); None for an id the
    registry does not know."""
    try:
        return f"{DOCS_URL}rules/#{registry.Rule.by_id(rule_id).anchor}"
    except KeyError:
        return None


def _rule_json(rule: Rule) -> dict:
    descriptor = {"id": rule.id, "name": rule.code,
                  "shortDescription": {"text": rule.summary},
                  "defaultConfiguration": {"level": LEVELS[rule.severity]},
                  "properties": {"element": rule.element}}
    uri = help_uri(rule.id)
    if uri is not None:
        descriptor["helpUri"] = uri
        descriptor["fullDescription"] = {"text": registry.Rule.by_id(rule.id).meaning}
    return descriptor


def sarif_document(files: list[CheckedFile], *, with_baseline: bool = False,
                   include_info: bool = False) -> dict:
    """The SARIF log of a check run over ``files``."""
    rules = list(RULES.values())
    extra = sorted({f.rule.id for cf in files for f in cf.findings} - {r.id for r in rules})
    index = {r.id: i for i, r in enumerate(rules)}
    for rid in extra:  # unregistered codes still get a descriptor (see rule_of)
        index[rid] = len(rules)
        rules.append(Rule(rid, rid, "link", "warning", rid))
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
            edit = cf.fixes.get(finding.link or "") if finding.code == "slip-proposed" \
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
