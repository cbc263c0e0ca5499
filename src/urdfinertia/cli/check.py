"""``urdf-inertia check``: lint inertials as written; exit 1 when problems are found.

``check`` is ``fix``'s plan without writing: it prints the same verdicts ``fix`` carries
out (:func:`urdfinertia.analysis.check.check_description`).

Exit codes: 0 clean; 1 errors (or warnings with ``--strict``) that a ``--baseline`` does
not know, or a link that could not be verified: geometry checks were asked for (the
default) and some of its geometry could not be read (a mesh reference that does not
resolve or a mesh that cannot be read), unless a baseline knows that finding; 2 unreadable
input (any :class:`UrdfInertiaError`, printed as one line by :mod:`cli`).
``--write-baseline`` exits 0: everything found is then known. ``--no-geometry`` asks for
the written values only, so unread meshes do not fail it.
"""

from __future__ import annotations

import argparse
import json
import sys
from collections import Counter
from dataclasses import replace
from pathlib import Path
from typing import Any

from rich.markup import escape
from rich.table import Table

from urdfinertia.analysis.baseline import Baseline, write_baseline
from urdfinertia.analysis.check import CheckResult, check_description
from urdfinertia.analysis.locate import CheckedFile, locate_all
from urdfinertia.analysis.statics import DEFAULT_MARGIN
from urdfinertia.atomic import atomic_write_bytes
from urdfinertia.body.options import FixOptions
from urdfinertia.cli.batch import add_batch_arguments, finish_single, single_file_library
from urdfinertia.cli.options import (
    add_engine_arguments,
    add_geometry_source_arguments,
    engine_request,
    positive_float,
    user_path,
)
from urdfinertia.descriptions.formats import is_description, read_bytes, robot_from_bytes
from urdfinertia.errors import UrdfInertiaError
from urdfinertia.findings import SEVERITIES, Finding, finding_dict
from urdfinertia.judge.realizability import METHODS
from urdfinertia.plan.edits import slip_fixes
from urdfinertia.plan.results import UNREAD
from urdfinertia.plan.total_mass import DEFAULT_MASS_TOLERANCE
from urdfinertia.render.annotations import annotation_lines
from urdfinertia.render.sarif import sarif_document

FORMATS = ("text", "json", "sarif", "github")


EPILOG = ("check is fix's plan without writing: it lists what fix would do with every link "
          "that has findings. Exit codes: 0 clean; 1 an error (a warning too with --strict) "
          "that no --baseline knows, or a link that was not verified because some of its "
          "geometry could not be read (pass --package-dir NAME=PATH, or --no-geometry to "
          "check the written values only); 2 unreadable input.")


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.epilog = EPILOG
    p.add_argument("urdf", type=Path, nargs="+", help="the description file(s) to check")
    p.add_argument("--format", choices=FORMATS, default="text",
                   help="what goes to stdout: text (tables), json, sarif (SARIF 2.1.0) or "
                        "github (workflow annotations) (default: text)")
    p.add_argument("--json", type=Path, metavar="PATH", help="write the findings as JSON")
    p.add_argument("--sarif", type=Path, metavar="PATH", help="write the findings as SARIF")
    p.add_argument("--baseline", type=Path, metavar="FILE",
                   help="findings recorded here (by rule, file and link) are known: shown, "
                        "but they do not fail the run")
    p.add_argument("--write-baseline", type=Path, metavar="FILE",
                   help="record every error and warning found as the new baseline (exit 0)")
    p.add_argument("--strict", action="store_true",
                   help="warnings also make the exit code 1, except those on values fix "
                        "keeps on purpose (each says why): check --strict passes on what "
                        "fix writes")
    p.add_argument("--no-geometry", action="store_true",
                   help="check the written values only; read no mesh (skips CoM-in-box, "
                        "density and tensor-size checks, and fix's plan; unread meshes then "
                        "do not fail the run)")
    p.add_argument("--show-info", action="store_true",
                   help="also list info findings (lumped masses, massless frames)")
    p.add_argument("--skip-unknown-formats", action="store_true",
                   help="skip files no registered format takes by suffix and root element "
                        "(package.xml, launch files): for hooks handed every *.xml")
    p.add_argument("--includers", action="store_true",
                   help="a xacro file with no links of its own (a macro include) is checked "
                        "through the top-level xacro files under the working directory "
                        "that include it, directly or not: for hooks handed changed files")
    p.add_argument("--no-statics", action="store_true",
                   help="skip whole-robot statics (each joint's gravity load over its range "
                        "against its effort limit)")
    p.add_argument("--effort-margin", type=float, default=DEFAULT_MARGIN, metavar="FRACTION",
                   help="warn when a joint's gravity load exceeds (1 - FRACTION) of its "
                        "effort limit (default: %(default)s)")
    p.add_argument("--realizable", choices=METHODS, default="ellipsoid",
                   help="the region UI210 holds each written inertial in: the geometry's "
                        "bounding ellipsoid (exact, fast) or its convex hull (an LP with "
                        "HiGHS: tighter, slower) (default: %(default)s)")
    p.add_argument("--total-mass", type=positive_float, metavar="KG",
                   help="what the robot is known to weigh (a datasheet's figure): warn "
                        "(UI703) when the written masses miss it by more than "
                        "--mass-tolerance, and plan fix --total-mass KG")
    p.add_argument("--scale-kept", action="store_true",
                   help="with --total-mass (or a spec's targets): plan fix --scale-kept, "
                        "which scales kept masses too")
    p.add_argument("--mass-tolerance", type=positive_float, default=DEFAULT_MASS_TOLERANCE,
                   metavar="FRACTION",
                   help="a written total within this fraction of its target is no finding "
                        "(default: %(default)s)")
    p.add_argument("--spec", type=user_path, metavar="TOML",
                   help="decomposition spec: its parts plan the links as fix --spec does; "
                        "its total_mass and [subtree.NAME] mass are held against the "
                        "written masses (UI703)")
    add_engine_arguments(p)
    add_geometry_source_arguments(p)
    p.add_argument("--no-slips", action="store_true",
                   help="do not search flagged links for a one-edit slip (plan as fix "
                        "--no-slips)")
    p.add_argument("-q", "--quiet", action="store_true", help="print only the summary line")
    add_batch_arguments(p)


