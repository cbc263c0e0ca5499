"""Command-line side of batch runs: options, progress bar and summary for ``fix``.

``urdf-inertia fix`` calls :func:`run_many` when given several inputs or a folder; the work
itself is :mod:`urdfinertia.batch`.
"""

from __future__ import annotations

import argparse
import json
import os
import sys
from pathlib import Path
from typing import TYPE_CHECKING, Any, TextIO

from urdfinertia.atomic import atomic_write_bytes
from urdfinertia.batch.inputs import collect_jobs
from urdfinertia.batch.run import BatchReport, BatchSettings, prepared_library, run_batch
from urdfinertia.body.options import FixOptions
from urdfinertia.cache.store import DEFAULT_MAX_BYTES, ENV_VAR
from urdfinertia.cli.options import positive_int
from urdfinertia.errors import OutputError
from urdfinertia.mesh.limits import BUDGET_ENV_VAR, DEFAULT_MESH_SECONDS
from urdfinertia.timing import StageTimes

if TYPE_CHECKING:
    from rich.console import Console
    from rich.table import Table

    from urdfinertia.cache.library import MeshLibrary

# rich is imported only to show something: a progress bar on a terminal, a table.


def add_batch_arguments(p: argparse.ArgumentParser) -> None:
    g = p.add_argument_group("speed: workers, cache, cluster")
    g.add_argument("-j", "--jobs", type=positive_int, default=None, metavar="N",
                   help="worker processes (default: the cores this process may use, "
                        f"now {available_cores()})")
    g.add_argument("--mesh-seconds", type=float, metavar="S",
                   help="CPU seconds a mesh's repair may spend on refined hole caps before it "
                        "caps them with fans and widens the stated error (default "
                        f"{DEFAULT_MESH_SECONDS:g}; 0: no limit); also "
                        f"${BUDGET_ENV_VAR}")
    g.add_argument("--no-cache", action="store_true",
                   help="neither read nor write the persistent mesh cache")
    g.add_argument("--cache-dir", type=Path, metavar="DIR",
                   help=f"mesh cache folder (default: ${ENV_VAR} or the user cache folder)")
    g.add_argument("--cache-max-mb", type=positive_int, default=DEFAULT_MAX_BYTES >> 20,
                   metavar="MB", help="size bound of the cache; least recently used entries "
                                      f"are deleted beyond it (default {DEFAULT_MAX_BYTES >> 20})")
    g.add_argument("--dask", metavar="ADDRESS",
                   help="run on a Dask distributed scheduler, e.g. tcp://host:8786 (workers "
                        "must see the same files; needs pip install 'urdfinertia[dask]')")
    g.add_argument("--timings", action="store_true",
                   help="print the wall time of each stage on stderr")


def available_cores() -> int:
    """Cores this process may run on (its CPU affinity where the system has one)."""
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except (AttributeError, OSError):
        return max(1, os.cpu_count() or 1)


def settings_from_args(args: argparse.Namespace) -> BatchSettings:
    # getattr: other commands reuse this with parsers that lack some of the options
    seconds = getattr(args, "mesh_seconds", None)
    if seconds is not None:  # the environment carries it to worker processes
        os.environ[BUDGET_ENV_VAR] = repr(float(seconds))
    jobs = getattr(args, "jobs", 1)
    return BatchSettings(
        jobs=jobs if jobs is not None else available_cores(),
        use_cache=not getattr(args, "no_cache", False),
        cache_dir=getattr(args, "cache_dir", None),
        cache_max_bytes=getattr(args, "cache_max_mb", DEFAULT_MAX_BYTES >> 20) << 20,
        dask=getattr(args, "dask", None),
        in_place=bool(getattr(args, "in_place", False)),
        details=getattr(args, "json", None) is not None,
        keep_mesh_paths=bool(getattr(args, "keep_mesh_paths", False)),
    )


def is_batch(args: argparse.Namespace) -> bool:
    """Several inputs, a folder, or -o naming an existing folder."""
    out = getattr(args, "output", None)
    return (bool(getattr(args, "more", None)) or args.urdf.is_dir()
            or (out is not None and out.is_dir()))


