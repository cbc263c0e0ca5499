"""Terminal tables (rich) for per-link results."""

from __future__ import annotations

from collections.abc import Sequence

from rich.console import Console
from rich.table import Table

from .fix import LinkResult


def _g(x: float) -> str:
    return f"{x:.4g}"


def fix_table(results: Sequence[LinkResult], title: str) -> Table:
    table = Table(title=title, show_lines=False)
    for col in ("link", "mass kg", "CoM m", "principal moments kg m^2", "geometry", "notes"):
        table.add_column(col, overflow="fold")
    for r in results:
        if r.assembly is None:
            table.add_row(r.name, "-", "-", "-", r.geometry, "; ".join(r.warnings))
            continue
        t = r.assembly.total
        moments, _ = t.principal()
        parts = r.assembly.parts
        methods = sorted({p.part.method for p in parts})
        geo = f"{r.geometry}: {len(parts)} part{'s' if len(parts) != 1 else ''}"
        geo += f" ({', '.join(methods)})"
        table.add_row(
            r.name,
            _g(t.mass),
            " ".join(_g(c) for c in t.com),
            " ".join(_g(m) for m in moments),
            geo,
            "; ".join((r.assembly.mass_source, *r.warnings)),
        )
    return table


def print_fix_table(results: Sequence[LinkResult], title: str, console: Console) -> None:
    console.print(fix_table(results, title))
