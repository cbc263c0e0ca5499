"""Realizability of the written inertials of the real corpus: how many fail the bounding
ellipsoid test (UI210) while passing every other rule, and which fail worst.

    nice .venv/bin/python scripts/bench_realizable.py [--packages a,b] [--per-package N]
        [--worst 10] [--json PATH]

For every URDF of ``support.corpus.robot_packages`` (installed packages and those
``scripts/gather_corpus.py`` unpacked), ``check`` runs as the command does; per link with
geometry and a written body (positive mass, finite values, a tensor) it prints the counts:
links tested, failing the test (scale > SCALE_WARN, 1.05), of those with no other
error or warning (they pass today's rules), and failing by more than SCALE_ERROR (3x:
errors). Links whose tensor breaks the triangle inequality (realizable nowhere) are left
out: the value checks report them. Then the worst links with
their scale, mass, CoM and the ellipsoid's axes, for a person to judge. Timing: the test
itself (ellipsoid plus scale) against reading the link's points, in the same run.
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tests"))

from support.corpus import robot_packages  # noqa: E402

from urdfinertia.analysis.check import check_description  # noqa: E402
from urdfinertia.analysis.realizability import (  # noqa: E402
    SCALE_ERROR,
    SCALE_WARN,
    geometry_points,
    link_realizability,
)
from urdfinertia.cache.library import mesh_library  # noqa: E402
from urdfinertia.descriptions.formats import read_description  # noqa: E402
from urdfinertia.errors import UrdfInertiaError  # noqa: E402
from urdfinertia.inertia.realizable import bounding_ellipsoid  # noqa: E402
from urdfinertia.link.bounds import BoundsCache  # noqa: E402


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--packages", help="comma-separated package names (default: all)")
    ap.add_argument("--per-package", type=int, default=0,
                    help="at most N descriptions per package (0: all)")
    ap.add_argument("--worst", type=int, default=10)
    ap.add_argument("--json", type=Path, help="write every failing link here")
    args = ap.parse_args(argv)
    packages = robot_packages(("urdf",))
    if args.packages:
        wanted = set(args.packages.split(","))
        packages = {k: v for k, v in packages.items() if k in wanted}
    meshes = mesh_library()
    rows = []
    totals = {"robots": 0, "tested": 0, "fail": 0, "fail_only": 0, "error": 0}
    t_points = t_test = 0.0
    crashes: list[str] = []
    print(f"{'package':<20} {'robots':>6} {'tested':>7} {'fail':>5} {'only':>5} {'>3x':>4}")
    for name, files in sorted(packages.items()):
        if args.per_package:
            files = files[:args.per_package]
        counts = dict.fromkeys(totals, 0)
        for path in files:
            try:
                robot, _ = read_description(path, lenient=True)
                checked = check_description(robot, meshes=meshes, statics=False)
            except (UrdfInertiaError, OSError, ValueError):
                continue
            except Exception as exc:  # a crash of check itself: counted and named, not hidden
                crashes.append(f"{path}: {type(exc).__name__}: {exc}")
                continue
            counts["robots"] += 1
            cache = BoundsCache(meshes)
            urdf_dir = path.parent
            by_link: dict[str, list] = {}
            for f in checked.findings:
                by_link.setdefault(f.link, []).append(f)
            for link in robot.links:
                try:
                    t0 = time.perf_counter()
                    refs = link.collisions + link.visuals
                    if not refs or link.inertial is None:
                        continue
                    points = geometry_points(refs, cache, urdf_dir)
                    t1 = time.perf_counter()
                    found = link_realizability(link, cache, urdf_dir)
                    bounding_ellipsoid(points)  # timed alone: the test's own cost
                    t2 = time.perf_counter()
                except (UrdfInertiaError, ValueError):
                    continue
                t_points += t1 - t0
                t_test += (t2 - t1) / 2
                if found is None:
                    continue
                if not np.isfinite(found.scale):
                    continue  # no density anywhere: the triangle inequality's finding
                counts["tested"] += 1
                if found.realizable:
                    continue
                others = [f for f in by_link.get(link.name, ())
                          if f.code != "not-realizable" and f.severity in ("error", "warning")]
                counts["fail"] += 1
                counts["fail_only"] += not others
                counts["error"] += found.scale > SCALE_ERROR
                inertial = link.inertial
                rows.append({"package": name, "file": str(path.relative_to(path.parents[1])),
                             "link": link.name, "scale": found.scale,
                             "mass": inertial.mass, "com": list(inertial.origin.xyz),
                             "axes": [2 * a for a in found.ellipsoid.semi_axes],
                             "other_findings": [f.code for f in others]})
        for k in totals:
            totals[k] += counts[k]
        print(f"{name:<20} {counts['robots']:>6} {counts['tested']:>7} {counts['fail']:>5} "
              f"{counts['fail_only']:>5} {counts['error']:>4}")
    print(f"{'total':<20} {totals['robots']:>6} {totals['tested']:>7} {totals['fail']:>5} "
          f"{totals['fail_only']:>5} {totals['error']:>4}")
    print(f"time: test (ellipsoid + scale) {t_test:.2f} s, reading points {t_points:.2f} s "
          f"(ratio {t_test / max(t_points, 1e-9):.2f})")
    for line in crashes:
        print(f"check crashed: {line.split('site-packages/')[-1]}")
    worst, seen = [], set()
    for r in sorted((r for r in rows if not r["other_findings"]), key=lambda r: -r["scale"]):
        key = (r["link"], round(r["scale"], 3), r["mass"])  # one per copy-pasted link
        if key not in seen and len(worst) < args.worst:
            seen.add(key)
            worst.append(r)
    print(f"\nworst {len(worst)} distinct failing links (scale > {SCALE_WARN:g}) that pass "
          "every other rule (a link copied into several descriptions listed once):")
    for r in worst:
        axes = "x".join(f"{a:.3g}" for a in r["axes"])
        com = ", ".join(f"{c:.3g}" for c in r["com"])
        print(f"  {r['scale']:8.3g}x  {r['package']}/{r['file']} {r['link']}: "
              f"{r['mass']:.4g} kg, CoM ({com}), ellipsoid {axes} m")
    if args.json:
        args.json.write_text(json.dumps(rows, indent=1))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
