#!/usr/bin/env python
"""Peak memory of `urdf-inertia fix` on one mesh at the default face limit, per format.

Writes a closed UV sphere of just under ``--faces`` triangles (default: the default
``--max-faces``, 1,000,000) as binary STL, ASCII STL, OBJ, GLB and COLLADA, a one-link URDF
for each, and runs ``urdf-inertia fix -q --no-cache`` on it in a fresh child process. Peak
memory is the child's ``getrusage(RUSAGE_CHILDREN).ru_maxrss`` (Linux: KiB), read after it
exits; wall time is printed too. Also checks that every format gives the same mass.

With ``--corpus`` it measures a robot collection instead (default: example-robot-data's
``robots`` folder), for this tree and, with ``--against REF``, for git revision REF too (a
temporary git worktree, as the comparison scripts check revisions out), side by side:

* the ``--meshes`` largest mesh files the descriptions reference (by file size), each
  read, repaired and integrated by the worker's own unit of work
  (``batch.tasks.mesh_task``) in a fresh process: that process's peak RSS (``VmHWM``);
* a cold ``urdf-inertia fix DIR -o OUT --all -q`` run (a private, empty mesh cache): its
  process tree is sampled from this process every few milliseconds through ``/proc``
  (Linux only), giving each process's peak (its ``VmHWM``, last read before it exits) and
  the whole run's peak (the largest sum of the tree's RSS over the samples: a sampled
  figure, it may miss a short spike). The two revisions' outputs are compared byte for
  byte.

Usage: python scripts/bench_memory.py [--faces N] [--formats stl,obj,...]
       python scripts/bench_memory.py --corpus [--robots DIR] [--meshes 8] [--against REF]
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
FORMATS = ("stl", "stl-ascii", "obj", "glb", "dae")

URDF = """<?xml version="1.0"?>
<robot name="sphere">
  <link name="ball">
    <collision><geometry><mesh filename="{mesh}"/></geometry></collision>
  </link>
