"""The report's words and numbers: the verdict in plain language, the per-link table.

Everything here reads a link's verdict through :class:`~urdfinertia.plan.results.
LinkResult`'s ``status``, ``changed``, ``action``, ``why`` and ``decision`` only, and ranks
links by what ``fix`` does with them: the links it changes first, then those it should
have changed and could not, then those it keeps, then the untouched. Numbers are rounded
to what they mean: four significant digits, and round-off (a component below 1e-9 of its
vector's largest, or a position under a picometre) shown as 0.
"""

from __future__ import annotations

import html
from collections.abc import Sequence
from typing import TYPE_CHECKING

import numpy as np

from urdfinertia.plan.results import Status

if TYPE_CHECKING:
    from urdfinertia.analysis.compare import LinkComparison
    from urdfinertia.findings import Finding
    from urdfinertia.plan.results import LinkResult
    from urdfinertia.render.report import LinkRow

#: Order of the statuses in the report: what fix changes first.
STATUS_ORDER = (Status.RECOMPUTED, Status.REPAIRED, Status.LEFT, Status.KEPT,
                Status.UNTOUCHED)
#: What each status means, in the report's words.
STATUS_WORDS = {
    Status.RECOMPUTED: "recomputed",
    Status.REPAIRED: "repaired",
    Status.LEFT: "left: could not compute",
    Status.KEPT: "kept as written",
    Status.UNTOUCHED: "untouched",
}
#: Relative size below which a vector's component is round-off (printed 0).
ROUND_OFF = 1e-9
#: Positions (m) below this are round-off whatever the vector: a picometre.
POSITION_FLOOR = 1e-12
#: A row's notes longer than this (characters), or more than NOTES_SHOWN of them, fold.
NOTES_CHARS = 160
NOTES_SHOWN = 2


def rank(result: LinkResult) -> int:
    """Where a link's verdict comes in the report (0: changed by fix, first)."""
    return STATUS_ORDER.index(result.status)


def ranked(rows: Sequence[LinkRow]) -> list[LinkRow]:
    """``rows`` in the report's order (stable within a status)."""
    return sorted(rows, key=lambda r: rank(r.fix))


def group(result: LinkResult) -> str:
    """The colour group of a verdict: "changed", "left", "kept" or "untouched"."""
    if result.changed:
        return "changed"
    return {Status.LEFT: "left", Status.KEPT: "kept"}.get(result.status, "untouched")


# --- numbers --------------------------------------------------------------------------
def num(x: float) -> str:
    """Four significant digits; -0 as 0."""
    x = float(x)
    return "0" if x == 0 else f"{x:.4g}"


def vec(v, floor: float = 0.0) -> str:  # noqa: ANN001 - any (3,) sequence of floats
    """Components to four digits, those below ``ROUND_OFF`` of the largest (or below
    ``floor``) as 0: ``-8.175e-20`` beside ``-0.175`` is round-off."""
    a = np.asarray(v, dtype=np.float64)
    if not np.all(np.isfinite(a)):
        return " ".join(num(x) if np.isfinite(x) else str(x) for x in a)
    cut = max(ROUND_OFF * float(np.max(np.abs(a), initial=0.0)), floor)
    return " ".join(num(0.0 if abs(x) < cut else x) for x in a)


def position(v) -> str:  # noqa: ANN001
    """A point in metres (see :func:`vec`; under a picometre is 0)."""
    return vec(v, POSITION_FLOOR)


def percent(x: float) -> str:
    """A fraction as a percentage to three digits: 0.4411 -> "44.1 %"."""
    return f"{100 * x:.3g} %"


# --- cells ----------------------------------------------------------------------------
def _pair(written: str, fixed: str) -> str:
    return (f'<span class="e">as written</span> {written}<br>'
            f'<span class="r">fix writes</span> {fixed}')


def mass_cells(row: LinkRow) -> list[str]:
    """Mass, CoM and principal moments: as written (even if invalid) over what fix writes
    ("kept" when fix keeps the written value)."""
    prev, r = row.fix.previous, row.recomputed
    if prev is None:
        written = ["no &lt;inertial&gt;"] * 3
    else:
        moments = (row.existing.principal()[0] if row.existing is not None else
                   getattr(row.comparison, "moments_a", None))
        written = [num(prev.mass), position(prev.origin.xyz),
                   vec(moments) if moments is not None else "-"]
        if row.existing is None:  # alarming only where fix acts on it (or cannot)
            style = "bad" if row.fix.changed or row.fix.status == Status.LEFT else "meta"
            written[0] += f' <span class="{style}">{html.escape(row.existing_note)}</span>'
    if r is None:
        fixed = ["kept" if prev is not None else "-"] * 3
        return [f'<span class="e">as written</span> {w}' if f == "kept" and prev is not None
                else _pair(w, f) for w, f in zip(written, fixed, strict=True)]
    fixed = [num(r.mass), position(r.com), vec(r.principal()[0])]
    return [_pair(w, f) for w, f in zip(written, fixed, strict=True)]


def verdict_cell(result: LinkResult) -> str:
    """What fix does with the link and why, in words."""
    status = html.escape(STATUS_WORDS.get(result.status, str(result.status)))
    parts = [f'<span class="v v-{group(result)}">{status}</span>']
    if result.why:
        parts.append(html.escape(result.why))
    if result.changed and (result.kept or result.derived):
        kept = f"kept {', '.join(result.kept)}; " if result.kept else ""
        parts.append(html.escape(f"{kept}derived {', '.join(result.derived)}"))
    if result.reason and result.status == Status.LEFT:
        parts.append(f'<span class="bad">{html.escape(result.reason)}</span>')
    return "<br>".join(parts)


