"""GitHub Actions workflow commands: one ``::error``/``::warning``/``::notice`` per finding.

https://docs.github.com/actions/reference/workflow-commands-for-github-actions: values
escape ``%``, CR and LF; property values also ``:`` and ``,``. Known (baseline) findings
are notices, so they stay visible without failing anything.
"""

from __future__ import annotations

from urdfinertia.analysis.locate import CheckedFile
from urdfinertia.render.sarif import display_path

_COMMANDS = {"error": "error", "warning": "warning", "info": "notice"}


def escape_data(text: str) -> str:
    return text.replace("%", "%25").replace("\r", "%0D").replace("\n", "%0A")


def escape_property(text: str) -> str:
    return escape_data(text).replace(":", "%3A").replace(",", "%2C")


def annotation_lines(files: list[CheckedFile], *, include_info: bool = False) -> list[str]:
    lines = []
    for cf in files:
        uri = display_path(cf.path)
        for finding, loc, known in zip(cf.findings, cf.locations, cf.known, strict=True):
            if finding.severity == "info" and not include_info:
                continue
            command = "notice" if known else _COMMANDS[finding.severity]
            title = f"{finding.rule.id} {finding.code}" + (" (known, in baseline)"
                                                           if known else "")
            props = ",".join(f"{k}={escape_property(v)}" for k, v in (
                ("file", uri), ("line", str(loc.line)), ("col", str(loc.column)),
                ("title", title)))
            where = f"link '{finding.link}': " if finding.link else ""
            lines.append(f"::{command} {props}::{escape_data(where + finding.message)}")
    return lines
