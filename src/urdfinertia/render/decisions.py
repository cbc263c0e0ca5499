"""What the policy decided, in words: per-link notes, the mass summary, check's plan table."""

from __future__ import annotations

from collections.abc import Sequence

from rich.console import Console
from rich.table import Table

from urdfinertia.plan.apply import mass_change
from urdfinertia.plan.results import Action, FixResult, LinkResult


def link_notes(r: LinkResult, warnings: bool = True) -> list[str]:
    """The decision, what was kept and derived, the mass source and the error bar (and the
    link's warnings, unless ``warnings`` is False: the table collapses them itself)."""
    notes = [r.decision] if r.decision else []
    if r.assembly is not None:
        if r.kept and r.derived:
            notes.append(f"kept {', '.join(r.kept)}; derived {', '.join(r.derived)}")
        notes.append(str(r.assembly.mass_source))
        if r.choice is not None and r.choice.others:  # a choice was made: which and why
            notes.append(f"from {r.choice}")
        if r.error_bar is not None:
            notes.append(str(r.error_bar))
    return [*notes, *r.warnings] if warnings else notes


def decision_dict(r: LinkResult) -> dict[str, object]:
    """JSON fields of one link's verdict: the decision and its grounds."""
    from urdfinertia.render.results_json import finding_dict

    return {"action": str(r.action) if r.action else None, "why": r.why,
            "decision": r.decision, "kept": list(r.kept), "derived": list(r.derived),
            "error_bar": r.error_bar.as_dict() if r.error_bar is not None else None,
            "geometry_choice": r.choice.as_dict() if r.choice is not None else None,
            "findings": [finding_dict(f) for f in r.findings],
            "unverified": list(r.unverified),
            "slip": r.slip.as_dict() if r.slip is not None else None}


def print_mass_summary(result: FixResult, console: Console, quiet: bool = False) -> None:
    """The robot's total mass before and after; with ``quiet`` only when it warns."""
    change = mass_change(result)
    if quiet and not change.warn and not result.targets:
        return
    for target in result.targets:  # asked for: the change is no surprise
        console.print(str(target), highlight=False)
    warn = change.warn and not result.targets
    if quiet and not warn:
        return
    style = "bold yellow" if warn else ""
    console.print(f"[{style}]warning: {change}[/]" if warn else change.text(), highlight=False)


def _worth_listing(r: LinkResult) -> bool:
    """Not a plausible link kept as written with nothing to say about it."""
    return r.action not in (Action.KEEP, Action.LEAVE) or bool(r.unverified) or any(
        f.severity != "info" for f in r.findings)


def plan_table(verdicts: Sequence[LinkResult], title: str) -> Table | str:
    """What ``fix`` would do with each link it would change, or that has findings or was
    not verified; a count of the plausible links kept as written. One line instead of an
    empty table when every link would be kept as written."""
    quiet = sum(not _worth_listing(r) for r in verdicts)
    if quiet == len(verdicts):
        return f"{title}: all {quiet} link(s) would be kept as written"
    table = Table(title=title, caption=f"{quiet} other link(s) would be kept as written")
    for col in ("link", "fix would"):
        table.add_column(col, overflow="fold")
    for r in verdicts:
        if _worth_listing(r):
            table.add_row(r.name, r.planned)
    return table


def plan_dict(verdicts: Sequence[LinkResult]) -> list[dict[str, object]]:
    """JSON rows of check's plan: every link's action, resulting status and reason."""
    return [{"link": r.name, "action": str(r.action) if r.action else None,
             "status": str(r.status), "why": r.why, "text": r.planned,
             "unverified": list(r.unverified),
             "slip": r.slip.as_dict() if r.slip is not None else None} for r in verdicts]


def unverified_summary(verdicts: Sequence[LinkResult]) -> str | None:
    """One line for the links not verified ("not verified: 3 meshes unresolved in 2
    links"), or None when everything was read."""
    links = [r for r in verdicts if r.unverified]
    if not links:
        return None
    n = sum(len(r.unverified) for r in links)
    return (f"not verified: {n} mesh{'es' if n != 1 else ''} unresolved or unreadable in "
            f"{len(links)} link{'s' if len(links) != 1 else ''}")
