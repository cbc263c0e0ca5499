"""Does this checkout repair and integrate every mesh exactly as another revision does?

    python scripts/compare_solids.py REF [--robots DIR] [--new REF] [--limit N]

Lists every mesh file the descriptions under DIR (default: example-robot-data's
``robots`` folder) reference, collision and visual, then reads, repairs and integrates
each one with revision REF's code (a temporary git worktree) and with this checkout's
(or revision ``--new REF``'s), one process per revision, one after the other. Per mesh it
compares exactly: the triangles read, the repaired bodies' vertex and face arrays (bytes),
each solid's volume integrals (bytes), method, error estimate, notes and provenance, the
file's notes, or the error raised. It prints the CPU seconds per stage (mesh read,
repair, union, integration) of both revisions, measured in this run, and their ratio,
then the meshes whose repair CPU time changed most, and each process's peak memory.

CPU time, not wall time: the machine may be shared. The repair's time budget per mesh
(``URDFINERTIA_MESH_SECONDS``) is as the environment sets it for both sides; a mesh that
runs over it in one revision only is reported as a difference.

``--winding`` compares this checkout with itself instead: generalized winding numbers
from libigl (the ``fast`` extra) on one side, from the numpy fallback on the other
(``URDFINERTIA_NO_LIBIGL=1``), so it says what installing without the extra changes.

    python scripts/compare_solids.py --winding [--robots DIR] [--limit N]

Exit code 0 when every mesh gives the same bytes and strings, 1 otherwise.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tests"))

STAGES = ("mesh read", "repair", "union", "integration")

# Run with the revision's ``src`` first on sys.path: only functions whose signatures have
# not changed across revisions (load_mesh, repair_mesh, integrate_repaired, StageTimes).
_WORKER = r"""
import hashlib, json, resource, sys, time, types
import numpy as np
import urdfinertia.timing as timing
from urdfinertia.errors import MeshError
from urdfinertia.mesh.read.load import load_mesh
from urdfinertia.mesh.repair.pipeline import repair_mesh
from urdfinertia.mesh.solids import integrate_repaired

# StageTimes measures with time.perf_counter: measure CPU seconds instead (the repair's
# Deadline already reads time.process_time, which this keeps)
timing.time = types.SimpleNamespace(perf_counter=time.process_time,
                                    process_time=time.process_time)


def digest(*arrays):
    h = hashlib.sha256()
    for a in arrays:
        a = np.ascontiguousarray(a)
        h.update(str((a.dtype.str, a.shape)).encode())
        h.update(a.tobytes())
    return h.hexdigest()


def value(x):
    return None if x is None else float(x).hex()


max_faces = int(sys.argv[1])
out = {}
for line in sys.stdin:
    path = line.rstrip("\n")
    times = timing.StageTimes()
    rec = {}
    try:
        with times.stage("mesh read"):
            mesh = load_mesh(path, max_faces)
        rec["read"] = digest(np.asarray(mesh.vertices, dtype=np.float64),
                             np.asarray(mesh.faces, dtype=np.int64))
        unions = timing.StageTimes()
        with times.stage("repair"):
            repaired = repair_mesh(mesh, unions)
        times.add("repair", -unions.get("union"))
        times.merge(unions)
        rec["bodies"] = [{"vertices": digest(np.asarray(b.vertices, dtype=np.float64)),
                          "faces": digest(np.asarray(b.faces, dtype=np.int64)),
                          "method": b.method, "error": value(b.error_estimate),
                          "notes": list(b.notes), "provenance": b.provenance,
                          "dependence": value(b.dependence)} for b in repaired.bodies]
        rec["repair notes"] = list(repaired.notes)
        with times.stage("integration"):
            solids = integrate_repaired(repaired)
        rec["solids"] = [{"integrals": digest(np.array([s.volume]), s.first, s.second),
                          "volume": value(s.volume), "method": s.method,
                          "error": value(s.error_estimate), "notes": list(s.notes),
                          "provenance": s.provenance} for s in solids.solids]
        rec["notes"] = list(solids.notes)
    except MeshError as exc:
        rec["error"] = f"{exc.code}: {exc}"
    rec["seconds"] = dict(times.seconds)
    out[path] = rec
out["__peak_mb__"] = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
json.dump(out, sys.stdout)
"""


def referenced_meshes(robots: Path) -> list[Path]:
    """Every resolvable mesh file the descriptions under ``robots`` use (collision and
    visual, every link), read with this checkout's description readers."""
    sys.path.insert(0, str(ROOT / "src"))
    from urdfinertia.batch.inputs import collect_jobs
    from urdfinertia.batch.tasks import mesh_needs
    from urdfinertia.body.options import FixOptions

    options = FixOptions(recompute="all")  # --all: every link's collisions and visuals
    found: dict[Path, None] = {}
    for job in collect_jobs([robots], None):
        solids, points = mesh_needs(job.source, options)
        found.update(dict.fromkeys(solids))
        found.update(dict.fromkeys(points))
    return sorted(found)


