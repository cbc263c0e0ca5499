"""``urdf-inertia fix --write-back``: edit the xacro and YAML sources of a fixed robot.

The logic is :mod:`urdfinertia.descriptions.xacro.writeback` (where each value is written)
and :mod:`~urdfinertia.descriptions.xacro.apply` (verified writing); this module runs them
for the ``fix`` command and prints and saves what was done per link.
"""

from __future__ import annotations

import argparse
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from urdfinertia.descriptions.xacro.writeback import Plan
    from urdfinertia.plan.results import FixResult


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("--write-back", action="store_true",
                   help="xacro input: change the values where they are written (xacro "
                        "literals, properties, macro call attributes, YAML scalars); values "
                        "that are computed or shared are reported, not changed "
                        "(--in-place implies this for xacro input)")
    p.add_argument("--write-back-report", type=parse_path, metavar="YAML",
                   help="with --write-back: write the links that were not written back, "
                        "with where each value comes from, to this YAML file")


def parse_path(text: str):  # noqa: ANN201 - argparse type
    from pathlib import Path

    return Path(text)


def wants_write_back(args: argparse.Namespace, result: FixResult) -> bool:
    if getattr(args, "write_back", False):
        return True
    return bool(getattr(args, "in_place", False)) and result.robot.format == "xacro"


def write_back(args: argparse.Namespace, result: FixResult) -> Plan:
    """Plan and apply the write-back of ``result`` (a fixed xacro robot): the library's
    :func:`urdfinertia.plan.save.write_back` with the command line's xacro settings."""
    from urdfinertia.descriptions.xacro.settings import current_settings
    from urdfinertia.errors import UrdfInertiaError
    from urdfinertia.plan.save import write_back as write_sources

    if result.robot.format != "xacro":
        raise UrdfInertiaError("--write-back applies to xacro input (a URDF is fixed with "
                               "--in-place or -o)", file=args.urdf)
    settings = current_settings()
    return write_sources(result, xacro_args=dict(settings.args),
                         package_dirs=dict(settings.package_dirs),
                         report=args.write_back_report)


def print_summary(plan: Plan, console) -> None:  # noqa: ANN001 - a rich Console
    from rich.table import Table

    table = Table(title="write-back")
    for col in ("link", "status", "where / why"):
        table.add_column(col, overflow="fold")
    style = {"written": "green", "reported": "yellow", "unchanged": "dim"}
    for o in plan.outcomes:
        table.add_row(o.link, f"[{style[o.status]}]{o.status}[/]", o.detail)
    console.print(table)
    counts = {s: sum(o.status == s for o in plan.outcomes)
              for s in ("written", "reported", "unchanged")}
    console.print(f"write-back: {counts['written']} link(s) written back, "
                  f"{counts['reported']} reported, {counts['unchanged']} unchanged")
