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
   mesh ``fix --all`` reads, whose ten slowest meshes are printed): the naive loop over
   its own collision meshes, ``fix`` and ``fix --all`` cold (each against it), then
   ``check`` twice on a private cache (the second reads what the first stored), then
   ``report`` (time and HTML size) cold, after the fix (its cache), and once more.

Wall time is the child's whole life (interpreter start, imports, work). Memory and CPU
of the child's process tree are sampled from this process every 50 ms (a sampling
thread in the child would make the command start its workers by forkserver, not fork,
as it never does for a user): each process's peak and the peak of their sum. Ratios are
to the naive row of the same run: the machine may be shared, so the load average is
printed at the start and the end.

Usage: python scripts/bench_speed.py [--robots DIR] [--against REF] [--robot FILE]
                                     [--robot-only]
(--robot-only --against REF: the single-robot rows for both versions, in one run)
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
#: proposed: a single robot's cold fix within this multiple of the naive loop over its
#: own collision meshes (the absolute 5 s depends on the robot and the machine)
ROBOT_X_NAIVE = 3.0
SECOND_CHECK_S = 2.0
REPORT_S = 15.0
REPORT_MB = 5.0
MEMORY_MB = 500.0


# ---------------------------------------------------------------------------- children

class TreeMemory:
    """Peak resident memory of this process and its descendants (worker processes),
    sampled every ``interval`` seconds from ``/proc``: each process's own peak and the
    peak of their sum (the whole run's footprint). Linux only; empty elsewhere."""

    def __init__(self, interval: float = 0.05, root: int | None = None) -> None:
        import threading

        self.interval = interval
        #: the process whose tree is sampled (default: this one)
        self.root = os.getpid() if root is None else root
        self.per_pid: dict[int, float] = {}
        #: CPU seconds (user + system) last seen of each process of the tree: workers
        #: started by a fork server are not this process's children, so getrusage's
        #: RUSAGE_CHILDREN misses them
        self.cpu: dict[int, float] = {}
        #: parent of each process seen in the tree
        self.parent: dict[int, int] = {}
        self.total = 0.0
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._run, daemon=True)

    def __enter__(self) -> TreeMemory:
        self._thread.start()
        return self

    def __exit__(self, *exc: object) -> None:
        self._stop.set()
        self._thread.join()

    def _run(self) -> None:
        while not self._stop.is_set():
            self.sample()
            self._stop.wait(self.interval)

    def sample(self) -> None:
        me = self.root
        children: dict[int, list[int]] = {}
        rss: dict[int, float] = {}
        try:
            pids = [int(d) for d in os.listdir("/proc") if d.isdigit()]
        except OSError:
            return
        for pid in pids:
            try:
                text = Path(f"/proc/{pid}/status").read_text()
            except OSError:
                continue
            fields = dict(line.split(":", 1) for line in text.splitlines() if ":" in line)
            children.setdefault(int(fields.get("PPid", "0").strip() or 0), []).append(pid)
            rss[pid] = int(fields.get("VmRSS", "0 kB").split()[0] or 0) / 1024
        tree, todo = [], [me]
        while todo:
            pid = todo.pop()
            tree.append(pid)
            for kid in children.get(pid, []):
                self.parent[kid] = pid
                todo.append(kid)
        total = 0.0
        tick = os.sysconf("SC_CLK_TCK")
        for pid in tree:
            try:
                stat = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()
                self.cpu[pid] = (int(stat[11]) + int(stat[12])) / tick  # utime, stime
            except (OSError, IndexError, ValueError):
                pass
            mb = rss.get(pid, 0.0)
            total += mb
            self.per_pid[pid] = max(self.per_pid.get(pid, 0.0), mb)
        self.total = max(self.total, total)


