"""A finding: one rule of the registry ([`urdfinertia.rules`][urdfinertia.rules]) applied to
one place.

The one channel of everything the tool has to say about a description: what the reader read past,
what the judgement found, what `fix` did and why. Every note a user sees is a
[`Finding`][urdfinertia.findings.Finding] with its rule, so it has a stable id (SARIF `ruleId`,
baselines), a severity and a page in the documentation.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Any

from urdfinertia.rules import Rule, Severity

#: Severities, worst first (the strings JSON and SARIF carry).
SEVERITIES = tuple(s.value for s in Severity)


@dataclass(frozen=True)
class Finding:
    """One finding.

    Attributes
    ----------
    rule : Rule
        What kind of finding it is; its severity, scope and documentation come from it.
    link : str or None
        The link (body) it is about; None for the document as a whole.
    message : str
        What was found, with the numbers.
    line : int or None
        The line of the element it points at, where known.
    element : str or None
        The element of the link it is about ("collision[1] 'x'", "inertial",
        "joint 'j1' origin"), None for the link itself.
    """

    rule: Rule
    link: str | None
    message: str
    line: int | None = None
    element: str | None = None

    def __post_init__(self) -> None:
        object.__setattr__(self, "rule", Rule(self.rule))

    @property
    def code(self) -> str:
        """The rule's code ("placeholder-inertia")."""
        return self.rule.value

    @property
    def severity(self) -> Severity:
        """The rule's severity."""
        return self.rule.severity

    def describe(self, file: str | Path | None = None) -> str:
        """One line: `file:line: link 'name' element: message` (the errors' layout)."""
        where = str(file) if file is not None else "<input>"
        if self.line is not None:
            where += f":{self.line}"
        link = f" link '{self.link}'" if self.link else ""
        element = f" {self.element}" if self.element else ""
        return f"{where}:{link}{element}{':' if link or element else ''} {self.message}"


def finding_dict(f: Finding) -> dict[str, Any]:
    """A finding as JSON: its rule's code and id, severity, link, element, line, message."""
    return {"link": f.link, "severity": f.severity.value, "code": f.code, "rule": f.rule.id,
            "element": f.element, "message": f.message, "line": f.line}
