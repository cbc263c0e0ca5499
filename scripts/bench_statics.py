"""Whole-robot statics over the corpus: joints judged, passive, and those that cannot hold
their robot against gravity (UI701) or are within the margin (UI702).

    nice .venv/bin/python scripts/bench_statics.py [--packages a,b] [--formats urdf,sdf,mjcf]

Reads every URDF of ``support.corpus.robot_packages`` and runs the statics on the written
masses (``check --no-geometry``'s values; no mesh is read). Prints per package the robots,
actuated joints judged, passive joints, errors and warnings, then every error with its
joint, load and effort, and the time of the statics against reading the descriptions.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tests"))

from support.corpus import robot_packages  # noqa: E402

from urdfinertia.analysis.statics import (  # noqa: E402
    robot_statics,
    statics_findings,
    written_bodies,
)
from urdfinertia.descriptions.formats import read_description  # noqa: E402
from urdfinertia.errors import UrdfInertiaError  # noqa: E402


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--packages", help="comma-separated package names (default: all)")
    ap.add_argument("--formats", default="urdf", help="comma-separated description formats "
                    "(urdf, sdf, mjcf, ...; default: urdf)")
    args = ap.parse_args(argv)
    packages = robot_packages(tuple(args.formats.split(",")))
    if args.packages:
        wanted = set(args.packages.split(","))
        packages = {k: v for k, v in packages.items() if k in wanted}
    t_read = t_statics = 0.0
    errors = []
    print(f"{'package':<20} {'robots':>6} {'judged':>7} {'passive':>7} {'UI701':>6} {'UI702':>6}")
    for name, files in sorted(packages.items()):
        robots = judged = passive = n701 = n702 = 0
        for path in files:
            t0 = time.perf_counter()
            try:
                robot, _ = read_description(path)
            except (UrdfInertiaError, OSError, ValueError):
                continue
            t1 = time.perf_counter()
            held = robot_statics(robot, written_bodies(robot))
            found = statics_findings(robot, held)
            t_statics += time.perf_counter() - t1
            t_read += t1 - t0
            robots += 1
            judged += sum(not ld.passive for ld in held.loads)
            passive += sum(ld.passive for ld in held.loads)
            n701 += sum(f.code == "joint-cannot-hold" for f in found)
            n702 += sum(f.code == "joint-effort-margin" for f in found)
            errors += [f"{name}/{path.name}: {f.message}" for f in found
                       if f.severity == "error"]
        print(f"{name:<20} {robots:>6} {judged:>7} {passive:>7} {n701:>6} {n702:>6}")
    print(f"time: statics {t_statics:.2f} s, reading the descriptions {t_read:.2f} s "
          f"(ratio {t_statics / max(t_read, 1e-9):.2f})")
    for line in errors:
        print(f"  error: {line}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