def may_be_terminal(stream: TextIO) -> bool:
    """False when rich would certainly not treat ``stream`` as a terminal (its own test
    also reads ``TTY_COMPATIBLE`` and ``FORCE_COLOR``): then rich need not be imported."""
    if os.environ.get("TTY_COMPATIBLE", "") == "1" or os.environ.get("FORCE_COLOR"):
        return True
    try:
        return stream.isatty()
    except (AttributeError, ValueError):
        return False


class ProgressBar:
    """A rich progress bar on stderr; silent when stderr is not a terminal or with -q."""

    def __init__(self, quiet: bool) -> None:
        self.progress: Any = None
        self.tasks: dict[str, int] = {}
        if quiet or not may_be_terminal(sys.stderr):
            return
        from rich.console import Console
        from rich.progress import (
            BarColumn,
            MofNCompleteColumn,
            Progress,
            TextColumn,
            TimeElapsedColumn,
        )

        console = Console(stderr=True)
        if console.is_terminal:
            self.progress = Progress(
                TextColumn("{task.description}"), BarColumn(), MofNCompleteColumn(),
                TimeElapsedColumn(), console=console, auto_refresh=False,
                redirect_stdout=False, redirect_stderr=False,
            )

    def __enter__(self) -> ProgressBar:
        if self.progress is not None:
            self.progress.start()
        return self

    def __exit__(self, *exc: object) -> None:
        if self.progress is not None:
            self.progress.stop()

    def __call__(self, kind: str, done: int, total: int) -> None:
        if self.progress is None:
            return
        if kind not in self.tasks:
            self.tasks[kind] = self.progress.add_task(kind, total=total)
        self.progress.update(self.tasks[kind], completed=done, total=total, refresh=True)


def stderr_console() -> Console:
    from urdfinertia.render.console import output_console

    return output_console(stderr=True)


def single_file_library(args: argparse.Namespace, options: FixOptions,
                        urdfs: list[Path] | None = None) -> MeshLibrary:
    """The mesh library for a one-file run, or a run over ``urdfs`` (default
    ``args.urdf``), with the meshes computed in parallel with --jobs/--dask."""
    from urdfinertia.cache.library import mesh_library

    settings = settings_from_args(args)
    if settings.jobs > 1 or settings.dask:
        with ProgressBar(getattr(args, "quiet", False)) as bar:
            return prepared_library(urdfs if urdfs is not None else [args.urdf], options,
                                    settings, settings.open_cache(), bar)
    return mesh_library(options.package_dirs, options.max_faces, use_cache=settings.use_cache,
                        cache_dir=settings.cache_dir, cache_max_bytes=settings.cache_max_bytes)


def finish_single(args: argparse.Namespace, meshes: MeshLibrary) -> None:
    """After a one-file run: keep the cache within its bound, report cache problems."""
    if meshes.cache is not None:
        meshes.cache.prune()
        for w in meshes.cache.warnings:
            print(f"urdf-inertia: warning: {w}", file=sys.stderr)
    if getattr(args, "timings", False):
        from rich.console import Console

        print_timings(meshes.timer, Console(stderr=True))