def exit_code(cf: CheckedFile, result: CheckResult, strict: bool) -> int:
    """1 when a finding no baseline knows fails the run (:meth:`CheckResult.failing`: an
    error, with ``strict`` a warning ``fix`` does not keep on purpose), a link was not
    verified (and no baseline knows why), or ``fix`` would leave a link that needs
    changing; else 0."""
    new = {id(f) for f in cf.new}
    if any(id(f) in new for f in result.failing(strict)):
        return 1
    if any(f.rule in UNREAD and f.link in cf.unverified for f in cf.new):
        return 1
    return 1 if result.left else 0


def run(args: argparse.Namespace) -> int:
    spec = None
    if args.spec is not None:
        from urdfinertia.body.spec import load_spec

        spec = load_spec(args.spec)
    if args.total_mass is not None and len(args.urdf) > 1:  # a datasheet's figure: one robot
        raise UrdfInertiaError("--total-mass takes a single description")
    options = FixOptions(geometry=args.geometry, package_dirs=dict(args.package_dir),
                         max_faces=args.max_faces, slips=not args.no_slips, spec=spec,
                         total_mass=args.total_mass, scale_kept=args.scale_kept,
                         realizable=args.realizable)
    paths = list(args.urdf)
    if args.includers:
        from urdfinertia.descriptions.xacro.includers import checked_through

        paths, replaced = checked_through(paths, Path.cwd())
        for r in replaced:
            print(f"{r.include}: no links of its own: checked through "
                  f"{', '.join(map(str, r.robots))}", file=sys.stderr)
    # the meshes in parallel with -j (default: the cores), through the persistent cache
    meshes = None if args.no_geometry else single_file_library(args, options, paths)
    baseline = (Baseline.load(args.baseline) if args.baseline is not None
                else Baseline.empty(Path.cwd()))
    engines = engine_request(args)
    checked: list[CheckedFile] = []
    plans: dict[Path, Any] = {}
    codes = []
    for path in paths:
        data = read_bytes(path)
        if args.skip_unknown_formats and not is_description(data, path):
            continue
        robot = robot_from_bytes(data, path)
        result = check_description(robot, meshes=meshes, options=options,
                                   geometry=meshes is not None,
                                   statics=not args.no_statics,
                                   effort_margin=args.effort_margin,
                                   mass_tolerance=args.mass_tolerance)
        if engines is not None:
            result = replace(result, findings=result.findings + tuple(
                engines.findings(path, robot, options.package_dirs)))
        findings = list(result.findings)
        cf = CheckedFile(path, robot, findings, locate_all(robot, data, findings),
                         baseline.mark(findings, path),
                         frozenset(r.name for r in result.unverified),
                         result.links, slip_fixes(robot, data, result.links))
        checked.append(cf)
        codes.append(exit_code(cf, result, args.strict))
        if result.links:  # what fix would do: the verdicts fix carries out
            plans[path] = result.links
    code = max(codes, default=0)
    if args.write_baseline is not None:
        n = write_baseline(args.write_baseline, [(cf.path, cf.findings) for cf in checked])
        print(f"{args.write_baseline}: baseline of {n} finding(s) written", file=sys.stderr)
        code = 0
    doc = json_document(checked, code, args.strict, plans)
    sarif = sarif_document(checked, with_baseline=args.baseline is not None,
                           include_info=args.show_info)
    if args.json is not None:
        atomic_write_bytes(args.json, json.dumps(doc, indent=2).encode())
    if args.sarif is not None:
        atomic_write_bytes(args.sarif, json.dumps(sarif, indent=2).encode())
    print_report(args, checked, doc, sarif, plans)
    if meshes is not None:
        finish_single(args, meshes)
    return code


