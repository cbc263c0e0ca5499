#!/usr/bin/env python
"""Benchmark: urdf-inertia over a URDF collection against a naive trimesh script.

Runs, in one invocation, each configuration in its own fresh child process (so that peak
memory and wall time of one do not leak into another), one after the other:

1. baseline: for every URDF, for every <collision> mesh reference, ``trimesh.load(path)``
   (default processing; a scene is concatenated) and ``.mass_properties``, no dedup;
2. the tool cold (empty cache) with 1 worker, and with ``--jobs`` workers;
3. the tool warm (cache filled by the previous run) with 1 worker and with ``--jobs``.

Wall time is the child's whole life (interpreter start, imports, work), the same way for
every row; "work" is the time inside the child from the start of the job to its end
(imports excluded), also for every row. Targets are checked on wall time. Peak memory is
``getrusage`` ``ru_maxrss``: RUSAGE_SELF of the child's main process and RUSAGE_CHILDREN
of its worker processes (the largest one), read after the pool has shut down. The
children run a snapshot of the package copied at the start, so edits made to the tree
meanwhile cannot mix two versions into one benchmark. Prints wall time, peak memory,
ratios to the baseline, a per-stage breakdown summed over processes, and checks that
every tool run wrote identical bytes.

With ``--against REF`` the cold and warm single-worker rows also run the package as it is
at git revision REF (a snapshot of ``src/urdfinertia`` taken with ``git archive``), in the
same invocation, and the table shows each beside the current code: the way to show that a
change made nothing slower.

Usage: python scripts/bench.py [--robots DIR] [--jobs 2] [--against REF]
(default DIR: example-robot-data's robots folder, a dev dependency).
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

TARGETS = {"cold, 1 worker": 0.5, "warm, 1 worker": 0.05, "warm, {jobs} workers": 0.05}
MEMORY_TARGET_MB = 2048


def example_robot_data() -> Path:
    for base in map(Path, sys.path):
        cand = base / "cmeel.prefix" / "share" / "example-robot-data" / "robots"
        if cand.is_dir():
            return cand
    sys.exit("example-robot-data is not installed: pip install -e '.[dev]'")


def peak_mb() -> tuple[float, float]:
    """(this process, largest reaped child) peak resident memory in MB (Linux: KiB units)."""
    unit = 1024 if sys.platform != "darwin" else 1
    kids = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss * unit / 2**20
    return own_peak_mb(), kids


def own_peak_mb() -> float:
    """This process's peak resident memory, MB.

    Linux's ``ru_maxrss`` survives ``exec``: a child spawned by a large parent starts with
    the parent's peak. ``VmHWM`` belongs to the process's own address space.
    """
    try:
        for line in Path("/proc/self/status").read_text().splitlines():
            if line.startswith("VmHWM:"):
                return int(line.split()[1]) / 1024
    except OSError:
        pass
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    return peak / 1024 if sys.platform != "darwin" else peak / 2**20



# ---------------------------------------------------------------------------- children

def child_baseline(robots: Path) -> dict:
    import trimesh
    from lxml import etree

    from urdfinertia.descriptions.paths import resolve_mesh_path
    from urdfinertia.errors import UrdfInertiaError

    start = time.perf_counter()
    refs = loaded = faces = failed = 0
    for urdf in [robots] if robots.is_file() else sorted(robots.rglob("*.urdf")):
        try:
            root = etree.parse(str(urdf), etree.XMLParser(resolve_entities=False)).getroot()
        except etree.XMLSyntaxError:
            failed += 1
            continue
        for mesh in root.iterfind("link/collision/geometry/mesh"):
            refs += 1
            try:
                path = resolve_mesh_path(mesh.get("filename", ""), urdf.parent)
                m = trimesh.load(str(path))
                if isinstance(m, trimesh.Scene):  # scene -> one mesh (dump/concatenate)
                    m = m.to_mesh() if hasattr(m, "to_mesh") else m.dump(concatenate=True)
                m.mass_properties  # noqa: B018 - the property computes the integrals
                faces += len(m.faces)
                loaded += 1
            except (UrdfInertiaError, ValueError, IndexError, KeyError, AttributeError):
                failed += 1
    work = time.perf_counter() - start
    own, kids = peak_mb()
    return {"work": work, "peak_main_mb": own, "peak_worker_mb": kids, "refs": refs,
            "loaded": loaded, "faces": faces, "failed": failed}


def child_tool(robots: Path, out: Path, jobs: int, cache_dir: Path) -> dict:
    try:
        from urdfinertia.batch.inputs import collect_jobs
        from urdfinertia.batch.run import BatchSettings, run_batch
        from urdfinertia.body.options import FixOptions
    except ImportError:  # a revision before the subpackage layout (--against)
        from urdfinertia.batch_inputs import collect_jobs  # type: ignore[no-redef]
        from urdfinertia.fix import FixOptions  # type: ignore[no-redef]

        from urdfinertia.batch import BatchSettings, run_batch  # type: ignore[no-redef]

    try:  # every link computed: the benchmark times the computation, not the policy
        options = FixOptions(recompute="all")
    except TypeError:  # a revision before the recompute policy (--against)
        options = FixOptions()
    start = time.perf_counter()
    report = run_batch(collect_jobs([robots], out), options,
                       BatchSettings(jobs=jobs, cache_dir=cache_dir))
    work = time.perf_counter() - start
    own, kids = peak_mb()
    import urdfinertia

    return {"work": work, "peak_main_mb": own, "peak_worker_mb": kids,
            "module": urdfinertia.__file__, "files": len(report.outcomes),
            "failed": len(report.failed),
            "errors": [o.error for o in report.failed],
            "meshes": report.meshes, "hits": report.cache_hits,
            "file_hits": report.file_hits,
            "misses": report.cache_misses, "stages": report.times.ordered()}


# ---------------------------------------------------------------------------- parent

def snapshot(dest: Path) -> Path:
    """Copy the package so that every child runs the same code, even if the tree changes.

    The copy is byte-compiled, as ``pip install`` compiles an installed package (and as
    the baseline's trimesh and numpy are): with ``PYTHONDONTWRITEBYTECODE`` set, as on
    these machines, a child would otherwise compile every module it imports, every run.
    """
    import compileall

    import urdfinertia

    shutil.copytree(Path(urdfinertia.__file__).parent, dest / "urdfinertia",
                    ignore=shutil.ignore_patterns("__pycache__"))
    compileall.compile_dir(dest / "urdfinertia", quiet=1)
    return dest


def snapshot_ref(ref: str, dest: Path) -> Path:
    """:func:`snapshot` of the package as it is at git revision ``ref``."""
    import compileall
    import io
    import tarfile

    root = Path(__file__).resolve().parents[1]
    data = subprocess.run(["git", "-C", str(root), "archive", "--format=tar", ref,
                           "src/urdfinertia"], capture_output=True, check=True).stdout
    with tarfile.open(fileobj=io.BytesIO(data)) as tar:
        tar.extractall(dest / "archive", filter="data")
    shutil.move(dest / "archive" / "src" / "urdfinertia", dest / "urdfinertia")
    compileall.compile_dir(dest / "urdfinertia", quiet=1)
    return dest


def run_child(args: list[str], code: Path, script: str = __file__) -> tuple[float, dict]:
    """Run ``script`` (this one by default) with ``args`` on the package at ``code``: its
    wall time and the JSON of its last line."""
    env = dict(os.environ, PYTHONPATH=str(code))
    start = time.perf_counter()
    proc = subprocess.run([sys.executable, script, *args], capture_output=True, text=True,
                          env=env)
    wall = time.perf_counter() - start
    if proc.returncode != 0:
        sys.exit(f"child {args} failed:\n{proc.stderr}")
    return wall, json.loads(proc.stdout.strip().splitlines()[-1])


def tree_bytes(folder: Path) -> dict[str, bytes]:
    return {str(p.relative_to(folder)): p.read_bytes() for p in sorted(folder.rglob("*.urdf"))}


def main() -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--robots", type=Path, help="folder of URDFs (default: example-robot-data)")
    p.add_argument("--jobs", type=int, default=2, help="workers of the parallel rows")
    p.add_argument("--against", metavar="REF",
                   help="also time the cold and warm 1-worker runs of git revision REF")
    p.add_argument("--child", choices=("baseline", "tool"), help=argparse.SUPPRESS)
    p.add_argument("--out", type=Path, help=argparse.SUPPRESS)
    p.add_argument("--cache-dir", type=Path, help=argparse.SUPPRESS)
    args = p.parse_args()
    robots = args.robots or example_robot_data()
    if args.child == "baseline":
        print(json.dumps(child_baseline(robots)))
        return 0
    if args.child == "tool":
        print(json.dumps(child_tool(robots, args.out, args.jobs, args.cache_dir)))
        return 0

    n = args.jobs
    print(f"collection: {robots} ({len(list(robots.rglob('*.urdf')))} URDFs)")
    print(f"machine: {os.cpu_count()} CPUs; python {sys.version.split()[0]}")
    rows: list[tuple[str, float, dict]] = []
    with tempfile.TemporaryDirectory(prefix="urdfinertia-bench-") as tmp:
        t = Path(tmp)
        code = snapshot(t / "code")
        wall, res = run_child(["--child", "baseline", "--robots", str(robots)], code)
        rows.append(("naive baseline", wall, res))
        print(f"baseline: {res['refs']} collision mesh references, {res['loaded']} loaded "
              f"({res['faces']:,} faces), {res['failed']} failed; {wall:.1f} s")
        plan = [
            ("cold, 1 worker", 1, "cache-1", "out-cold-1"),
            (f"cold, {n} workers", n, "cache-n", "out-cold-n"),
            ("warm, 1 worker", 1, "cache-n", "out-warm-1"),
            (f"warm, {n} workers", n, "cache-n", "out-warm-n"),
        ]
        for name, jobs, cache, out in plan:
            wall, res = run_child(["--child", "tool", "--robots", str(robots), "--jobs",
                                   str(jobs), "--cache-dir", str(t / cache),
                                   "--out", str(t / out)], code)
            assert res["module"].startswith(str(code)), res["module"]
            rows.append((name, wall, res))
            print(f"{name}: {wall:.1f} s")
        trees = [tree_bytes(t / out) for *_, out in plan]
        identical = all(tr == trees[0] for tr in trees[1:])
        against = []
        if args.against:
            old = snapshot_ref(args.against, t / "old-code")
            for name, cache, out in [("cold, 1 worker", "cache-old", "out-old-cold"),
                                     ("warm, 1 worker", "cache-old", "out-old-warm")]:
                wall, res = run_child(["--child", "tool", "--robots", str(robots), "--jobs",
                                       "1", "--cache-dir", str(t / cache),
                                       "--out", str(t / out)], old)
                assert res["module"].startswith(str(old)), res["module"]
                against.append((f"{name} [{args.against}]", wall, res))
                print(f"{name} [{args.against}]: {wall:.1f} s")
            same_as_old = tree_bytes(t / "out-old-cold") == trees[0]
    base = rows[0][1]
    base_work = rows[0][2]["work"]
    print()
    print("| run | wall s | work s | x baseline (wall) | target | x baseline (work) | "
          "peak main MB | peak worker MB |")
    print("|---|---:|---:|---:|---:|---:|---:|---:|")
    for name, wall, res in rows:
        target = TARGETS.get(name.replace(f"{n} workers", "{jobs} workers"))
        mark = "" if target is None else (f"<= {target}" + (" ok" if wall / base <= target
                                                            else " MISSED"))
        print(f"| {name} | {wall:.2f} | {res['work']:.2f} | {wall / base:.3f} | {mark} | "
              f"{res['work'] / base_work:.3f} | {res['peak_main_mb']:.0f} | "
              f"{res['peak_worker_mb']:.0f} |")
    if against:
        now = {name: (wall, res) for name, wall, res in rows}
        print(f"\nthis checkout beside {args.against}, measured in this run:\n")
        print("| run | this checkout wall s | " + args.against + " wall s | ratio | "
              "this checkout work s | " + args.against + " work s |")
        print("|---|---:|---:|---:|---:|---:|")
        for name, wall, res in against:
            plain = name.split(" [")[0]
            w_now, r_now = now[plain]
            print(f"| {plain} | {w_now:.2f} | {wall:.2f} | {w_now / wall:.2f} | "
                  f"{r_now['work']:.2f} | {res['work']:.2f} |")
        print(f"outputs identical to {args.against}'s: {'yes' if same_as_old else 'NO'}")
    worst = max(r["peak_main_mb"] + n * r["peak_worker_mb"] for _, _, r in rows[1:])
    print(f"\npeak memory bound (main + {n} x largest worker): {worst:.0f} MB "
          f"(target < {MEMORY_TARGET_MB}: {'ok' if worst < MEMORY_TARGET_MB else 'MISSED'})")
    tool = rows[1][2]
    warm = rows[3][2]
    print(f"tool: {tool['files']} files, {tool['meshes']} distinct meshes, "
          f"{tool['failed']} files failed; warm run: {warm['file_hits']} files reused whole, "
          f"{warm['meshes']} meshes looked up ({warm['hits']} hits)")
    print(f"identical outputs across all tool runs: {'yes' if identical else 'NO'}")
    stage_names = list(dict.fromkeys(s for _, _, r in rows[1:] for s, _ in r["stages"]))
    print("\nper-stage wall time, seconds summed over processes:\n")
    print("| stage | " + " | ".join(name for name, _, _ in rows[1:]) + " |")
    print("|---|" + "---:|" * (len(rows) - 1))
    for stage in stage_names:
        cells = [f"{dict(r['stages']).get(stage, 0.0):.2f}" for _, _, r in rows[1:]]
        print(f"| {stage} | " + " | ".join(cells) + " |")
    if tool["errors"]:
        print("\nfiles the tool refused (reported, run continued):")
        for e in tool["errors"]:
            print(f"  {e[:200]}")
    return 0 if identical else 1


if __name__ == "__main__":
    sys.exit(main())
