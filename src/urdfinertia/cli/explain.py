"""``urdf-inertia explain``: one link's per-element and per-part breakdown (paper sec. 5).

The total is what ``fix`` writes for the link (its decision is printed under the table);
the elements are its geometry's homogeneous model. A wrong ``--link`` names the three
nearest link names.
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

from urdfinertia.analysis.explain import breakdown_dict, explain_link
from urdfinertia.cli.options import add_common_geometry_arguments, options_from_args
from urdfinertia.descriptions.formats import read_description
from urdfinertia.render.table import breakdown_table


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("urdf", type=Path, help="the URDF")
    p.add_argument("--link", required=True, metavar="NAME", help="the link to break down")
    add_common_geometry_arguments(p)
    p.add_argument("--json", action="store_true",
                   help="print the breakdown as JSON on stdout instead of a table")
    p.add_argument("--plot", type=Path, metavar="PATH.png",
                   help="also write a PNG: each element's share of the mass and of each "
                        "principal moment")


def run(args: argparse.Namespace) -> int:
    options = options_from_args(args)
    robot, _ = read_description(args.urdf)
    breakdown = explain_link(robot, args.link, options)
    if args.plot is not None:
        from urdfinertia.render.explain_plot import plot_breakdown

        plot_breakdown(breakdown, args.plot)
        print(f"urdf-inertia: wrote {args.plot}", file=sys.stderr)
    if args.json:
        sys.stdout.write(json.dumps(breakdown_dict(breakdown), indent=2) + "\n")
        return 0
    from urdfinertia.render.console import output_console

    console = output_console()
    console.print(breakdown_table(breakdown))
    if breakdown.decision:
        console.print(f"fix: {breakdown.decision}", markup=False, highlight=False)
    verdict = breakdown.verdict
    if verdict is not None and verdict.error_bar is not None and verdict.changed:
        console.print(f"error bar: {verdict.error_bar}", markup=False, highlight=False)
    from urdfinertia.rules import Severity

    for f in breakdown.findings:
        if f.severity != Severity.INFO:
            console.print(f"{f.severity.value}: {f.rule.id} {f.code}: {f.message}",
                          markup=False, highlight=False)
    return 0
