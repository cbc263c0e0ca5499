"""What the policy decided, in words: per-link notes, the mass summary, check's plan table."""

from __future__ import annotations

from collections import Counter
from collections.abc import Mapping

from rich.console import Console
from rich.table import Table

from urdfinertia.link.apply import mass_change
from urdfinertia.link.policy import Decision
from urdfinertia.link.results import FixResult, LinkResult


def link_notes(r: LinkResult, warnings: bool = True) -> list[str]:
    """The decision, what was kept and derived, the mass source and the error bar (and the
    link's warnings, unless ``warnings`` is False: the table collapses them itself)."""
    notes = [r.decision] if r.decision else []
    if r.assembly is not None:
        if r.kept and r.derived:
            notes.append(f"kept {', '.join(r.kept)}; derived {', '.join(r.derived)}")
        notes.append(str(r.assembly.mass_source))
        if r.error_bar is not None:
            notes.append(str(r.error_bar))
    return [*notes, *r.warnings] if warnings else notes


def decision_dict(r: LinkResult) -> dict[str, object]:
    """JSON fields of one link's decision."""
    return {"decision": r.decision, "kept": list(r.kept), "derived": list(r.derived),
            "error_bar": r.error_bar.as_dict() if r.error_bar is not None else None}


def print_mass_summary(result: FixResult, console: Console, quiet: bool = False) -> None:
    """The robot's total mass before and after; with ``quiet`` only when it warns."""
    change = mass_change(result)
    if quiet and not change.warn:
        return
    style = "bold yellow" if change.warn else ""
    console.print(f"[{style}]{'warning: ' if change.warn else ''}{change}[/]" if style
                  else str(change), highlight=False)


def plan_table(plan: Mapping[str, Decision], title: str) -> Table:
    """Links ``fix`` would not keep as they are, with why; a count of the kept ones."""
    counts = Counter(d.action for d in plan.values())
    table = Table(title=title, caption=f"{counts['keep']} link(s) would be kept as written")
    for col in ("link", "fix would"):
        table.add_column(col, overflow="fold")
    for d in plan.values():
        if d.action != "keep":
            table.add_row(d.link, d.describe(done=False))
    return table


def plan_dict(plan: Mapping[str, Decision]) -> list[dict[str, object]]:
    return [{"link": d.link, "action": d.action, "why": d.why,
             "text": d.describe(done=False)} for d in plan.values()]