def run_many(args: argparse.Namespace, options: FixOptions) -> int:
    """``fix A.urdf B.urdf DIR -o OUTDIR``: every file, errors reported at the end."""
    inputs = [args.urdf, *args.more]
    if args.output is None and not args.in_place:
        raise OutputError("several inputs or a folder: give -o FOLDER or --in-place")
    if args.output is not None and args.output.exists() and not args.output.is_dir():
        raise OutputError("with several inputs or a folder, -o must be a folder",
                          file=args.output)
    jobs = collect_jobs(inputs, None if args.in_place else args.output)
    settings = settings_from_args(args)
    with ProgressBar(args.quiet) as bar:
        report = run_batch(jobs, options, settings, bar)
    if not args.quiet:
        stderr_console().print(summary_table(report))
    if args.timings:
        print_timings(report.times, stderr_console())
    code = batch_exit_code(report)
    if args.json is not None:
        doc = {"exit_code": code, "files": [
            _file_json(o, up) for o, up in zip(report.outcomes, _up_to_date(report),
                                               strict=True)]}
        atomic_write_bytes(args.json, json.dumps(doc, indent=2).encode())
    for w in report.warnings:
        print(f"urdf-inertia: warning: {w}", file=sys.stderr)
    for o in report.outcomes:
        if o.error is None:
            for line in o.problems:
                print(f"urdf-inertia: warning: {line}", file=sys.stderr)
            for line in o.left:
                print(f"urdf-inertia: left as it was: {line}", file=sys.stderr)
    for o in report.failed:
        print(f"urdf-inertia: error: {o.error}", file=sys.stderr)
    partial = [o for o in report.outcomes if o.error is None and o.left]
    rewritten = sum(o.rewritten for o in report.outcomes)
    if rewritten:
        print(f"urdf-inertia: {rewritten} relative mesh reference(s) rewritten to resolve "
              "from the output folder (--keep-mesh-paths keeps them)", file=sys.stderr)
    written = sum(o.error is None for o in report.outcomes)
    untouched = (f"; {report.untouched} of them already held these bytes and were left "
                 "untouched" if report.untouched else "")
    print(f"urdf-inertia: {len(report.outcomes)} files: {written} written "
          f"({len(partial)} with links left as they were: "
          f"{sum(len(o.left) for o in partial)} links{untouched}), "
          f"{len(report.failed)} failed", file=sys.stderr)
    return code


def _up_to_date(report: BatchReport) -> tuple[bool, ...]:
    """Per outcome: its output already held these bytes (a report built without it: no)."""
    return report.up_to_date or (False,) * len(report.outcomes)


def batch_exit_code(report: BatchReport) -> int:
    """2 when a file failed (nothing written for it), else 1 when a written file has links
    left as they were, else 0 (:mod:`urdfinertia.cli.outcome`)."""
    from urdfinertia.cli.outcome import EXIT_NOTHING_WRITTEN, fix_exit_code

    if report.failed:
        return EXIT_NOTHING_WRITTEN
    return fix_exit_code(sum(len(o.left) for o in report.outcomes))


def _file_json(o, up_to_date: bool) -> dict:  # noqa: ANN001 - a FileOutcome
    doc = dict(o.details) if o.details is not None else {"file": str(o.source)}
    if o.error is not None:
        doc["error"] = o.error
    doc["left_as_they_were"] = list(o.left)
    doc["problems"] = list(o.problems)
    doc["mesh_references_rewritten"] = o.rewritten
    doc["output_up_to_date"] = up_to_date
    return doc


def summary_table(report: BatchReport) -> Table:
    from rich.table import Table

    table = Table(title=f"{len(report.outcomes)} files ({report.file_hits} unchanged since a "
                        f"cached run), {report.meshes} distinct meshes computed or read from "
                        f"the cache ({report.cache_hits} hits, {report.cache_misses} misses)")
    for col in ("file", "robot", "links recomputed", "left", "warnings", "result"):
        table.add_column(col, overflow="fold")
    cwd = Path.cwd()
    for o, up_to_date in zip(report.outcomes, _up_to_date(report), strict=True):
        name = os.path.relpath(o.source, cwd) if o.source.is_absolute() else str(o.source)
        if o.error is not None:
            table.add_row(name, o.robot, "-", "-", "-", "[red]failed[/red]")
            continue
        result = str(o.output) if o.output is not None else "-"
        if up_to_date:
            result += " (up to date, untouched)"
        table.add_row(name, o.robot, f"{o.recomputed}/{o.links}",
                      f"[yellow]{len(o.left)}[/yellow]" if o.left else "0",
                      str(len(o.warnings) + len(o.problems)),
                      result if o.changed or o.output is not None else "unchanged")
    return table


def print_timings(times: StageTimes, console: Console) -> None:
    from rich.table import Table

    table = Table(title="wall time per stage (summed over processes)")
    table.add_column("stage")
    table.add_column("seconds", justify="right")
    for name, seconds in times.ordered():
        table.add_row(name, f"{seconds:.2f}")
    table.add_row("total", f"{times.total():.2f}")
    console.print(table)
