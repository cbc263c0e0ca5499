"""Terminal tables (rich) for per-link results."""

from __future__ import annotations

from collections.abc import Iterable, Sequence

import numpy as np
from rich.console import Console
from rich.table import Table

from urdfinertia.analysis.explain import Breakdown, Contribution, link_breakdown
from urdfinertia.body.geometry_choice import KIND_WORDS
from urdfinertia.plan.results import LinkResult
from urdfinertia.render.decisions import link_notes, note_text, verdict_notes


def _g(x: float) -> str:
    return f"{x:.4g}"


#: fix table columns, most important first: a narrow terminal keeps a prefix of them
#: (link and status always), with the width each needs to be readable.
#: Columns in the order they are dropped last (a narrow terminal keeps the first ones),
#: with the width each needs; they are shown in :data:`_FIX_ORDER`.
_FIX_COLUMNS = (("link", 0), ("mass kg", 10), ("notes", 24), ("CoM m", 26),
                ("principal moments kg m^2", 28), ("geometry", 30))
_FIX_ORDER = ("link", "mass kg", "CoM m", "principal moments kg m^2", "geometry", "notes")


def fix_console(stderr: bool = False) -> Console:
    from urdfinertia.render.console import output_console

    return output_console(stderr)


def _fix_columns(width: int | None) -> list[str]:
    if width is None:
        return list(_FIX_ORDER)
    keep: list[str] = []
    used = 12
    for name, need in _FIX_COLUMNS:
        if used + need <= width or not keep:
            keep.append(name)
            used += need
    return [name for name in _FIX_ORDER if name in keep]


def _notes(r: LinkResult) -> str:
    """Decision, kept/derived, mass source, error bar, then the verdict's note findings
    (elements dropped, meshes repaired ...); each note once. The error bar is its band only
    ("±79 %"): its basis is in ``--json`` and ``explain``."""
    full_bar = str(r.error_bar) if r.error_bar is not None else None
    short_bar = None
    if r.error_bar is not None:
        short_bar = f"±{100 * r.error_bar.band:.0f} %"
        band = r.error_bar.mass
        if band is not None:  # a derived mass states its band where it is shown
            short_bar += (f"; mass prior {band.low:.3g}-{band.high:.3g} kg "
                          f"({100 * band.level:.0f} %)")
    decided = [short_bar if n == full_bar else n for n in link_notes(r, findings=False)]
    notes = (*decided, *collapse_notes([note_text(f) for f in verdict_notes(r)]))
    return "; ".join(dict.fromkeys(x for x in notes if x))


def collapse_notes(notes: Sequence[str]) -> list[str]:
    """Notes repeated for every body of one mesh (``collision[0] body 3: note``) as one
    line with a count (``collision[0] (12 bodies): note``)."""
    import re

    counts: dict[tuple[str, str], int] = {}
    order: list[tuple[str, str]] = []
    for note in notes:
        m = re.match(r"(.*?) body \d+: (.*)\Z", note, re.S)
        key = (m.group(1), m.group(2)) if m else ("", note)
        if key not in counts:
            order.append(key)
            counts[key] = 0
        counts[key] += 1
    out = []
    for element, note in order:
        n = counts[element, note]
        if not element:
            out.append(note)
        else:
            out.append(f"{element}{f' ({n} bodies)' if n > 1 else ' body'}: {note}")
    return out


def fix_table(results: Sequence[LinkResult], title: str, width: int | None = None) -> Table:
    from rich.text import Text

    # a long path folds rather than widening the output
    table = Table(title=Text(title, overflow="fold"), show_lines=False)
    columns = _fix_columns(width)
    for col in columns:
        table.add_column(col, overflow="fold")

    def row(cells: dict[str, str]) -> None:
        table.add_row(*(cells[c] for c in columns))

    for r in results:
        if r.assembly is None:
            if r.status == "left":
                status = "[yellow]left as it was[/yellow]"
                notes = f"[yellow]left as it was:[/yellow] {r.reason}"
            else:
                status, notes = r.geometry, _notes(r)
            row({"link": r.name, "mass kg": "-", "CoM m": "-",
                 "principal moments kg m^2": "-", "geometry": status, "notes": notes})
            continue
        t = r.assembly.total
        moments, _ = t.principal()
        parts = r.assembly.parts
        methods = sorted({p.part.method for p in parts})
        if parts:
            kind = f" {KIND_WORDS[r.choice.kind]}" if r.choice is not None else ""
            geo = f"{r.geometry}{kind}: {len(parts)} part{'s' if len(parts) != 1 else ''}"
            geo += f" ({', '.join(methods)})"
        else:  # --repair-only: the written values, corrected, no geometry involved
            geo = r.geometry
        row({"link": r.name, "mass kg": _g(t.mass),
             "CoM m": _vec(t.com, r.size),  # round-off below 1e-12 x size shown as 0
             "principal moments kg m^2": " ".join(_g(m) for m in moments),
             "geometry": geo,
             "notes": _notes(r)})  # decision, kept/derived, mass source, error bar
    return table


