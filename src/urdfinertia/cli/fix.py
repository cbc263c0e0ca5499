"""``urdf-inertia fix``: arguments and output of the main job.

Exit codes (:mod:`urdfinertia.cli.outcome`): 0 every link computed, 1 written but some
links left as they were (each listed on stderr), 2 nothing written.
"""

from __future__ import annotations

import argparse
import json
import sys
from dataclasses import replace
from pathlib import Path

from urdfinertia.atomic import atomic_write_bytes
from urdfinertia.cli.batch import (
    add_batch_arguments,
    finish_single,
    is_batch,
    run_many,
    single_file_library,
)
from urdfinertia.cli.options import (
    add_common_geometry_arguments,
    add_engine_arguments,
    add_policy_arguments,
    engine_request,
    options_from_args,
    positive_float,
)
from urdfinertia.cli.outcome import fix_exit_code, left_lines, problem_lines, unverified_line
from urdfinertia.errors import OutputError, UrdfInertiaError
from urdfinertia.plan.fix import fix_file

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
    p.add_argument("--strict", action="store_true",
                   help="all or nothing: any element dropped, value ignored or link left "
                        "as it was is an error (exit 2, nothing written)")
    p.add_argument("--keep-mesh-paths", action="store_true",
                   help="keep relative mesh references as written even when the output "
                        "lands in another folder (default: rewrite them to resolve from "
                        "the output's folder)")
    p.add_argument("--no-slips", action="store_true",
                   help="derive a flagged inertial from its geometry even where one edit of "
                        "the written values (a slip: izz x1e-3, mass in grams) clearly "
                        "undoes what is wrong (default: undo the slip)")
    p.add_argument("--keep-auto", action="store_true",
                   help="SDFormat: leave <inertial auto=\"true\"> for the simulator to compute "
                        "(default: write explicit values and drop the auto attribute)")
    p.add_argument("--total-mass", type=positive_float, metavar="KG",
                   help="the robot weighs KG (a datasheet's figure): the masses fix derives "
                        "are scaled to meet it, kept masses stay (exit 2, nothing written, "
                        "when the kept masses alone reach it)")
    p.add_argument("--scale-kept", action="store_true",
                   help="with --total-mass (or a spec's target masses): scale every mass, "
                        "kept ones too, tensors with them")
    add_batch_arguments(p)
    from urdfinertia.cli import writeback

    writeback.add_arguments(p)
    add_engine_arguments(p)


