"""Baselines: findings a repository has accepted for now, so only new ones fail CI.

A finding is known by (rule id, file, link), never by line or message: an edit elsewhere
in the file moves lines and changes the numbers in messages, and must not turn a known
finding into a new one. Files are stored relative to the baseline file's folder, so the
check may run from any directory. Keys are counted: a link with the same rule twice in the
baseline and three times now has one new finding.
"""

from __future__ import annotations

import json
import os
from collections import Counter
from collections.abc import Iterable
from dataclasses import dataclass
from pathlib import Path

from urdfinertia.analysis.check import Finding
from urdfinertia.atomic import atomic_write_bytes
from urdfinertia.errors import UrdfInertiaError

#: Bumped only if the key changes; older files are then refused with a clear message.
BASELINE_VERSION = 1

Key = tuple[str, str, str]  # (rule id, file relative to the baseline, link or "")


class BaselineError(UrdfInertiaError):
    """A baseline file that cannot be read or is not one."""


def file_key(path: Path, base_dir: Path) -> str:
    """``path`` as stored in a baseline in ``base_dir``: relative, POSIX separators."""
    absolute = Path(os.path.abspath(path))
    try:
        rel = os.path.relpath(absolute, os.path.abspath(base_dir))
    except ValueError:  # another drive on Windows
        return absolute.as_posix()
    return Path(rel).as_posix()


def finding_key(finding: Finding, path: Path, base_dir: Path) -> Key:
    return (finding.rule.id, file_key(path, base_dir), finding.link or "")


@dataclass
class Baseline:
    """The accepted findings of a baseline file in ``base_dir``."""

    base_dir: Path
    counts: Counter[Key]

    @classmethod
    def empty(cls, base_dir: Path) -> Baseline:
        return cls(base_dir, Counter())

    @classmethod
    def load(cls, path: Path) -> Baseline:
        try:
            doc = json.loads(Path(path).read_bytes())
        except OSError as exc:
            raise BaselineError(f"cannot read baseline: {exc.strerror or exc}",
                                file=path) from None
        except ValueError as exc:
            raise BaselineError(f"baseline is not JSON: {exc}", file=path) from None
        if not isinstance(doc, dict) or doc.get("version") != BASELINE_VERSION:
            raise BaselineError(f"not a version {BASELINE_VERSION} urdf-inertia baseline "
                                "(write one with check --write-baseline)", file=path)
        counts: Counter[Key] = Counter()
        for entry in doc.get("findings", []):
            try:
                counts[(str(entry["rule"]), str(entry["file"]), str(entry.get("link") or ""))] += 1
            except (KeyError, TypeError):
                raise BaselineError(f"baseline entry without rule/file: {entry!r}",
                                    file=path) from None
        return cls(Path(path).parent, counts)

    def mark(self, findings: list[Finding], path: Path) -> list[bool]:
        """Which of one file's findings are known (each baseline entry is used once)."""
        left = Counter(self.counts)
        known = []
        for f in findings:
            key = finding_key(f, path, self.base_dir)
            known.append(left[key] > 0)
            left[key] -= 1
        return known


def baseline_document(files: Iterable[tuple[Path, list[Finding]]], base_dir: Path) -> dict:
    """A baseline of every error and warning (info findings never fail a run)."""
    entries = []
    for path, findings in files:
        for f in findings:
            if f.severity == "info":
                continue
            rule, file, link = finding_key(f, path, base_dir)
            entries.append({"rule": rule, "code": f.code, "file": file, "link": link,
                            "severity": f.severity, "message": f.message})
    entries.sort(key=lambda e: (e["file"], e["link"], e["rule"]))
    return {"tool": "urdf-inertia", "version": BASELINE_VERSION, "findings": entries}


def write_baseline(path: Path, files: Iterable[tuple[Path, list[Finding]]]) -> int:
    """Write a baseline next to nothing but itself; returns the number of entries."""
    doc = baseline_document(files, Path(os.path.abspath(path)).parent)
    atomic_write_bytes(path, (json.dumps(doc, indent=2) + "\n").encode())
    return len(doc["findings"])