def print_fix_table(results: Sequence[LinkResult], title: str, console: Console) -> None:
    console.print(fix_table(results, title, console.width))
    from_spec = [r for r in results if r.geometry == "spec" and r.assembly is not None]
    if from_spec:
        console.print(element_table(from_spec, "per-element contributions (links in the spec)"))


#: Values below this fraction of the link's scale are round-off and shown as 0.
_NOISE = 1e-12


def _vec(v: Iterable[float] | None, scale: float = 0.0) -> str:
    if v is None:
        return "-"
    return " ".join(_g(0.0 if abs(c) < _NOISE * scale else float(c)) for c in v)


def _tensor_cell(m: np.ndarray | None, scale: float = 0.0) -> str:
    """Diagonal on the first line, products (ixy ixz iyz, URDF signs) on the second."""
    if m is None:
        return "-"
    return (_vec((m[0, 0], m[1, 1], m[2, 2]), scale) + "\n"
            + _vec((m[0, 1], m[0, 2], m[1, 2]), scale))


def _pct(share: Iterable[float]) -> str:
    return " ".join(f"{100 * float(s):.1f}" for s in share)


def element_table(results: Sequence[LinkResult], title: str) -> Table:
    """Per-element contributions of every link (mass, CoM, share of principal moments)."""
    table = Table(title=title)
    for col in ("link", "element", "mass kg", "mass %", "CoM in link frame m",
                "share of principal moments % (λ1 λ2 λ3)"):
        table.add_column(col, overflow="fold")
    for r in results:
        if r.assembly is None:
            continue
        b = link_breakdown(r)
        for i, e in enumerate(b.elements):
            c = e.element
            table.add_row(r.name if i == 0 else "", c.name, _g(c.mass),
                          f"{100 * c.mass / b.total.mass:.1f}", _vec(c.com, r.size),
                          _pct(c.share),
                          end_section=i == len(b.elements) - 1)
    return table


def breakdown_table(b: Breakdown) -> Table:
    """``urdf-inertia explain``: elements, their parts and the link total (paper sec. 5)."""
    t = b.total
    size = float(np.sqrt(np.trace(t.inertia) / t.mass) + np.linalg.norm(t.com))
    big = float(np.abs(t.inertia).max())
    geometry = str(b.choice) if b.choice is not None else b.geometry
    table = Table(title=f"link '{b.link}' ({geometry}; {b.mass_source})",
                  caption="tensors: ixx iyy izz / ixy ixz iyz, kg m^2, link axes, URDF signs\n"
                          f"principal moments λ1 λ2 λ3 = {_vec(b.moments)} kg m^2\n"
                          f"principal axes e1; e2; e3 = "
                          + "; ".join(_vec(a, 1.0) for a in b.axes.T))
    for col in ("element / part", "mass kg", "CoM in link frame m", "I about own CoM (I_sp)",
                "I about link CoM (I_p,s)", "share % (λ1 λ2 λ3)", "how"):
        table.add_column(col, overflow="fold")  # wraps at spaces, folds long names
    for e in b.elements:
        c = e.element
        table.add_row(f"[bold]{c.name}[/bold]", _g(c.mass), _vec(c.com, size),
                      _tensor_cell(c.inertia_own, big), _tensor_cell(c.inertia_link, big),
                      _pct(c.share), "")
        if len(e.parts) == 1 and e.parts[0].name.rsplit("/", 1)[0] == c.name:
            table.add_row(f"  {e.parts[0].name}", "", "", "", "", "", _how(e.parts[0]),
                          end_section=True)
            continue
        for i, p in enumerate(e.parts):
            table.add_row(f"  {p.name}", _g(p.mass), _vec(p.com, size),
                          _tensor_cell(p.inertia_own, big), _tensor_cell(p.inertia_link, big),
                          _pct(p.share), _how(p), end_section=i == len(e.parts) - 1)
    table.add_row("[bold]link total[/bold]", _g(t.mass), _vec(t.com, size),
                  _tensor_cell(t.inertia, big), _tensor_cell(t.inertia, big),
                  _pct([1.0, 1.0, 1.0]), "")
    return table


def _how(p: Contribution) -> str:
    text = p.method
    if p.density is not None:
        text += f", {_g(p.density)} kg/m^3"
    return text + (", cavity" if p.cavity else "")
