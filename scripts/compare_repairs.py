"""Did a change to the mesh repair move any real part by more than it states?

    python scripts/compare_repairs.py OLD_REF [MESH_DIR] [--new REF]

Checks out OLD_REF into a temporary git worktree and, with that revision's code and with
this checkout's (or ``--new REF``'s), repairs and integrates every STL, OBJ and DAE file
under MESH_DIR (default: example-robot-data's ``robots`` folder), each in its own
process. Per file it compares the volume (= mass at fixed density) and the inertia
tensor about the CoM (at density 1) and prints every file that changed, beside the
larger of the two revisions' stated volume uncertainties. A change within round-off
(``ROUNDOFF`` relative) or within the stated uncertainty is "within"; any other is
"BEYOND". It also prints the time both revisions took (load, repair and integrate,
no cache) and the files that got slowest. Exit code 0 when no file is beyond, 1
otherwise.
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

from support.corpus import example_robot_data_robots  # noqa: E402

#: Relative change of the sums that reordered floating-point arithmetic can make.
ROUNDOFF = 1e-8

_WORKER = r"""
import json, sys, time
import numpy as np
from urdfinertia.errors import MeshError
from urdfinertia.inertia.massprops import combine
from urdfinertia.mesh.read.load import load_mesh
from urdfinertia.mesh.repair.pipeline import repair_mesh
from urdfinertia.mesh.solids import integrate_repaired
out = {}
for line in sys.stdin:
    path = line.strip()
    start = time.perf_counter()
    try:
        solids = integrate_repaired(repair_mesh(load_mesh(path))).solids
    except MeshError as exc:
        out[path] = {"error": str(exc), "seconds": time.perf_counter() - start}
        continue
    seconds = time.perf_counter() - start
    mp = combine(s.mass_properties(1.0) for s in solids)
    stated = sum((s.error_estimate or 0.0) * s.volume for s in solids) / mp.mass
    out[path] = {"volume": mp.mass, "inertia": np.asarray(mp.inertia).tolist(),
                 "stated": stated, "method": "; ".join(s.method for s in solids),
                 "seconds": seconds}
json.dump(out, sys.stdout)
"""


def measure(src: Path, files: list[Path]) -> dict:
    env = dict(os.environ, PYTHONPATH=str(src))
    proc = subprocess.run([sys.executable, "-c", _WORKER], env=env, text=True,
                          input="\n".join(map(str, files)), capture_output=True, check=True)
    return json.loads(proc.stdout)


def main(argv: list[str] | None = None) -> int:
    import numpy as np

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("old")
    parser.add_argument("mesh_dir", nargs="?", type=Path)
    parser.add_argument("--new", default=None)
    args = parser.parse_args(argv)
    base = args.mesh_dir or example_robot_data_robots()
    files = sorted(p for p in base.rglob("*") if p.suffix.lower() in (".stl", ".obj", ".dae"))
    from support.revisions import revision_sources

    with revision_sources(ROOT, {"old": args.old, "new": args.new}) as trees:
        old, new = measure(trees["old"], files), measure(trees["new"], files)
    changed = beyond = errors = 0
    print(f"{len(files)} mesh files under {base}")
    print(f"{'file':60s} {'volume':>10s} {'tensor':>10s} {'stated':>10s}")
    for path in map(str, files):
        a, b = old[path], new[path]
        if "error" in a or "error" in b:
            if ("error" in a) != ("error" in b):
                errors += 1
                print(f"{path[-60:]:60s} old: {a.get('error', 'ok')} / new: "
                      f"{b.get('error', 'ok')}")
            continue
        dv = abs(b["volume"] - a["volume"]) / abs(a["volume"])
        ia, ib = np.array(a["inertia"]), np.array(b["inertia"])
        di = float(np.linalg.norm(ib - ia) / np.linalg.norm(ia))
        if dv == 0 and di == 0:
            continue
        changed += 1
        stated = max(a["stated"], b["stated"])
        ok = dv <= stated + ROUNDOFF
        beyond += not ok
        print(f"{path[-60:]:60s} {dv:10.2e} {di:10.2e} {stated:10.2e} "
              f"{'within' if ok else 'BEYOND'}")
    t_old = sum(old[p]["seconds"] for p in map(str, files))
    t_new = sum(new[p]["seconds"] for p in map(str, files))
    print(f"\nload + repair + integrate, one process each, no cache: {t_old:.1f} s old, "
          f"{t_new:.1f} s new (ratio {t_new / t_old:.2f})")
    slower = sorted(files, key=lambda p: new[str(p)]["seconds"] - old[str(p)]["seconds"])
    for path in slower[-5:]:
        print(f"  {path.name}: {old[str(path)]['seconds']:.2f} s -> "
              f"{new[str(path)]['seconds']:.2f} s")
    print(f"{changed} of {len(files)} files changed; {beyond} beyond the stated volume "
          f"uncertainty (+{ROUNDOFF:g} round-off); {errors} changed between error and "
          "result")
    return 1 if beyond or errors else 0


if __name__ == "__main__":
    raise SystemExit(main())
