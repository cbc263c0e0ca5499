"""``urdf-inertia check``: lint inertials as written; exit 1 when problems are found.

Exit codes: 0 clean, 1 errors (or warnings with ``--strict``), 2 unreadable input (any
:class:`UrdfInertiaError`, printed as one line by :mod:`cli`).
"""

from __future__ import annotations

import argparse
import json
from collections import Counter
from pathlib import Path

from rich.console import Console
from rich.table import Table

from urdfinertia.analysis.check import SEVERITIES, Finding, check_robot
from urdfinertia.atomic import atomic_write_bytes
from urdfinertia.cache.library import MeshLibrary
from urdfinertia.cli.options import add_geometry_source_arguments
from urdfinertia.descriptions.formats import read_description
from urdfinertia.link.options import FixOptions


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("urdf", type=Path, nargs="+", help="the URDF file(s) to check")
    p.add_argument("--json", type=Path, metavar="PATH", help="write the findings as JSON")
    p.add_argument("--strict", action="store_true", help="warnings also make the exit code 1")
    p.add_argument("--no-geometry", action="store_true",
                   help="check the written values only; read no mesh (skips CoM-in-box, "
                        "density and tensor-size checks)")
    p.add_argument("--show-info", action="store_true",
                   help="also list info findings (lumped masses, massless frames)")
    add_geometry_source_arguments(p)
    p.add_argument("-q", "--quiet", action="store_true", help="print only the summary line")


def exit_code(findings: list[Finding], strict: bool) -> int:
    bad = {"error", "warning"} if strict else {"error"}
    return 1 if any(f.severity in bad for f in findings) else 0


def run(args: argparse.Namespace) -> int:
    options = FixOptions(geometry=args.geometry, package_dirs=dict(args.package_dir),
                         max_faces=args.max_faces)
    meshes = None if args.no_geometry else MeshLibrary(options.package_dirs, options.max_faces)
    console = Console(width=170)
    report = []
    code = 0
    for path in args.urdf:
        robot, _ = read_description(path, lenient=True)
        findings = check_robot(robot, meshes=meshes, options=options)
        code = max(code, exit_code(findings, args.strict))
        report.append({"file": str(path), "robot": robot.name, "links": len(robot.links),
                       "counts": severity_counts(findings),
                       "findings": [vars(f) for f in findings]})
        if not args.quiet:
            shown = [f for f in findings if args.show_info or f.severity != "info"]
            if shown:
                console.print(findings_table(shown, f"{path}: {robot.name}"))
        if meshes is not None:  # what fix would do, by the same rules (issue 14)
            _show_plan(robot, meshes, options, report[-1], console, args.quiet)
        console.print(summary_line(str(path), len(robot.links), findings))
    if args.json is not None:
        doc = {"exit_code": code, "strict": args.strict, "files": report}
        atomic_write_bytes(args.json, json.dumps(doc, indent=2).encode())
    return code


def _show_plan(robot, meshes: MeshLibrary, options: FixOptions, entry: dict,
               console: Console, quiet: bool) -> None:
    from urdfinertia.link.policy import plan_robot
    from urdfinertia.render.decisions import plan_dict, plan_table

    plan = plan_robot(robot, options, meshes)
    entry["fix_plan"] = plan_dict(plan)
    if not quiet:
        console.print(plan_table(plan, f"urdf-inertia fix (default) on {robot.name}"))


def severity_counts(findings: list[Finding]) -> dict[str, int]:
    counts = Counter(f.severity for f in findings)
    return {s: counts.get(s, 0) for s in SEVERITIES}


def summary_line(path: str, n_links: int, findings: list[Finding]) -> str:
    c = severity_counts(findings)
    codes = Counter(f.code for f in findings if f.severity != "info")
    top = ", ".join(f"{code} x{n}" for code, n in codes.most_common(4))
    return (f"{path}: {n_links} links, {c['error']} error(s), {c['warning']} warning(s), "
            f"{c['info']} info{': ' + top if top else ''}")


def findings_table(findings: list[Finding], title: str) -> Table:
    table = Table(title=title)
    for col in ("link", "severity", "code", "message"):
        table.add_column(col, overflow="fold")
    style = {"error": "red", "warning": "yellow", "info": "cyan"}
    order = {s: i for i, s in enumerate(SEVERITIES)}
    for f in sorted(findings, key=lambda f: order[f.severity]):
        table.add_row(f.link or "-", f"[{style[f.severity]}]{f.severity}[/]", f.code,
                      f.message)
    return table
