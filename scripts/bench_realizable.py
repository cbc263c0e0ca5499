"""Realizability of the written inertials of the real corpus: how many fail the bounding
ellipsoid test (UI210) while passing every other rule, and which fail worst.

    nice .venv/bin/python scripts/bench_realizable.py [--packages a,b] [--per-package N]
        [--worst 10] [--json PATH] [--hull]

For every URDF of ``support.corpus.robot_packages`` (installed packages and those
``scripts/gather_corpus.py`` unpacked), ``check`` runs as the command does; per link with
geometry and a written body (positive mass, finite values, a tensor) it prints the counts:
links tested, failing the test (scale > SCALE_WARN, 1.05), of those with no other
error or warning (they pass today's rules), and failing by more than SCALE_ERROR (3x:
errors). Links whose tensor breaks the triangle inequality (realizable nowhere) are left
out: the value checks report them. Then the worst links with
their scale, mass, CoM and the ellipsoid's axes, for a person to judge. Timing: the test
itself (ellipsoid plus scale) against reading the link's points, in the same run.

With ``--hull`` every tested link that passes the ellipsoid is also tested in its convex
hull (``check --realizable hull``; a link failing the ellipsoid fails the hull too, since
the hull lies inside the ellipsoid): the columns ``hull`` (failing the hull by more than
SCALE_WARN, proved by the LP's certificate), ``h-only`` (of those, no other error or
warning), ``undec`` (an LP left undecided), and the hull test's time.
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
from urdfinertia.body.bounds import BoundsCache  # noqa: E402
from urdfinertia.body.hull import convex_hull, hull_scale  # noqa: E402
from urdfinertia.cache.library import mesh_library  # noqa: E402
from urdfinertia.descriptions.formats import read_description  # noqa: E402
from urdfinertia.descriptions.inertial import RawInertial  # noqa: E402
from urdfinertia.errors import UrdfInertiaError  # noqa: E402
from urdfinertia.inertia.realizable import bounding_ellipsoid  # noqa: E402
from urdfinertia.judge.realizability import (  # noqa: E402
    SCALE_ERROR,
    SCALE_WARN,
    geometry_points,
    link_realizability,
)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--packages", help="comma-separated package names (default: all)")
    ap.add_argument("--per-package", type=int, default=0,
                    help="at most N descriptions per package (0: all)")
    ap.add_argument("--worst", type=int, default=10)
    ap.add_argument("--json", type=Path, help="write every failing link here")
    ap.add_argument("--hull", action="store_true",
                    help="also test the links passing the ellipsoid in their convex hull")
    args = ap.parse_args(argv)
    packages = robot_packages(("urdf",))
    if args.packages:
        wanted = set(args.packages.split(","))
        packages = {k: v for k, v in packages.items() if k in wanted}
    meshes = mesh_library()
    rows = []
    totals = {"robots": 0, "tested": 0, "fail": 0, "fail_only": 0, "error": 0,
              "hull": 0, "hull_only": 0, "undecided": 0}
    t_points = t_test = t_hull = 0.0
    n_hull = 0
    hull_rows = []
    crashes: list[str] = []
    head = f"{'package':<20} {'robots':>6} {'tested':>7} {'fail':>5} {'only':>5} {'>3x':>4}"
    print(head + (f" {'hull':>5} {'h-only':>6} {'undec':>5}" if args.hull else ""))
    for name, files in sorted(packages.items()):
        if args.per_package:
            files = files[:args.per_package]
        counts = dict.fromkeys(totals, 0)
        for path in files:
            try:
                robot, _ = read_description(path)
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
                others = [f for f in by_link.get(link.name, ())
                          if f.code != "not-realizable" and f.severity in ("error", "warning")]
                if found.realizable and args.hull:
                    raw = RawInertial.from_inertial(link.inertial)
                    t3 = time.perf_counter()
                    h = hull_scale(raw.mass, raw.com, raw.inertia, convex_hull(points))
                    t_hull += time.perf_counter() - t3
                    n_hull += 1
                    counts["undecided"] += not h.decided
                    if h.low > SCALE_WARN:
                        counts["hull"] += 1
                        counts["hull_only"] += not others
                        hull_rows.append({"package": name, "link": link.name,
                                          "file": str(path.relative_to(path.parents[1])),
                                          "low": h.low, "high": h.high,
                                          "ellipsoid": found.scale, "mass": raw.mass,
                                          "other_findings": [f.code for f in others]})
                if found.realizable:
                    continue
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
        print(_row(name, counts, args.hull))
    print(_row("total", totals, args.hull))
    print(f"time: test (ellipsoid + scale) {t_test:.2f} s, reading points {t_points:.2f} s "
          f"(ratio {t_test / max(t_points, 1e-9):.2f})")
    if args.hull:
        print(f"hull: {n_hull} links passing the ellipsoid tested in {t_hull:.2f} s "
              f"({1000 * t_hull / max(n_hull, 1):.1f} ms a link)")
        seen_h = set()
        for r in sorted(hull_rows, key=lambda r: -r["low"]):
            key = (round(r["low"], 3), r["mass"])  # one per copied or mirrored link
            if key in seen_h or len(seen_h) >= args.worst:
                continue
            seen_h.add(key)
            print(f"  hull {r['low']:.4g}..{r['high']:.4g}x (ellipsoid {r['ellipsoid']:.3g}x)"
                  f"  {r['package']}/{r['file']} {r['link']}: {r['mass']:.4g} kg"
                  f"{'  [' + ', '.join(r['other_findings']) + ']' if r['other_findings'] else ''}")
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


def _row(name: str, c: dict, hull: bool) -> str:
    out = (f"{name:<20} {c['robots']:>6} {c['tested']:>7} {c['fail']:>5} "
           f"{c['fail_only']:>5} {c['error']:>4}")
    return out + (f" {c['hull']:>5} {c['hull_only']:>6} {c['undecided']:>5}" if hull else "")


if __name__ == "__main__":
    raise SystemExit(main())