def comparison_cell(c: LinkComparison | None) -> str:
    """The written inertial against the geometry, in words (compare's numbers)."""
    if c is None or c.verdict == "missing":
        return "-" if c is None else html.escape(c.note or "nothing to compare")
    parts = []
    if c.mass_ratio is not None and np.isfinite(c.mass_ratio):
        parts.append(f"mass ×{c.mass_ratio:.3g} of the geometry's" if c.mass_ratio != 1
                     else "same mass")
    if c.com_distance is not None and np.isfinite(c.com_distance):
        rel = (f" ({percent(c.com_distance_rel)} of the link's size)"
               if c.com_distance_rel is not None and np.isfinite(c.com_distance_rel) else "")
        parts.append(f"CoM {c.com_distance * 1000:.3g} mm away{rel}")
    if c.inertia_rel_error is not None and np.isfinite(c.inertia_rel_error):
        parts.append(f"tensor differs by {percent(c.inertia_rel_error)}")
    if c.axis_angle_deg is not None and np.isfinite(c.axis_angle_deg):
        parts.append(f"principal axes turned {c.axis_angle_deg:.2g}°")
    if c.note:
        parts.append(f"<i>{html.escape(c.note)}</i>")
    return "<br>".join(html.escape(p) if not p.startswith("<i>") else p for p in parts)


def finding_html(f: Finding, *, folded: bool = True) -> str:
    """A finding: severity, name and rule id; the message folded beneath."""
    severity = html.escape(str(f.severity))
    rule = getattr(getattr(f, "rule", None), "id", "")
    head = (f'<span class="s s-{severity}">{severity}</span> {html.escape(str(f.code))}'
            + (f" ({html.escape(str(rule))})" if rule else ""))
    message = html.escape(str(f.message))
    if not folded:
        return f"{head}: {message}"
    return f"<details><summary>{head}</summary>{message}</details>"


def geometry_cell(row: LinkRow) -> str:
    a = row.fix.assembly
    if a is None:
        return html.escape(row.fix.geometry)
    methods = sorted({p.part.method for p in a.parts})
    n = len(a.parts)
    return html.escape(f"{row.fix.geometry}: {n} part{'s' if n != 1 else ''} "
                       f"({', '.join(methods)})")


def notes(row: LinkRow) -> list[str]:
    """The row's notes: mass source, repairs and fallbacks, clipped boxes."""
    out = []
    if row.fix.assembly is not None:
        out.append(f"mass: {row.fix.assembly.mass_source}")
    from urdfinertia.render.decisions import note_text, verdict_notes

    out += [note_text(f) for f in verdict_notes(row.fix)]
    out += [f"{b.source} tensor breaks the triangle inequality: its box has a side "
            "clipped to 0" for b in row.boxes if b.clipped]
    return out


def notes_cell(row: LinkRow) -> str:
    """Short notes as they are; many or long ones folded under a count."""
    items = notes(row)
    if not items:
        return ""
    body = "<br>".join(html.escape(n) for n in items)
    if len(items) <= NOTES_SHOWN and sum(map(len, items)) <= NOTES_CHARS:
        return body
    return (f"<details><summary>{len(items)} notes (mass, repairs, fallbacks)</summary>"
            f"{body}</details>")


#: The table's columns: heading and share of the page width (percent), fixed so that the
#: table never scrolls sideways; long words and number lists wrap inside their cells.
COLUMNS = (
    ("link", 10), ("what fix does", 14), ("geometry used", 10), ("mass (kg)", 9),
    ("centre of mass (m, link frame)", 12), ("principal moments (kg m²)", 12),
    ("as written vs geometry", 13), ("check findings", 11), ("notes", 9),
)


def table_html(rows: Sequence[LinkRow]) -> str:
    """One row per link, in the report's order (what fix changes first)."""
    out = ['<table id="links"><colgroup>']
    out += [f'<col style="width:{w}%">' for _, w in COLUMNS]
    out.append("</colgroup><thead><tr>")
    out += [f"<th>{h}</th>" for h, _ in COLUMNS]
    out.append("</tr></thead><tbody>")
    labels = [html.escape(h, quote=True) for h, _ in COLUMNS]
    for row in ranked(rows):
        contents = [(html.escape(row.name), "name"), (verdict_cell(row.fix), ""),
                    (geometry_cell(row), "")]
        contents += [(c, "num") for c in mass_cells(row)]
        contents += [(comparison_cell(row.comparison), ""),
                     ("".join(finding_html(f) for f in row.findings), ""),
                     (notes_cell(row), "notes")]
        # data-label: the column's name, shown beside each cell when a narrow window
        # stacks a row into a card (the page's CSS)
        cells = [f'<td data-label="{label}"' + (f' class="{cls}"' if cls else "")
                 + f"><div>{content}</div></td>"
                 for label, (content, cls) in zip(labels, contents, strict=True)]
        out.append(f'<tr class="g-{group(row.fix)}">' + "".join(cells) + "</tr>")
    out.append("</tbody></table>")
    return "".join(out)