def run(args: argparse.Namespace) -> int:
    options = replace(options_from_args(args), total_mass=getattr(args, "total_mass", None),
                      scale_kept=getattr(args, "scale_kept", False))
    if options.scale_kept and options.total_mass is None and (
            options.spec is None or not options.spec.has_targets):
        raise UrdfInertiaError("--scale-kept needs a target: --total-mass KG, or total_mass "
                               "or [subtree.NAME] mass in the spec")
    if _to_terminal(args):
        raise UrdfInertiaError(
            "not printing the fixed document on the terminal: write it with -o FILE (or "
            "--in-place), or redirect it: urdf-inertia fix ROBOT > FILE", file=args.urdf)
    if getattr(args, "repair_only", False):
        from urdfinertia.plan.repair_only import repair_file

        if is_batch(args):
            raise UrdfInertiaError("--repair-only takes a single URDF file")
        result = repair_file(args.urdf)
    elif is_batch(args):
        if getattr(args, "write_back", False):
            raise UrdfInertiaError("--write-back takes a single xacro file")
        if engine_request(args) is not None:
            raise UrdfInertiaError("--engines takes a single URDF file")
        if options.total_mass is not None:  # a datasheet's figure is one robot's
            raise UrdfInertiaError("--total-mass takes a single description")
        return run_many(args, options)
    else:
        meshes = single_file_library(args, options)
        result = fix_file(args.urdf, options, meshes)
        finish_single(args, meshes)
    from urdfinertia.descriptions.formats import format_of

    fmt = format_of(result.robot)  # USD: an override layer beside the asset by default
    if fmt.default_output is not None and args.output is None and not args.in_place:
        args.output = fmt.default_output(result.path)
    if args.output is not None and args.output.resolve() == args.urdf.resolve():
        raise OutputError("output is the input file: use --in-place", file=args.output)
    # everything is computed before the first write; the description (the file that
    # matters) is written first, so a failure leaves at most the JSON missing
    doc = None
    if args.json is not None:
        from urdfinertia.render.results_json import fix_result_dict

        doc = fix_result_dict(result)
        doc["exit_code"] = fix_exit_code(len(result.left), len(result.unverified))
    from urdfinertia.cli import writeback

    # xacro: the sources are edited (--write-back, or --in-place on xacro input)
    plan = writeback.write_back(args, result) if writeback.wants_write_back(args, result) \
        else None
    rewritten = 0
    # the library's one saving path: relocated references, atomic write, backup
    if args.in_place and plan is None:
        result.save(in_place=True)
    elif args.output is not None:
        rewritten = result.save(args.output,
                                keep_mesh_paths=args.keep_mesh_paths).references_rewritten
    if doc is not None:
        doc["mesh_references_rewritten"] = rewritten
        atomic_write_bytes(args.json, json.dumps(doc, indent=2).encode())
    if not args.quiet:
        from urdfinertia.render.table import fix_console, print_fix_table

        console = fix_console(stderr=args.output is None and not args.in_place
                              and plan is None)
        print_fix_table(result.links, f"{result.path}: {result.robot.name}", console)
        if plan is not None:
            writeback.print_summary(plan, console)
    _mass_summary(result, args.quiet)  # the robot's mass never changes silently
    if args.output is None and not args.in_place and plan is None:
        sys.stdout.buffer.write(result.output)  # a filter: -q only silences the table
    for line in problem_lines(result):
        print(f"urdf-inertia: warning: {line}", file=sys.stderr)
    if rewritten:
        print(f"urdf-inertia: {rewritten} relative mesh reference(s) rewritten to resolve "
              f"from {args.output.parent} (--keep-mesh-paths keeps them)", file=sys.stderr)
    left = left_lines(result)
    for line in left:
        print(f"urdf-inertia: left as it was: {line}", file=sys.stderr)
    if left:
        print(f"urdf-inertia: {len(left)} of {len(result.links)} links left as they were "
              "(exit 1)", file=sys.stderr)
    unread = unverified_line(result)
    if unread is not None:  # even with -q: the cause is otherwise only in --json
        print(f"urdf-inertia: {unread}; their links were not verified (exit 1)",
              file=sys.stderr)
    return max(fix_exit_code(len(left), len(result.unverified)),
               engine_regressions(args, result, options))


def _to_terminal(args: argparse.Namespace) -> bool:
    """Whether the fixed document would go to stdout and stdout is a terminal (as a
    filter, piped or redirected, stdout is where it belongs)."""
    if args.output is not None or args.in_place or getattr(args, "write_back", False) \
            or is_batch(args):
        return False
    try:
        return sys.stdout.isatty()
    except (AttributeError, ValueError):
        return False


def engine_regressions(args: argparse.Namespace, result, options) -> int:
    """``--engines``: load input and output in each engine; 1 if the output fares worse."""
    engines = engine_request(args)
    if engines is None:
        return 0
    from urdfinertia.engines.run import outcome_summary, regressions

    before = engines.outcomes(args.urdf, result.robot, options.package_dirs)
    after = engines.outcomes(args.urdf, result.robot, options.package_dirs,
                             data=result.output)
    for name, old in before.items():
        print(f"{args.urdf}: {name}: input {outcome_summary(old)}, output "
              f"{outcome_summary(after[name])}", file=sys.stderr)
    worse = regressions(before, after)
    for f in worse:
        print(f"{args.urdf}: {f.severity}: {f.message}", file=sys.stderr)
    return 1 if any(f.severity == "error" for f in worse) else 0


def _mass_summary(result, quiet: bool) -> None:
    from urdfinertia.render.console import output_console
    from urdfinertia.render.decisions import print_mass_summary

    print_mass_summary(result, output_console(stderr=True), quiet=quiet)


__all__ = ["add_arguments", "run", "UrdfInertiaError"]
