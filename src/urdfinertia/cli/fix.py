"""``urdf-inertia fix``: arguments and output of the main job."""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

from urdfinertia.atomic import atomic_write_bytes, write_in_place
from urdfinertia.cli.batch import (
    add_batch_arguments,
    finish_single,
    is_batch,
    run_many,
    single_file_library,
)
from urdfinertia.cli.options import (
    add_common_geometry_arguments,
    add_policy_arguments,
    options_from_args,
)
from urdfinertia.errors import OutputError, UrdfInertiaError
from urdfinertia.link.fix import fix_file

# rich (tables) and the JSON writer are imported when they are used: a quiet batch run
# whose results are all cached needs neither.


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("urdf", type=Path, help="the URDF to fix, or a folder of URDFs")
    p.add_argument("more", type=Path, nargs="*", metavar="URDF_OR_DIR",
                   help="more URDFs or folders (searched recursively for *.urdf); with "
                        "several inputs or a folder, -o names an output folder that keeps "
                        "the tree")
    out = p.add_mutually_exclusive_group()
    out.add_argument("-o", "--output", type=Path, help="write the fixed URDF here")
    out.add_argument("--in-place", action="store_true",
                     help="overwrite the input (a copy is kept as URDF.bak)")
    add_common_geometry_arguments(p)
    add_policy_arguments(p)
    p.add_argument("--json", type=Path, metavar="PATH", help="write per-link results as JSON")
    p.add_argument("-q", "--quiet", action="store_true", help="no table on the terminal")
    p.add_argument("--repair-only", action="store_true",
                   help="keep every mass and CoM; only lift the principal moments of invalid "
                        "tensors (not positive definite, A + B < C) just enough; geometry "
                        "options are ignored")
    add_batch_arguments(p)


def run(args: argparse.Namespace) -> int:
    options = options_from_args(args)
    if getattr(args, "repair_only", False):
        from urdfinertia.link.repair_only import repair_file

        if is_batch(args):
            raise UrdfInertiaError("--repair-only takes a single URDF file")
        result = repair_file(args.urdf)
    elif is_batch(args):
        return run_many(args, options)
    else:
        meshes = single_file_library(args, options)
        result = fix_file(args.urdf, options, meshes)
        finish_single(args, meshes)
    if args.output is not None and args.output.resolve() == args.urdf.resolve():
        raise OutputError("output is the input file: use --in-place", file=args.output)
    # everything is computed before the first write; the URDF (the file that matters)
    # is written first, so a failure leaves at most the JSON missing
    text = None
    if args.json is not None:
        from urdfinertia.render.results_json import fix_result_dict

        text = json.dumps(fix_result_dict(result), indent=2)
    if args.in_place:
        if result.changed:
            write_in_place(args.urdf, result.output)
    elif args.output is not None:
        atomic_write_bytes(args.output, result.output)
    if text is not None:
        atomic_write_bytes(args.json, text.encode())
    if not args.quiet:
        from rich.console import Console

        from urdfinertia.render.table import print_fix_table

        console = Console(stderr=args.output is None and not args.in_place, width=160)
        print_fix_table(result.links, f"{result.path}: {result.robot.name}", console)
    _mass_summary(result, args.quiet)  # issue 14: the robot's mass never changes silently
    if args.output is None and not args.in_place:
        sys.stdout.buffer.write(result.output)  # a filter: -q only silences the table
    return 0


def _mass_summary(result, quiet: bool) -> None:
    from rich.console import Console

    from urdfinertia.render.decisions import print_mass_summary

    print_mass_summary(result, Console(stderr=True, width=160), quiet=quiet)


__all__ = ["add_arguments", "run", "UrdfInertiaError"]
