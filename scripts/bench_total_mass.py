"""Target masses on real robots: before, target, after and the factor, and the time
``fix --total-mass`` takes against plain ``fix`` measured in the same run.

    nice .venv/bin/python scripts/bench_total_mass.py [--corpus] [--repeat 3]

The Panda of example-robot-data against Franka's datasheet figure for the arm (about 18
kg), with ``scale_kept`` (every stated mass there is kept). ``--corpus`` adds, for every
example-robot-data URDF, the share of the robot's mass that ``fix`` derives (what
``--total-mass`` scales without ``--scale-kept``).
"""

from __future__ import annotations

import argparse
import statistics
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tests"))

from support.corpus import robot_packages  # noqa: E402

from urdfinertia.body.options import FixOptions  # noqa: E402
from urdfinertia.errors import UrdfInertiaError  # noqa: E402
from urdfinertia.plan.fix import fix_file  # noqa: E402

PANDA_DATASHEET_KG = 18.0  # Franka Emika Panda arm, "approx. 18 kg"


def _time(path: Path, options: FixOptions, repeat: int) -> tuple[float, object]:
    times, result = [], None
    for _ in range(repeat):
        t0 = time.perf_counter()
        result = fix_file(path, options)
        times.append(time.perf_counter() - t0)
    return statistics.median(times), result


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--corpus", action="store_true", help="derived mass share per robot")
    ap.add_argument("--repeat", type=int, default=3)
    args = ap.parse_args(argv)
    erd = robot_packages(("urdf",)).get("example-robot-data", [])
    panda = next((p for p in erd if p.name == "panda.urdf"), None)
    if panda is None:
        print("example-robot-data's panda.urdf is not installed")
        return 1
    fix_file(panda)  # warm the mesh cache: both timings read the same meshes
    base, _ = _time(panda, FixOptions(), args.repeat)
    target = FixOptions(total_mass=PANDA_DATASHEET_KG, scale_kept=True)
    timed, result = _time(panda, target, args.repeat)
    (t,) = result.targets  # type: ignore[attr-defined]
    print(f"panda: before {t.before:.4f} kg, target {t.target:g} kg, after {t.after:.4f} kg, "
          f"factor {t.factor:.5f}, {len(t.scaled)} links scaled")
    print(f"time: fix {base * 1e3:.0f} ms, fix --total-mass --scale-kept {timed * 1e3:.0f} ms "
          f"(ratio {timed / base:.3f})")
    if args.corpus:
        print(f"{'robot':<40} {'mass kg':>9} {'derived kg':>11} {'share':>6}")
        for path in sorted(erd):
            try:
                r = fix_file(path)
            except (UrdfInertiaError, OSError, ValueError) as exc:
                print(f"{path.stem:<40} error: {exc}")
                continue
            total = sum(x.after.mass for x in r.links if x.after is not None
                        and x.after.mass > 0)
            derived = sum(x.after.mass for x in r.links if x.changed and x.after is not None
                          and "mass" in x.derived and x.status == "recomputed")
            share = derived / total if total > 0 else 0.0
            print(f"{path.stem:<40} {total:9.3f} {derived:11.3f} {100 * share:5.1f}%")
    return 0


if __name__ == "__main__":
    sys.exit(main())
