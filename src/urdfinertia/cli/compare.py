"""``urdf-inertia compare``: existing inertials against the geometry or another URDF.

Against the geometry each link shows what ``fix`` would do with it; a link beyond
tolerance that ``fix`` keeps is "kept", not "differs" (the homogeneous geometry is a
model), and ``--fail-above`` counts only links that differ or are invalid.
"""

from __future__ import annotations

import argparse
import csv
import io
import json
import math
import sys
from pathlib import Path

from rich.table import Table

from urdfinertia.analysis.compare import (
    DEFAULT_TOL_COM,
    DEFAULT_TOL_INERTIA,
    DEFAULT_TOL_MASS,
    FAILING,
    LinkComparison,
    compare_with_geometry,
    comparison_dict,
    match_files,
    summary,
    worst_first,
)
from urdfinertia.analysis.matching import Matching
from urdfinertia.atomic import atomic_write_bytes
from urdfinertia.cli.options import add_common_geometry_arguments, options_from_args, positive_float
from urdfinertia.errors import OutputError


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("urdf", type=Path, help="the URDF whose inertials are compared (side A)")
    p.add_argument("--against", type=Path, metavar="OTHER",
                   help="compare with this description's inertials (side B) instead of the "
                        "geometry; of another format (robot.usd from robot.urdf or .xml), "
                        "also name what the conversion changed")
    p.add_argument("--json", type=Path, metavar="PATH", help="write per-link results as JSON")
    p.add_argument("--csv", type=Path, metavar="PATH", help="write per-link results as CSV")
    p.add_argument("--plot", type=Path, metavar="PATH.png",
                   help="write a PNG of per-link errors, worst first")
    p.add_argument("--tol-com", type=positive_float, default=DEFAULT_TOL_COM,
                   metavar="FRACTION", help="CoM distance / link size above which a link "
                   f"differs (default {DEFAULT_TOL_COM:g})")
    p.add_argument("--tol-inertia", type=positive_float, default=DEFAULT_TOL_INERTIA,
                   metavar="FRACTION", help="relative Frobenius tensor error above which a "
                   f"link differs (default {DEFAULT_TOL_INERTIA:g})")
    p.add_argument("--tol-mass", type=positive_float, default=DEFAULT_TOL_MASS,
                   metavar="FRACTION", help="|mass ratio - 1| above which a link differs "
                   f"(default {DEFAULT_TOL_MASS:g})")
    p.add_argument("--fail-above", type=positive_float, metavar="FRACTION",
                   help="exit 1 when a link's CoM distance / size, tensor error or "
                        "|mass ratio - 1| exceeds FRACTION, or a side is invalid; against "
                        "the geometry, links fix keeps as written do not count")
    p.add_argument("--all", action="store_true", help="table: also list links that are ok")
    p.add_argument("-q", "--quiet", action="store_true",
                   help="no table on the terminal, only the summary line")
    add_common_geometry_arguments(p)


def worst_error(c: LinkComparison) -> float:
    """The largest relative error of a link (inf when a side is invalid, 0 when missing)."""
    if c.verdict == "invalid":
        return math.inf
    values = [c.com_distance_rel, c.inertia_rel_error,
              abs(c.mass_ratio - 1) if c.mass_ratio is not None else None]
    return max([v for v in values if v is not None] or [0.0])


def run(args: argparse.Namespace) -> int:
    tols = dict(tol_com=args.tol_com, tol_inertia=args.tol_inertia, tol_mass=args.tol_mass)
    matching: Matching | None = None
    if args.against is not None:
        comparisons, matching = match_files(args.urdf, args.against, **tols)
        title = f"{args.urdf} (A) vs {args.against} (B)"
    else:
        comparisons = compare_with_geometry(args.urdf, options_from_args(args), **tols)
        title = f"{args.urdf}: written (A) vs geometry (B)"
    stats = summary(comparisons)
    conversion = None  # a conversion's named differences (analysis/against.py)
    if args.against is not None:
        from urdfinertia.analysis.against import compare_import, is_conversion

        if is_conversion(args.urdf, args.against):
            conversion = compare_import(args.urdf, args.against)
    if args.json is not None:
        doc = {"file": str(args.urdf), "against": str(args.against) if args.against else None,
               "tolerances": tols, "summary": stats,
               "links": [comparison_dict(c) for c in comparisons]}
        if conversion is not None:
            doc["conversion"] = conversion.as_dict()
        if matching is not None:
            doc["matching"] = {"renamed": [list(p) for p in matching.renamed],
                               "only_a": list(matching.only_a),
                               "only_b": list(matching.only_b)}
        atomic_write_bytes(args.json, json.dumps(doc, indent=2).encode())
    if args.csv is not None:
        atomic_write_bytes(args.csv, comparisons_csv(comparisons).encode())
    if args.plot is not None:
        from urdfinertia.render.compare_plot import plot_errors

        try:
            plot_errors(comparisons, args.plot, tol_com=args.tol_com,
                        tol_inertia=args.tol_inertia, title=str(args.urdf.name))
        except OSError as exc:
            raise OutputError(f"cannot write: {exc.strerror or exc}", file=args.plot) from None
        print(f"urdf-inertia: wrote {args.plot}", file=sys.stderr)
    from urdfinertia.render.console import output_console

    console = output_console()
    if not args.quiet:
        shown = worst_first(comparisons, args.tol_com, args.tol_inertia)
        if not args.all:
            shown = [c for c in shown if c.verdict != "ok"]
        console.print(comparison_table(shown, title, console.width))
    console.print(summary_line(stats), soft_wrap=True)
    if matching is not None and conversion is None and (
            matching.renamed or matching.only_a or matching.only_b):
        console.print(matching.summary(), soft_wrap=True, markup=False, highlight=False)
    if conversion is not None:
        from urdfinertia.analysis.against import report_lines

        for line in report_lines(conversion):
            console.print(line, soft_wrap=True, markup=False, highlight=False)
        if args.fail_above is not None and conversion.differences:
            return 1
    if args.fail_above is not None:
        failing = [c for c in comparisons
                   if c.verdict in FAILING and worst_error(c) > args.fail_above]
        if failing:
            console.print(f"{len(failing)} link(s) above --fail-above {args.fail_above:g}")
            return 1
    return 0


