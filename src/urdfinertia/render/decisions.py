"""What the policy decided, in words: per-link notes, the mass summary, check's plan table."""

from __future__ import annotations

from collections.abc import Sequence

from rich.console import Console
from rich.table import Table

from urdfinertia.findings import Finding, finding_dict
from urdfinertia.plan.results import Action, FixResult, LinkResult
from urdfinertia.plan.total_mass import mass_change
from urdfinertia.rules import Rule, Scope, Severity

#: Findings the fix table lists among a link's notes (what carrying the plan out found, and
#: the elements left out): the findings on the values as written are ``check``'s to list.
NOTE_RULES = frozenset({Rule.MESH_REPAIRED, Rule.DERIVED_FROM_IMPLAUSIBLE,
                        Rule.GEOMETRY_SPANS_FAR, Rule.MINIMAL_BODY, Rule.TENSOR_HOLDS_NOTHING,
                        Rule.TENSOR_LIFTED, Rule.MASS_TARGET_MET, Rule.READ_ONLY_BODY})


def note_text(f: Finding) -> str:
    """A finding as a note of the fix table: "collision[1] dropped (line 7): cause"."""
    if f.rule.scope == Scope.ELEMENT and f.severity != Severity.INFO and f.element:
        where = f" (line {f.line})" if f.line is not None else ""
        cause = f.message.removeprefix("dropped: ")
        return f"{f.element} dropped{where}: {cause}"
    return f.message


def link_notes(r: LinkResult, findings: bool = True) -> list[str]:
    """The decision, what was kept and derived, the mass source, the geometry choice and the
    error bar; then (unless ``findings`` is False) the findings that are notes of the
    verdict (:data:`NOTE_RULES`, elements dropped), each a finding with its rule."""
    notes = [r.decision] if r.decision else []
    if r.assembly is not None:
        if r.kept and r.derived:
            notes.append(f"kept {', '.join(r.kept)}; derived {', '.join(r.derived)}")
        notes.append(str(r.assembly.mass_source))
        if r.choice is not None and r.choice.others:  # a choice was made: which and why
            notes.append(f"from {r.choice}")
        if r.error_bar is not None:
            notes.append(str(r.error_bar))
    if findings:
        notes += [note_text(f) for f in verdict_notes(r)]
    return notes


def verdict_notes(r: LinkResult) -> list[Finding]:
    """The findings of ``r`` that the fix table shows as notes (:func:`link_notes`)."""
    return [f for f in r.findings if f.rule in NOTE_RULES or (
        f.rule.scope == Scope.ELEMENT and f.severity != Severity.INFO)]


def decision_dict(r: LinkResult) -> dict[str, object]:
    """JSON fields of one link's verdict: the decision and its grounds."""
    return {"action": r.action.value, "why": r.why, "grounds": [str(g) for g in r.grounds],
            "because": str(r.because) if r.because is not None else None,
            "because_rule": r.because.id if r.because is not None else None,
            "decision": r.decision, "kept": list(r.kept), "derived": list(r.derived),
            "error_bar": r.error_bar.as_dict() if r.error_bar is not None else None,
            "geometry_choice": r.choice.as_dict() if r.choice is not None else None,
            "findings": [finding_dict(f) for f in r.findings],
            "unverified": [f.message for f in r.unverified],
            "slip": r.slip.as_dict() if r.slip is not None else None}


def print_mass_summary(result: FixResult, console: Console, quiet: bool = False) -> None:
    """The robot's total mass before and after; with ``quiet`` only when it warns."""
    change = mass_change(result.links)
    if quiet and not change.warn and not result.targets:
        return
    for target in result.targets:  # asked for: the change is no surprise
        console.print(str(target), highlight=False)
    warn = change.warn and not result.targets
    if quiet and not warn:
        return
    style = "bold yellow" if warn else ""
    console.print(f"[{style}]warning: {change}[/]" if warn else change.text(), highlight=False)
    for f in result.robot_findings:
        if f.rule is Rule.MASS_PRIOR:
            console.print(f"mass prior: {f.message}", highlight=False, markup=False)


def _worth_listing(r: LinkResult) -> bool:
    """Not a plausible link kept as written with nothing to say about it."""
    return r.action not in (Action.KEEP, Action.LEAVE) or bool(r.unverified) or any(
        f.severity != Severity.INFO for f in r.findings)


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
    return [{"link": r.name, "action": r.action.value, "status": r.status.value,
             "why": r.why, "grounds": [str(g) for g in r.grounds],
             "because": str(r.because) if r.because is not None else None,
             "text": r.planned, "unverified": [f.message for f in r.unverified],
             "slip": r.slip.as_dict() if r.slip is not None else None} for r in verdicts]


def unverified_summary(verdicts: Sequence[LinkResult]) -> str | None:
    """One line for the links not verified ("not verified: 3 meshes unresolved in 2
    links"), or None when everything was read."""
    links = [r for r in verdicts if r.unverified]
    if not links:
        return None
    # one mesh may have two findings (unresolved, and its element dropped): count elements
    n = sum(len({f.element or f.message for f in r.unverified}) for r in links)
    return (f"not verified: {n} mesh{'es' if n != 1 else ''} unresolved or unreadable in "
            f"{len(links)} link{'s' if len(links) != 1 else ''}")


def problem_lines(result: FixResult) -> list[str]:
    """One line per thing read past (an element dropped, a value not read, the document
    read leniently, an include not followed), with its rule's id: what ``fix`` prints on
    stderr."""
    out = []
    seen: set[tuple[str | None, str | None]] = set()
    for f in result.findings:
        if f.severity == Severity.INFO or f.rule in (Rule.TOTAL_MASS_CHANGED,
                                                     Rule.CONVENTION_INFERRED):
            continue
        if f.rule.scope == Scope.JOINT:
            continue  # statics' concern: check says it
        if f.link is not None and f.rule.scope != Scope.ELEMENT:
            continue  # the link's verdict says it
        key = (f.link, f.element)
        if f.element and key in seen:
            continue  # one line per element: its first cause
        seen.add(key)
        done = ("read leniently" if f.rule in (Rule.VECTOR_COMMAS, Rule.XML_READ_LENIENTLY)
                else "value ignored" if f.rule == Rule.VALUE_UNREADABLE
                else "value not read" if f.element == "inertial"
                else "element dropped" if f.rule.scope == Scope.ELEMENT and f.link
                else None)
        said = f"{done}; " if done else ""
        out.append(f"{f.describe(result.path)} ({said}{f.rule.id} {f.code})")
    return out


def verdict_note_lines(result: FixResult) -> tuple[str, ...]:
    """Every link's note findings (:func:`verdict_notes`) as "link: note" lines."""
    return tuple(f"{r.name}: {note_text(f)}" for r in result.links for f in verdict_notes(r))