def measure(src: Path, files: list[Path], max_faces: int,
            env_extra: dict[str, str] | None = None) -> dict:
    """Run the worker on ``files`` with the package under ``src`` (and ``env_extra`` set)."""
    env = dict(os.environ, PYTHONPATH=str(src), **(env_extra or {}))
    proc = subprocess.run([sys.executable, "-c", _WORKER, str(max_faces)], env=env,
                          text=True, input="".join(f"{p}\n" for p in files),
                          capture_output=True)
    if proc.returncode != 0:
        sys.stderr.write(proc.stderr)
        raise SystemExit(f"the worker on {src} failed (exit {proc.returncode})")
    return json.loads(proc.stdout)


def differences(a: dict, b: dict) -> list[str]:
    """What differs between two records of one mesh (timings aside)."""
    keys = sorted((set(a) | set(b)) - {"seconds"})
    return [k for k in keys if a.get(k) != b.get(k)]


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("old", metavar="REF", nargs="?")
    parser.add_argument("--winding", action="store_true",
                        help="this checkout with libigl against itself with the numpy "
                             "winding numbers (no REF)")
    parser.add_argument("--robots", type=Path, help="folder of descriptions "
                                                    "(default: example-robot-data's robots)")
    parser.add_argument("--new", metavar="REF", help="compare with revision REF, "
                                                     "not this checkout")
    parser.add_argument("--limit", type=int, help="only the first N meshes (a quick look)")
    parser.add_argument("--max-faces", type=int, default=1_000_000)
    args = parser.parse_args(argv)
    if args.robots is None:
        from support.corpus import example_robot_data_robots

        args.robots = example_robot_data_robots()
    args.robots = args.robots.resolve()
    files = referenced_meshes(args.robots)[:args.limit]
    print(f"{len(files)} mesh files referenced under {args.robots.name}/ (collision and "
          "visual)", flush=True)
    if args.winding:
        from urdfinertia.mesh.repair.winding import NO_COMPILED

        old = measure(ROOT / "src", files, args.max_faces)
        new = measure(ROOT / "src", files, args.max_faces, {NO_COMPILED: "1"})
        names = {"old": "libigl", "new": "numpy"}
    else:
        if args.old is None:
            parser.error("REF is required (or --winding)")
        from support.revisions import revision_sources

        with revision_sources(ROOT, {"old": args.old, "new": args.new}) as trees:
            old = measure(trees["old"], files, args.max_faces)
            new = measure(trees["new"], files, args.max_faces)
        names = {"old": args.old, "new": args.new or "this checkout"}
    peaks = {"old": old.pop("__peak_mb__"), "new": new.pop("__peak_mb__")}
    differing = 0
    for path in map(str, files):
        what = differences(old[path], new[path])
        if what:
            differing += 1
            print(f"DIFFERS {path}: {', '.join(what)}")
            for key in what:
                print(f"    {names['old']}: {str(old[path].get(key))[:300]}")
                print(f"    {names['new']}: {str(new[path].get(key))[:300]}")
    errors = sum("error" in old[str(p)] for p in files)
    print(f"{len(files)} meshes ({errors} refused by both or either), {differing} differ")
    print("\nCPU seconds, one process per revision, in this run:")
    print(f"{'stage':14s} {names['old'][:14]:>14s} {names['new'][:14]:>14s} {'ratio':>7s}")
    totals = {}
    for tag, res in (("old", old), ("new", new)):
        totals[tag] = {s: sum(r["seconds"].get(s, 0.0) for r in res.values()) for s in STAGES}
    for stage in (*STAGES, "total"):
        a = sum(totals["old"].values()) if stage == "total" else totals["old"][stage]
        b = sum(totals["new"].values()) if stage == "total" else totals["new"][stage]
        ratio = f"{b / a:7.3f}" if a > 0 else "      -"
        print(f"{stage:14s} {a:14.2f} {b:14.2f} {ratio}")
    repair = {tag: {p: r["seconds"].get("repair", 0.0) + r["seconds"].get("union", 0.0)
                    for p, r in res.items()} for tag, res in (("old", old), ("new", new))}
    print("\nslowest repairs (repair + union CPU seconds):")
    for path in sorted(repair["old"], key=repair["old"].get, reverse=True)[:10]:
        shown = Path(path)
        if shown.is_relative_to(args.robots):
            shown = shown.relative_to(args.robots)
        print(f"  {repair['old'][path]:7.2f} -> {repair['new'][path]:7.2f}  {shown}")
    print(f"\npeak RSS: {peaks['old']:.0f} MB ({names['old']}), {peaks['new']:.0f} MB "
          f"({names['new']})")
    return 1 if differing else 0


if __name__ == "__main__":
    raise SystemExit(main())