def _g(x: float | None, fmt: str = ".3g") -> str:
    return "-" if x is None else format(x, fmt)


def _moments(m) -> str:
    return "-" if m is None else " ".join(f"{v:.3g}" for v in m)


#: compare's columns, most important first: the ones that do not fit the width are left
#: out (the JSON and CSV keep every figure); numbers never wrap, the note does.
_COLUMNS = ("link", "verdict", "tensor err", "CoM/size", "mass B/A", "note", "axes deg",
            "CoM dist mm", "principal moments A", "principal moments B")
#: the note's narrowest useful width, in characters
_NOTE_WIDTH = 24


def comparison_table(comparisons: list[LinkComparison], title: str,
                     width: int | None = None) -> Table:
    """The comparison as a table; with ``width`` (characters), only the columns that fit."""
    style = {"ok": "green", "differs": "yellow", "kept": "cyan", "invalid": "red",
             "missing": "dim"}
    rows = [{
        "link": c.link, "verdict": c.verdict, "mass B/A": _g(c.mass_ratio, ".4g"),
        "CoM dist mm": _g(c.com_distance * 1000 if c.com_distance is not None else None,
                          ".3g"),
        "CoM/size": _g(c.com_distance_rel), "tensor err": _g(c.inertia_rel_error),
        "principal moments A": _moments(c.moments_a),
        "principal moments B": _moments(c.moments_b),
        "axes deg": _g(c.axis_angle_deg, ".1f"),
        "note": "; ".join(x for x in (c.note, c.decision) if x)} for c in comparisons]
    shown = _fitting_columns(rows, width)
    table = Table(title=title)
    for col in shown:
        if col == "note":
            table.add_column(col, overflow="fold", min_width=_NOTE_WIDTH, ratio=1)
        else:
            table.add_column(col, no_wrap=True)
    for cells, c in zip(rows, comparisons, strict=True):
        cells["verdict"] = f"[{style[c.verdict]}]{c.verdict}[/]"
        table.add_row(*(cells[col] for col in shown))
    return table


def _fitting_columns(rows: list[dict[str, str]], width: int | None) -> list[str]:
    if width is None:
        return list(_COLUMNS)
    used, keep = 1, list[str]()
    for col in _COLUMNS:
        need = _NOTE_WIDTH if col == "note" else max(
            [len(col)] + [len(r[col]) for r in rows])
        if used + need + 3 <= width or len(keep) < 2:
            keep.append(col)
            used += need + 3
    return [c for c in _COLUMNS if c in keep]


def summary_line(stats: dict) -> str:
    v = stats["verdicts"]
    med = stats["median"]
    counts = ", ".join(f"{v.get(k, 0)} {k}" for k in ("ok", "differs", "kept", "invalid",
                                                       "missing") if k != "kept" or k in v)
    worst = stats["worst"]
    worst_i = ", ".join(f"{n} {x:.3g}" for n, x in worst["inertia_rel_error"])
    worst_c = ", ".join(f"{n} {x:.3g}" for n, x in worst["com_distance_rel"])
    return (f"{stats['links']} links: {counts}. Medians: mass B/A {_g(med['mass_ratio'], '.4g')}, "
            f"CoM/size {_g(med['com_distance_rel'])}, tensor error "
            f"{_g(med['inertia_rel_error'])}, axes {_g(med['axis_angle_deg'], '.1f')} deg. "
            f"Worst tensor: {worst_i or '-'}. Worst CoM: {worst_c or '-'}.")


def comparisons_csv(comparisons: list[LinkComparison]) -> str:
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(["link", "verdict", "mass_a", "mass_b", "mass_ratio", "com_distance_m",
                "com_distance_rel", "inertia_rel_error", "axis_angle_deg",
                "moment_a1", "moment_a2", "moment_a3", "moment_b1", "moment_b2", "moment_b3",
                "size_m", "note"])

    def cell(x) -> str:
        return "" if x is None or not math.isfinite(x) else repr(float(x))

    for c in comparisons:
        ma = list(c.moments_a) if c.moments_a is not None else [None] * 3
        mb = list(c.moments_b) if c.moments_b is not None else [None] * 3
        w.writerow([c.link, c.verdict, cell(c.a.mass if c.a else None),
                    cell(c.b.mass if c.b else None), cell(c.mass_ratio),
                    cell(c.com_distance), cell(c.com_distance_rel),
                    cell(c.inertia_rel_error), cell(c.axis_angle_deg),
                    *map(cell, ma), *map(cell, mb), cell(c.size), c.note])
    return buf.getvalue()