</robot>
"""


def sphere(faces: int):
    """A UV sphere (radius 0.1 m) with at most ``faces`` triangles (closed once welded)."""
    import trimesh

    # trimesh's UV sphere with count (rows, cols) has 4 cols (rows - 2) triangles
    rows = int((faces / 4) ** 0.5) + 2
    cols = faces // (4 * (rows - 2))
    mesh = trimesh.creation.uv_sphere(radius=0.1, count=[rows, cols])
    while len(mesh.faces) > faces:  # trimesh may round the counts up
        cols -= 1
        mesh = trimesh.creation.uv_sphere(radius=0.1, count=[rows, cols])
    return mesh


def write(mesh, fmt: str, folder: Path) -> Path:
    import trimesh

    if fmt == "stl-ascii":
        path = folder / "ball_ascii.stl"
        path.write_text(trimesh.exchange.stl.export_stl_ascii(mesh))
    else:
        path = folder / f"ball.{fmt}"
        mesh.export(path)
    return path


def run_fix(urdf: Path, out: Path) -> tuple[float, float, str]:
    """Fix ``urdf`` in a fresh child process: (wall s, the child's peak RSS MB, output)."""
    start = time.perf_counter()
    proc = subprocess.run([sys.executable, __file__, "--child", str(urdf), str(out)],
                          capture_output=True, text=True)
    wall = time.perf_counter() - start
    if proc.returncode != 0:
        sys.exit(f"fix failed on {urdf}:\n{proc.stderr}")
    return wall, json.loads(proc.stdout.strip().splitlines()[-1])["peak_mb"], out.read_text()


def child(urdf: str, out: str) -> int:
    from bench import own_peak_mb  # scripts/bench.py, next to this script

    from urdfinertia.cli import main as cli_main

    code = cli_main(["fix", "--all", urdf, "-o", out, "-q", "--no-cache"])
    print(json.dumps({"peak_mb": own_peak_mb()}))
    return code



# ----------------------------------------------------------------------------- --corpus

# Run with a revision's ``src`` first on sys.path: the worker's unit of work on one mesh.
_MESH_CHILD = r"""
import json, sys
from urdfinertia.batch.tasks import mesh_task
solids, faces = mesh_task(sys.argv[1], int(sys.argv[2]))[:2]  # (older revisions return fewer)
peak = 0.0
for line in open("/proc/self/status"):
    if line.startswith("VmHWM:"):
        peak = int(line.split()[1]) / 1024
print(json.dumps({"peak_mb": peak, "faces": faces,
                  "error": str(solids) if isinstance(solids, Exception) else None}))
"""


def mesh_peak(src: Path, path: Path, max_faces: int) -> dict:
    """Peak RSS (MB) of one fresh process reading, repairing and integrating ``path`` with
    the package under ``src``."""
    env = dict(os.environ, PYTHONPATH=str(src))
    proc = subprocess.run([sys.executable, "-c", _MESH_CHILD, str(path), str(max_faces)],
                          env=env, capture_output=True, text=True)
    if proc.returncode != 0:
        sys.exit(f"the mesh worker failed on {path} ({src}):\n{proc.stderr}")
    return json.loads(proc.stdout.strip().splitlines()[-1])


def _tree(root: int) -> list[int]:
    """``root`` and its living descendants (from ``/proc/*/stat``)."""
    parents: dict[int, list[int]] = {}
    for entry in os.scandir("/proc"):
        if not entry.name.isdigit():
            continue
        try:
            with open(f"/proc/{entry.name}/stat") as f:
                stat = f.read()
        except OSError:
            continue
        ppid = int(stat.rsplit(")", 1)[1].split()[1])  # the name may hold spaces
        parents.setdefault(ppid, []).append(int(entry.name))
    found, todo = [], [root]
    while todo:
        pid = todo.pop()
        found.append(pid)
        todo.extend(parents.get(pid, ()))
    return found


def _memory(pid: int) -> tuple[float, float] | None:
    """(RSS, peak RSS) of ``pid`` in MB, or None once it is gone."""
    rss = hwm = None
    try:
        with open(f"/proc/{pid}/status") as f:
            for line in f:
                if line.startswith("VmRSS:"):
                    rss = int(line.split()[1]) / 1024
                elif line.startswith("VmHWM:"):
                    hwm = int(line.split()[1]) / 1024
    except OSError:
        return None
    return None if rss is None or hwm is None else (rss, hwm)


def fix_run_peaks(src: Path, robots: Path, out: Path, cache: Path,
                  interval: float = 0.005) -> dict:
    """A cold ``fix --all`` of ``robots`` with the package under ``src``, its process tree
    sampled every ``interval`` s: wall time, the main process's and each other process's
    peak RSS (MB, largest first) and the sampled peak of the tree's summed RSS."""
    env = dict(os.environ, PYTHONPATH=str(src), URDFINERTIA_CACHE_DIR=str(cache))
    start = time.perf_counter()
    proc = subprocess.Popen([sys.executable, "-m", "urdfinertia.cli", "fix", str(robots),
                             "-o", str(out), "--all", "-q"], env=env,
                            stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    peaks: dict[int, float] = {}
    total = 0.0
    while proc.poll() is None:
        now = 0.0
        for pid in _tree(proc.pid):
            seen = _memory(pid)
            if seen is not None:
                now += seen[0]
                peaks[pid] = max(peaks.get(pid, 0.0), seen[1])
        total = max(total, now)
        time.sleep(interval)
    wall = time.perf_counter() - start
    stderr = proc.stderr.read().decode(errors="replace") if proc.stderr else ""
    if not out.is_dir():
        sys.exit(f"fix failed with exit code {proc.returncode} ({src}):\n{stderr}")
    main_peak = peaks.pop(proc.pid, 0.0)
    others = sorted((p for p in peaks.values() if p >= 50), reverse=True)  # workers
    return {"wall": wall, "main": main_peak, "workers": others, "total": total,
            "exit": proc.returncode}


def _outputs(folder: Path) -> dict[str, bytes]:
    return {p.relative_to(folder).as_posix(): p.read_bytes()
            for p in sorted(folder.rglob("*")) if p.is_file()}


def corpus(robots: Path, meshes: int, against: str | None, max_faces: int) -> int:
    """The ``--corpus`` measurements: prints a Markdown table, this tree beside ``against``."""
    sys.path.insert(0, str(ROOT / "tests"))
    from compare_solids import referenced_meshes  # scripts/, next to this script
    from support.revisions import revision_sources

    files = referenced_meshes(robots)
    largest = sorted(files, key=lambda p: p.stat().st_size, reverse=True)[:meshes]
    tags = {"ref": against, "new": None} if against else {"new": None}
    names = {"ref": against or "", "new": "this tree"}
    rows: list[tuple[str, dict[str, float]]] = []
    results: dict[str, dict] = {}
    with revision_sources(ROOT, tags) as trees, \
            tempfile.TemporaryDirectory(prefix="urdfinertia-mem-") as tmp:
        for path in largest:
            shown = path.relative_to(robots) if path.is_relative_to(robots) else path
            row = {}
            for tag in tags:
                found = mesh_peak(trees[tag], path, max_faces)
                row[tag] = found["peak_mb"]
            label = f"{shown} ({found['faces']:,} faces)"
            rows.append((label, row))
            print(f"  {label}: " + ", ".join(f"{names[t]} {row[t]:.0f} MB" for t in tags),
                  flush=True)
        for tag in tags:
            results[tag] = fix_run_peaks(trees[tag], robots, Path(tmp) / f"out-{tag}",
                                         Path(tmp) / f"cache-{tag}")
            print(f"  fix --all ({names[tag]}): {results[tag]}", flush=True)
        same = None
        if against:
            same = _outputs(Path(tmp) / "out-ref") == _outputs(Path(tmp) / "out-new")
    workers = max(len(r["workers"]) for r in results.values())
    for i in range(workers):
        rows.append((f"fix --all: worker {i + 1} peak",
                     {t: (r["workers"][i] if i < len(r["workers"]) else float("nan"))
                      for t, r in results.items()}))
    rows.append(("fix --all: main process peak", {t: r["main"] for t, r in results.items()}))
    rows.append(("fix --all: whole run peak (sampled sum)",
                 {t: r["total"] for t, r in results.items()}))
    print(f"\npeak RSS, MB ({len(files)} meshes referenced under {robots.name}/, the "
          f"{len(largest)} largest each in a fresh process; a cold fix --all run)")
    if against:
        print(f"| | {against} | this tree | ratio |\n|---|---:|---:|---:|")
        for label, row in rows:
            print(f"| {label} | {row['ref']:.0f} | {row['new']:.0f} | "
                  f"{row['new'] / row['ref']:.3f} |")
    else:
        print("| | this tree |\n|---|---:|")
        for label, row in rows:
            print(f"| {label} | {row['new']:.0f} |")
    print("fix --all wall s: " + ", ".join(f"{names[t]} {r['wall']:.1f} (exit {r['exit']})"
                                           for t, r in results.items()))
    if same is not None:
        print(f"outputs byte-identical: {'yes' if same else 'NO'}")
        return 0 if same else 1
    return 0


def main() -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--faces", type=int, default=1_000_000)
    p.add_argument("--formats", default=",".join(FORMATS))
    p.add_argument("--child", nargs=2, help=argparse.SUPPRESS)
    p.add_argument("--corpus", action="store_true",
                   help="measure a robot collection (see above) instead of one sphere")
    p.add_argument("--robots", type=Path,
                   help="--corpus: folder of descriptions (default: example-robot-data's)")
    p.add_argument("--meshes", type=int, default=8,
                   help="--corpus: how many of the largest meshes to measure one by one")
    p.add_argument("--against", metavar="REF", help="--corpus: also measure git revision REF")
    args = p.parse_args()
    if args.child:
        return child(*args.child)
    if args.corpus:
        robots = args.robots
        if robots is None:
            sys.path.insert(0, str(ROOT / "tests"))
            from support.corpus import example_robot_data_robots

            robots = example_robot_data_robots()
        return corpus(robots.resolve(), args.meshes, args.against, args.faces)
    mesh = sphere(args.faces)
    print(f"closed UV sphere: {len(mesh.faces):,} faces, {len(mesh.vertices):,} vertices")
    print("| format | file MB | wall s | peak RSS MB | mass kg |")
    print("|---|---:|---:|---:|---:|")
    masses = []
    with tempfile.TemporaryDirectory(prefix="urdfinertia-mem-") as tmp:
        folder = Path(tmp)
        for fmt in args.formats.split(","):
            path = write(mesh, fmt, folder)
            urdf = folder / f"{path.stem}_{fmt}.urdf"
            urdf.write_text(URDF.format(mesh=path.name))
            wall, peak, text = run_fix(urdf, folder / f"out_{fmt}.urdf")
            mass = float(text.split('<mass value="')[1].split('"')[0])
            masses.append(mass)
            print(f"| {fmt} | {path.stat().st_size / 1e6:.0f} | {wall:.1f} | {peak:.0f} | "
                  f"{mass:.6g} |")
    spread = (max(masses) - min(masses)) / max(masses)
    print(json.dumps({"same_mass_across_formats": spread < 1e-6, "spread": spread}))
    return 0 if spread < 1e-6 else 1


if __name__ == "__main__":
    sys.exit(main())
