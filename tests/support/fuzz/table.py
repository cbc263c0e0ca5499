"""The figures of a fuzz run: runs per class and per format, for each command."""

from __future__ import annotations

from collections import Counter
from collections.abc import Sequence

from support.fuzz.cases import COMMANDS
from support.fuzz.classify import CLASSES, DEFECTS
from support.fuzz.drive import CaseResult
from support.fuzz.seeds import DESCRIPTION_FORMATS, MESH_FORMATS


def counts(results: Sequence[CaseResult]) -> Counter[tuple[str, str, str]]:
    """(command, class, format) -> runs."""
    found: Counter[tuple[str, str, str]] = Counter()
    for r in results:
        for o in r.outcomes:
            found[o.command, o.cls, r.case.fmt] += 1
    return found


def format_table(results: Sequence[CaseResult]) -> str:
    """One table per command: a row per class, a column per format, and a total."""
    found = counts(results)
    fmts = [f for f in (*DESCRIPTION_FORMATS, *MESH_FORMATS)
            if any(r.case.fmt == f for r in results)]
    cases = Counter(r.case.fmt for r in results)
    lines = []
    width = max(len(c) for c in CLASSES) + 2
    head = f"{'':<{width}}" + "".join(f"{f:>10}" for f in fmts) + f"{'total':>10}"
    for command in (*COMMANDS, "fix-strict"):
        if not any(k[0] == command for k in found):
            continue
        lines.append(f"{command} ({len(results)} cases)")
        lines.append(head)
        lines.append(f"{'cases':<{width}}" + "".join(f"{cases[f]:>10}" for f in fmts)
                     + f"{len(results):>10}")
        for cls in CLASSES:
            row = [found[command, cls, f] for f in fmts]
            lines.append(f"{cls:<{width}}" + "".join(f"{n:>10}" for n in row)
                         + f"{sum(row):>10}")
        lines.append("")
    known = known_counts(results)
    if known:
        lines.append("of the defects above, reproduced by strict xfails of code being "
                     "rewritten: " + ", ".join(f"{c} {tag} x{n}"
                                              for (c, tag), n in sorted(known.items())))
    lines.append(resources(results))
    return "\n".join(lines)


def resources(results: Sequence[CaseResult]) -> str:
    """The slowest run and the largest peak memory per format."""
    parts = []
    for fmt in (*DESCRIPTION_FORMATS, *MESH_FORMATS):
        runs = [o.run for r in results if r.case.fmt == fmt for o in r.outcomes]
        if runs:
            parts.append(f"{fmt}: max {max(x.seconds for x in runs):.1f} s, "
                         f"{max(x.max_rss_mb for x in runs):.0f} MB")
    return "slowest run and peak memory per format: " + "; ".join(parts)


def defect_lines(results: Sequence[CaseResult], known: bool = True) -> list[str]:
    """One line per defective run: the case, the command, the class and why (``known``:
    also those a strict xfail reproduces, marked so)."""
    return [f"{r.case.label} {o.command}: {o.cls}: "
            f"{f'(known: {o.known}) ' if o.known else ''}{o.detail}"
            for r in results for o in r.outcomes
            if o.cls in DEFECTS and (known or not o.known)]


def known_counts(results: Sequence[CaseResult]) -> Counter[tuple[str, str]]:
    """(command, known tag) -> defective runs a strict xfail reproduces."""
    return Counter((o.command, o.known) for r in results for o in r.outcomes
                   if o.cls in DEFECTS and o.known)