def child_cli(argv: list[str], cache_dir: Path) -> dict:
    """Run ``urdf-inertia ARGV`` in this process with the mesh cache in ``cache_dir``."""
    import contextlib
    import io

    os.environ["URDFINERTIA_CACHE_DIR"] = str(cache_dir)
    from urdfinertia.cli import main

    start = time.perf_counter()
    # no sampling thread here: with a thread running, the command would start its workers
    # by forkserver instead of fork, as it never does for a user (the parent samples)
    with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(io.StringIO()):
        code = main(argv)
    work = time.perf_counter() - start
    own, kids = bench.peak_mb()
    import urdfinertia

    return {"work": work, "code": code, "peak_main_mb": own, "peak_worker_mb": kids,
            "cpu": cpu_seconds(), "module": urdfinertia.__file__}


def cpu_seconds() -> float:
    """User + system CPU seconds of this process and its reaped children: less sensitive
    than wall time to other jobs on a shared machine (workers under a fork server are
    added from :class:`TreeMemory`'s samples, to within its 50 ms period)."""
    import resource

    own = resource.getrusage(resource.RUSAGE_SELF)
    kids = resource.getrusage(resource.RUSAGE_CHILDREN)
    return own.ru_utime + own.ru_stime + kids.ru_utime + kids.ru_stime


def child_meshes(robots: Path) -> dict:
    """Seconds to read, repair and integrate each distinct mesh ``fix --all`` reads (by
    stage), and which description files use it; and the seconds of the hull points
    the geometry checks read of every checked mesh (collision and visual)."""
    from urdfinertia.batch.inputs import collect_jobs
    from urdfinertia.batch.tasks import mesh_needs
    from urdfinertia.body.options import FixOptions
    from urdfinertia.cache.library import integrate_mesh, points_of
    from urdfinertia.mesh.read.load import load_mesh
    from urdfinertia.timing import StageTimes

    options = FixOptions(recompute="all")
    users: dict[Path, list[str]] = {}
    checked: dict[Path, None] = {}
    for job in collect_jobs([robots], None):
        solids, points = mesh_needs(job.source, options)
        for path in solids:
            users.setdefault(path, []).append(str(job.source))
        checked.update(dict.fromkeys(points))
    costs = []
    for path in dict.fromkeys([*users, *checked]):
        start = time.perf_counter()
        faces = 0
        times = StageTimes()
        try:
            with times.stage("mesh read"):
                mesh = load_mesh(path, options.max_faces)
            faces = len(mesh.faces)
            with times.stage("hull points"):
                points_of(mesh)
            notes = ""
            if path in users:
                solids = integrate_mesh(mesh, times)
                notes = "; ".join(solids.notes)
        except Exception as exc:  # noqa: BLE001 - a refused mesh is timed too
            notes = f"error: {exc}"
        costs.append({"mesh": str(path), "faces": faces, "seconds":
                      time.perf_counter() - start, "files": users.get(path, []),
                      "integrated": path in users, "stages": dict(times.seconds),
                      "united": "overlapping bodies into" in notes,
                      "notes": notes[:160]})
    return {"costs": costs}


# ---------------------------------------------------------------------------- parent

def run_child(args: list[str], code: Path) -> tuple[float, dict]:
    """This script as a child on the package at ``code`` (checked to be the one loaded),
    its process tree (the child and its workers) sampled from here: per process peaks
    (``workers_mb``), the peak of their sum (``tree_mb``), and CPU seconds of workers
    that are not the child's own children (a fork server's)."""
    import subprocess

    env = dict(os.environ, PYTHONPATH=str(code))
    start = time.perf_counter()
    proc = subprocess.Popen([sys.executable, __file__, *args], stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True, env=env)
    with TreeMemory(root=proc.pid) as memory:
        out, err = proc.communicate()
    wall = time.perf_counter() - start
    if proc.returncode != 0:
        sys.exit(f"child {args} failed:\n{err}")
    res = json.loads(out.strip().splitlines()[-1])
    if "module" in res:
        assert res["module"].startswith(str(code)), res["module"]
    res["workers_mb"] = sorted((mb for pid, mb in memory.per_pid.items() if pid != proc.pid),
                               reverse=True)
    res["tree_mb"] = memory.total
    # workers of a fork server are not reaped by the child: their CPU is added here
    res["cpu"] = res.get("cpu", 0.0) + sum(
        c for pid, c in memory.cpu.items()
        if pid != proc.pid and memory.parent.get(pid) != proc.pid)
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


