#!/usr/bin/env python
"""Speed of the whole tool against a naive integral loop, side by side in one run.

Rows, each in a fresh child process running a snapshot of the package taken at the start
(so edits meanwhile cannot mix versions), one after the other over one robots folder
(default: example-robot-data's):

1. naive: lxml plus ``trimesh.load(...).mass_properties`` per collision mesh, no repair,
   one process (:func:`bench.child_baseline`);
2. ``urdf-inertia fix DIR -o OUT --all`` cold (private, empty mesh cache), default ``-j``;
3. the same, warm (the cache the cold run filled);
4. with ``--against REF``: the cold and warm rows again with the package of git revision
   REF, and whether both wrote the same bytes;
5. the slowest robot of the folder (most repair time, from a per-mesh timing of every
   mesh ``fix --all`` reads, whose ten slowest meshes are printed): ``fix`` cold, then
   ``check`` twice on a private cache (the second reads what the first stored), then
   ``report`` (time and HTML size) cold, after the fix (its cache), and once more.

Wall time is the child's whole life (interpreter start, imports, work). Peak memory is
the child's own high-water mark plus its largest worker's (Linux ``VmHWM`` and
``RUSAGE_CHILDREN``). Ratios are to the naive row of the same run: the machine may be
shared, so the load average is printed at the start and the end.

Usage: python scripts/bench_speed.py [--robots DIR] [--against REF] [--robot FILE]
                                     [--robot-only]
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
import bench  # noqa: E402 - the naive loop, snapshots and peak memory live there

TARGETS = {"cold": 1.0, "warm": 0.05}
ROBOT_COLD_S = 5.0
SECOND_CHECK_S = 2.0
REPORT_S = 15.0
REPORT_MB = 5.0
MEMORY_MB = 500.0


# ---------------------------------------------------------------------------- children

def child_cli(argv: list[str], cache_dir: Path) -> dict:
    """Run ``urdf-inertia ARGV`` in this process with the mesh cache in ``cache_dir``."""
    import contextlib
    import io

    os.environ["URDFINERTIA_CACHE_DIR"] = str(cache_dir)
    from urdfinertia.cli import main

    start = time.perf_counter()
    with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(io.StringIO()):
        code = main(argv)
    work = time.perf_counter() - start
    own, kids = bench.peak_mb()
    import urdfinertia

    return {"work": work, "code": code, "peak_main_mb": own, "peak_worker_mb": kids,
            "module": urdfinertia.__file__}


def child_meshes(robots: Path) -> dict:
    """Seconds to read, repair and integrate each distinct mesh ``fix --all`` reads, and
    which description files use it."""
    from urdfinertia.batch.inputs import collect_jobs
    from urdfinertia.batch.tasks import referenced_meshes
    from urdfinertia.cache.library import integrate_mesh
    from urdfinertia.link.options import FixOptions
    from urdfinertia.mesh.read.load import load_mesh

    options = FixOptions(recompute="all")
    users: dict[Path, list[str]] = {}
    for job in collect_jobs([robots], None):
        for path in referenced_meshes(job.source, options):
            users.setdefault(path, []).append(str(job.source))
    costs = []
    for path, files in users.items():
        start = time.perf_counter()
        faces = 0
        try:
            mesh = load_mesh(path, options.max_faces)
            faces = len(mesh.faces)
            solids = integrate_mesh(mesh)
            notes = "; ".join(solids.notes)
        except Exception as exc:  # noqa: BLE001 - a refused mesh is timed too
            notes = f"error: {exc}"
        costs.append({"mesh": str(path), "faces": faces, "seconds":
                      time.perf_counter() - start, "files": files, "notes": notes[:160]})
    return {"costs": costs}


# ---------------------------------------------------------------------------- parent

def run_child(args: list[str], code: Path) -> tuple[float, dict]:
    """This script as a child on the package at ``code`` (checked to be the one loaded)."""
    wall, res = bench.run_child(args, code, __file__)
    if "module" in res:
        assert res["module"].startswith(str(code)), res["module"]
    return wall, res


def cli(code: Path, cache: Path, *argv: str) -> tuple[float, dict]:
    return run_child(["--child", "cli", "--cache-dir", str(cache), "--", *argv], code)


def tree_bytes(folder: Path) -> dict[str, bytes]:
    return {str(p.relative_to(folder)): p.read_bytes() for p in sorted(folder.rglob("*"))
            if p.is_file()}


def load() -> str:
    return " ".join(f"{x:.2f}" for x in os.getloadavg())


def verdict(value: float, target: float) -> str:
    return f"<= {target:g} " + ("ok" if value <= target else "MISSED")


def main() -> int:
    argv = sys.argv[1:]
    rest: list[str] = []
    if "--" in argv:
        cut = argv.index("--")
        argv, rest = argv[:cut], argv[cut + 1:]
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--robots", type=Path, help="folder of descriptions "
                                               "(default: example-robot-data's robots)")
    p.add_argument("--against", metavar="REF", help="also run cold and warm with revision REF")
    p.add_argument("--robot", type=Path, help="the single robot of rows 5 (default: the "
                                              "slowest of the folder)")
    p.add_argument("--robot-only", action="store_true",
                   help="only the single-robot rows (with --robot)")
    p.add_argument("--child", choices=("baseline", "cli", "meshes"), help=argparse.SUPPRESS)
    p.add_argument("--cache-dir", type=Path, help=argparse.SUPPRESS)
    args = p.parse_args(argv)
    robots = args.robots or bench.example_robot_data()
    if args.child == "baseline":
        print(json.dumps(bench.child_baseline(robots)))
        return 0
    if args.child == "cli":
        print(json.dumps(child_cli(rest, args.cache_dir)))
        return 0
    if args.child == "meshes":
        print(json.dumps(child_meshes(robots)))
        return 0

    print(f"collection: {robots}")
    print(f"machine: {os.cpu_count()} CPUs, {len(os.sched_getaffinity(0))} usable; "
          f"load average at start {load()}")
    with tempfile.TemporaryDirectory(prefix="urdfinertia-bench-speed-") as tmp:
        t = Path(tmp)
        code = bench.snapshot(t / "code")
        if args.robot_only:
            if args.robot is None:
                sys.exit("--robot-only needs --robot FILE")
            robot_rows(code, t, args.robot)
            print(f"\nload average at end {load()}")
            return 0
        rows: list[tuple[str, float, dict]] = []
        wall, res = run_child(["--child", "baseline", "--robots", str(robots)], code)
        rows.append(("naive loop", wall, res))
        print(f"naive: {res['refs']} collision mesh references, {res['loaded']} loaded; "
              f"{wall:.1f} s", flush=True)
        versions = [("this checkout", code)]
        if args.against:
            versions.append((args.against, bench.snapshot_ref(args.against, t / "old")))
        outs = {}
        for label, src in versions:
            cache = t / f"cache-{len(outs)}"
            for kind in ("cold", "warm"):
                out = t / f"out-{len(outs)}-{kind}"
                wall, res = cli(src, cache, "fix", str(robots), "-o", str(out), "--all", "-q")
                rows.append((f"fix --all {kind} [{label}]", wall, res))
                outs[(label, kind)] = out
                print(f"fix --all {kind} [{label}]: {wall:.1f} s", flush=True)
        base = rows[0][1]
        print("\n| run | wall s | x naive | target | peak main MB | peak worker MB |")
        print("|---|---:|---:|---:|---:|---:|")
        for name, wall, res in rows:
            kind = "cold" if " cold " in name else "warm" if " warm " in name else None
            target = (verdict(wall / base, TARGETS[kind])
                      if kind and "this checkout" in name else "")
            print(f"| {name} | {wall:.2f} | {wall / base:.3f} | {target} | "
                  f"{res['peak_main_mb']:.0f} | {res['peak_worker_mb']:.0f} |")
        cold = dict((n, r) for n, _, r in rows)["fix --all cold [this checkout]"]
        peak = cold["peak_main_mb"] + cold["peak_worker_mb"] * max(
            1, len(os.sched_getaffinity(0)))
        print(f"\npeak memory of the cold corpus run (main + workers x largest): {peak:.0f} MB "
              f"({verdict(peak, MEMORY_MB)})")
        same = tree_bytes(outs[("this checkout", "cold")]) == tree_bytes(
            outs[("this checkout", "warm")])
        print(f"cold and warm outputs identical: {'yes' if same else 'NO'}")
        if args.against:
            same = tree_bytes(outs[("this checkout", "cold")]) == tree_bytes(
                outs[(args.against, "cold")])
            print(f"outputs identical to {args.against}'s: {'yes' if same else 'NO'}")

        _, res = run_child(["--child", "meshes", "--robots", str(robots)], code)
        costs = sorted(res["costs"], key=lambda c: -c["seconds"])
        print("\nten slowest meshes (read + repair + integrate, one process, "
              f"{len(costs)} meshes, {sum(c['seconds'] for c in costs):.1f} s in all):\n")
        print("| s | faces | mesh | notes |")
        print("|---:|---:|---|---|")
        for c in costs[:10]:
            print(f"| {c['seconds']:.2f} | {c['faces']} | {Path(c['mesh']).name} | "
                  f"{c['notes']} |")
        per_file: dict[str, float] = {}
        for c in costs:
            for f in set(c["files"]):
                per_file[f] = per_file.get(f, 0.0) + c["seconds"]
        robot = args.robot or Path(max(per_file, key=per_file.__getitem__))
        print(f"\nslowest robot: {robot} ({per_file.get(str(robot), 0.0):.1f} s of meshes)")
        robot_rows(code, t, robot)
    print(f"\nload average at end {load()}")
    return 0


def robot_rows(code: Path, t: Path, robot: Path) -> None:
    """fix cold and warm, check twice, report cold and after fix, on one robot."""
    cache = t / "cache-robot"
    wall, _ = cli(code, cache, "fix", str(robot), "-o", str(t / "robot.urdf"), "-q")
    print(f"fix cold: {wall:.2f} s ({verdict(wall, ROBOT_COLD_S)})")
    wall, _ = cli(code, cache, "fix", str(robot), "-o", str(t / "robot2.urdf"), "-q")
    print(f"fix warm: {wall:.2f} s")
    check_cache = t / "cache-check"
    first, _ = cli(code, check_cache, "check", str(robot), "-q")
    second, _ = cli(code, check_cache, "check", str(robot), "-q")
    print(f"check: first {first:.2f} s (empty cache), second {second:.2f} s "
          f"({verdict(second, SECOND_CHECK_S)})")
    for label, where in (("cold", t / "cache-report"), ("after fix", cache),
                         ("again", cache)):
        html = t / f"report-{where.name}.html"
        wall, res = cli(code, where, "report", str(robot), "-o", str(html))
        size = html.stat().st_size / 2**20 if html.exists() else float("nan")
        print(f"report {label}: {wall:.2f} s ({verdict(wall, REPORT_S)}), {size:.2f} MB "
              f"({verdict(size, REPORT_MB)}), peak {res['peak_main_mb']:.0f} MB")


if __name__ == "__main__":
    sys.exit(main())