def print_report(args: argparse.Namespace, checked: list[CheckedFile], doc: dict,
                 sarif: dict, plans: dict[Path, Any] | None = None) -> None:
    if args.format == "json":
        print(json.dumps(doc, indent=2))
    elif args.format == "sarif":
        print(json.dumps(sarif, indent=2))
    elif args.format == "github":
        for line in annotation_lines(checked, include_info=args.show_info):
            print(line)
    from urdfinertia.render.console import output_console

    # the summary goes to stderr when stdout carries a document; plain text when piped
    console = output_console(stderr=args.format in ("json", "sarif"))
    for cf in checked:
        if args.format == "text" and not args.quiet:
            shown = [(f, k) for f, k in zip(cf.findings, cf.known, strict=True)
                     if args.show_info or f.severity != "info"]
            if shown:
                console.print(findings_table(shown, f"{cf.path}: {cf.robot.name}"))
            if plans and cf.path in plans:
                from urdfinertia.render.decisions import plan_table

                console.print(plan_table(plans[cf.path],
                                         f"urdf-inertia fix (default) on {cf.robot.name}"))
        if not (args.quiet and args.format != "text"):
            console.print(summary_line(str(cf.path), len(cf.robot.links), cf.findings,
                                       sum(cf.known)), markup=False, highlight=False)
            unread = unverified_line(plans.get(cf.path, ()) if plans else ())
            if unread is not None:
                console.print(unread, markup=False, highlight=False)


def json_document(checked: list[CheckedFile], code: int, strict: bool,
                  plans: dict[Path, Any] | None = None) -> dict:
    from urdfinertia.render.decisions import plan_dict

    report = []
    for cf in checked:
        rows = [{**finding_dict(f), "line": loc.line, "column": loc.column,
                 "known": known, "fix": cf.decision_of(f.link), "kept": cf.keeps(f)}
                for f, loc, known in zip(cf.findings, cf.locations, cf.known, strict=True)]
        report.append({"file": str(cf.path), "robot": cf.robot.name,
                       "links": len(cf.robot.links), "counts": severity_counts(cf.findings),
                       "findings": rows})
        if plans and cf.path in plans:
            report[-1]["fix_plan"] = plan_dict(plans[cf.path])
            report[-1]["unverified"] = [r.name for r in plans[cf.path] if r.unverified]
    return {"exit_code": code, "strict": strict, "files": report}


def unverified_line(verdicts) -> str | None:
    """The one summary line of what could not be verified, with how to fix it."""
    from urdfinertia.render.decisions import unverified_summary

    line = unverified_summary(verdicts)
    return None if line is None else f"{line}: pass --package-dir NAME=PATH"


def severity_counts(findings: list[Finding]) -> dict[str, int]:
    counts = Counter(f.severity.value for f in findings)
    return {s: counts.get(s, 0) for s in SEVERITIES}


def summary_line(path: str, n_links: int, findings: list[Finding], known: int = 0) -> str:
    c = severity_counts(findings)
    codes = Counter(f.code for f in findings if f.severity != "info")
    top = ", ".join(f"{code} x{n}" for code, n in codes.most_common(4))
    base = f" ({known} known from the baseline)" if known else ""
    return (f"{path}: {n_links} links, {c['error']} error(s), {c['warning']} warning(s), "
            f"{c['info']} info{base}{': ' + top if top else ''}")


def findings_table(findings: list[tuple[Finding, bool]], title: str) -> Table:
    """Findings with whether each is known from a baseline (known ones are dimmed)."""
    table = Table(title=title)
    for col in ("link", "severity", "code", "message"):
        table.add_column(col, overflow="fold")
    style = {"error": "red", "warning": "yellow", "info": "cyan"}
    order = {s: i for i, s in enumerate(SEVERITIES)}
    for f, known in sorted(findings, key=lambda fk: order[fk[0].severity]):
        severity = f"[{style[f.severity]}]{f.severity}[/]" + (" (known)" if known else "")
        table.add_row(f.link or "-", severity, f"{f.code} ({f.rule.id})", escape(f.message),
                      style="dim" if known else None)
    return table