def read_all(folder: Path) -> int:
    """Read every file under ``folder`` once (into the page cache); the bytes read."""
    total = 0
    for path in sorted(folder.rglob("*")):
        if path.is_file():
            with open(path, "rb") as f:
                while chunk := f.read(1 << 20):
                    total += len(chunk)
    return total


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
        print(json.dumps({**bench.child_baseline(robots), "cpu": cpu_seconds()}))
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
            print(f"\nrobot: {args.robot} [this checkout]")
            robot_rows(code, t / "now", args.robot)
            if args.against:
                print(f"\nrobot: {args.robot} [{args.against}]")
                robot_rows(bench.snapshot_ref(args.against, t / "old"), t / "then",
                           args.robot)
            print(f"\nload average at end {load()}")
            return 0
        rows: list[tuple[str, float, dict]] = []
        # every row then finds the files in the system's page cache: the first timed run
        # would otherwise also pay for the first reading of the visual meshes from disk
        print(f"read once before timing: {read_all(robots) / 2**20:.0f} MB", flush=True)
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
        cpu_base = rows[0][2].get("cpu") or float("nan")
        print("\n| run | wall s | x naive | target | CPU s | x naive (CPU) | peak main MB "
              "| peak per worker MB | peak of the whole run MB |")
        print("|---|---:|---:|---:|---:|---:|---:|---:|---:|")
        for name, wall, res in rows:
            kind = "cold" if " cold " in name else "warm" if " warm " in name else None
            target = (verdict(wall / base, TARGETS[kind])
                      if kind and "this checkout" in name else "")
            workers = res.get("workers_mb") or []
            per_worker = " / ".join(f"{mb:.0f}" for mb in workers) or "-"
            tree = res.get("tree_mb", res["peak_main_mb"])
            cpu = res.get("cpu", float("nan"))
            print(f"| {name} | {wall:.2f} | {wall / base:.3f} | {target} | {cpu:.1f} | "
                  f"{cpu / cpu_base:.3f} | {res['peak_main_mb']:.0f} | {per_worker} | "
                  f"{tree:.0f} |")
        cold = dict((n, r) for n, _, r in rows)["fix --all cold [this checkout]"]
        peak = cold.get("tree_mb", 0.0)
        print(f"\npeak memory of the cold corpus run, main and workers together (sampled "
              f"every 50 ms): {peak:.0f} MB ({verdict(peak, MEMORY_MB)})")
        same = tree_bytes(outs[("this checkout", "cold")]) == tree_bytes(
            outs[("this checkout", "warm")])
        print(f"cold and warm outputs identical: {'yes' if same else 'NO'}")
        if args.against:
            same = tree_bytes(outs[("this checkout", "cold")]) == tree_bytes(
                outs[(args.against, "cold")])
            print(f"outputs identical to {args.against}'s: {'yes' if same else 'NO'}")

        _, res = run_child(["--child", "meshes", "--robots", str(robots)], code)
        costs = sorted(res["costs"], key=lambda c: -c["seconds"])
        integrated = [c for c in costs if c["integrated"]]
        print("\nten slowest meshes (read + hull points + repair + integrate, one process, "
              f"{len(integrated)} integrated meshes and {len(costs) - len(integrated)} "
              f"checked only, {sum(c['seconds'] for c in costs):.1f} s in all):\n")
        print("| s | read | hull | repair | union | faces | mesh | notes |")
        print("|---:|---:|---:|---:|---:|---:|---|---|")
        for c in integrated[:10]:
            st = c["stages"]
            print(f"| {c['seconds']:.2f} | {st.get('mesh read', 0):.2f} | "
                  f"{st.get('hull points', 0):.2f} | {st.get('repair', 0):.2f} | "
                  f"{st.get('union', 0):.2f} | {c['faces']} | {Path(c['mesh']).name} | "
                  f"{c['notes']} |")
        stages: dict[str, float] = {}
        for c in costs:
            for k, v in c["stages"].items():
                stages[k] = stages.get(k, 0.0) + v
        print("\nwhere the per-mesh work goes, one process, against the naive loop's "
              f"{base:.2f} s (wall, the same run):\n")
        print("| stage | s | x naive | the naive loop does it too |")
        print("|---|---:|---:|---|")
        also = {"mesh read": "yes (trimesh reads every reference)",
                "integration": "yes (mass_properties)"}
        for k in ("mesh read", "hull points", "repair", "union", "integration"):
            print(f"| {k} | {stages.get(k, 0.0):.2f} | {stages.get(k, 0.0) / base:.3f} | "
                  f"{also.get(k, 'no')} |")
        ran = [c for c in costs if c["stages"].get("union", 0.0) > 0]
        united = [c for c in ran if c["united"]]
        seconds = sum(c["stages"]["union"] for c in united)
        print(f"\nboolean unions (manifold3d): {len(ran)} meshes ran one; in {len(united)} "
              f"the bodies overlapped (the union changed the volume, so it cannot be "
              f"skipped): {seconds:.2f} s, {seconds / base:.3f}x the naive loop on its "
              "own")
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
    t.mkdir(parents=True, exist_ok=True)
    naive, res = run_child(["--child", "baseline", "--robots", str(robot)], code)
    refs = res["refs"]
    print(f"naive loop over this robot's collision meshes: {naive:.2f} s "
          f"({refs} references, one process"
          + ("; no collision mesh: the loop is its imports, no ratio is taken)" if not refs
             else ")"))
    cache = t / "cache-robot"
    for flags in ((), ("--all",)):
        wall, res = cli(code, cache if not flags else t / "cache-robot-all", "fix",
                        str(robot), "-o", str(t / "robot.urdf"), "-q", *flags)
        ratio = (f"{wall / naive:.2f}x naive, {verdict(wall / naive, ROBOT_X_NAIVE)}"
                 if refs else "no naive ratio")
        print(f"fix{''.join(' ' + f for f in flags)} cold: {wall:.2f} s "
              f"({verdict(wall, ROBOT_COLD_S)}; {ratio}), CPU "
              f"{res.get('cpu', float('nan')):.1f} s, peak main "
              f"{res['peak_main_mb']:.0f} MB, whole run {res.get('tree_mb', 0):.0f} MB")
    wall, _ = cli(code, cache, "fix", str(robot), "-o", str(t / "robot2.urdf"), "-q")
    print(f"fix warm: {wall:.2f} s")
    check_cache = t / "cache-check"
    first, res = cli(code, check_cache, "check", str(robot), "-q")
    second, _ = cli(code, check_cache, "check", str(robot), "-q")
    print(f"check: first {first:.2f} s (empty cache; CPU {res.get('cpu', float('nan')):.1f} "
          f"s), second {second:.2f} s ({verdict(second, SECOND_CHECK_S)})")
    for label, where in (("cold", t / "cache-report"), ("after fix", cache),
                         ("again", cache)):
        html = t / f"report-{where.name}.html"
        wall, res = cli(code, where, "report", str(robot), "-o", str(html))
        size = html.stat().st_size / 2**20 if html.exists() else float("nan")
        print(f"report {label}: {wall:.2f} s ({verdict(wall, REPORT_S)}; CPU "
              f"{res.get('cpu', float('nan')):.1f} s), {size:.2f} MB "
              f"({verdict(size, REPORT_MB)}), peak main {res['peak_main_mb']:.0f} MB, "
              f"whole run {res.get('tree_mb', res['peak_main_mb']):.0f} MB")


if __name__ == "__main__":
    sys.exit(main())
