"""Load and step every example-robot-data URDF in each engine, before and after ``fix``.

    nice .venv/bin/python scripts/bench_engines.py [--engines mujoco,pinocchio,pybullet]
        [--seconds 2] [--limit N] [--json PATH]

For each URDF: ``check --engines``'s probe (a child process per engine: load with the
meshes resolved, a passive run of --seconds under gravity with zero controls) on the file
as shipped and on ``fix``'s output (default options, the shipped file untouched). Prints
one line per URDF, then per engine how many were accepted and how many stayed stable
(finite, no runaway joint, no MuJoCo bad-state warning) before and after, and every
regression: an engine that accepted (or ran stably) the input and refuses (or does not
run stably) the output. The target is none.
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from collections import Counter
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tests"))

from support.corpus import example_robot_data_dir  # noqa: E402

from urdfinertia.body.options import FixOptions  # noqa: E402
from urdfinertia.cache.library import MeshLibrary  # noqa: E402
from urdfinertia.descriptions.formats import read_description  # noqa: E402
from urdfinertia.engines.run import (  # noqa: E402
    EngineCheck,
    installed,
    outcome_summary,
    parse_engines,
    regressions,
    stable,
)
from urdfinertia.errors import UrdfInertiaError  # noqa: E402
from urdfinertia.plan.fix import fix_file  # noqa: E402


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--engines", type=parse_engines, default=parse_engines("all"))
    parser.add_argument("--seconds", type=float, default=2.0)
    parser.add_argument("--limit", type=int, default=None, help="first N URDFs only")
    parser.add_argument("--json", type=Path)
    args = parser.parse_args(argv)
    root = example_robot_data_dir()
    if root is None:
        print("example-robot-data is not installed (pip install example-robot-data)")
        return 1
    engines = tuple(e for e in args.engines if installed(e))
    missing = sorted(set(args.engines) - set(engines))
    if missing:
        print(f"not installed, skipped: {', '.join(missing)}")
    check = EngineCheck(engines, seconds=args.seconds)
    files = sorted(root.rglob("*.urdf"))[:args.limit]
    counts: dict[str, Counter] = {e: Counter() for e in engines}
    worse: list[str] = []
    rows = []
    fix_failed = 0
    start = time.perf_counter()
    meshes = MeshLibrary()
    for path in files:
        name = str(path.relative_to(root))
        try:
            robot, data = read_description(path)
            before = check.outcomes(path, robot, data=data)
        except UrdfInertiaError as exc:
            print(f"{name}: unreadable: {exc.cause}")
            continue
        try:
            fixed = fix_file(path, FixOptions(), meshes).output
        except UrdfInertiaError as exc:
            fix_failed += 1
            print(f"{name}: fix refused: {exc.cause}")
            fixed = None
        after = check.outcomes(path, robot, data=fixed) if fixed is not None else {}
        for e in engines:
            c = counts[e]
            c["files"] += 1
            c["accepted before"] += before[e].accepted
            c["stable before"] += stable(before[e])
            if e in after:
                c["fixed"] += 1
                c["accepted after"] += after[e].accepted
                c["stable after"] += stable(after[e])
        lost = regressions(before, after)
        worse.extend(f"{name}: {f.severity}: {f.message}" for f in lost)
        print(f"{name}: " + "; ".join(
            f"{e} {outcome_summary(before[e])} -> "
            f"{outcome_summary(after[e]) if e in after else 'n/a'}" for e in engines),
            flush=True)
        rows.append({"file": name, **{e: [outcome_summary(before[e]), outcome_summary(
            after[e]) if e in after else None] for e in engines}})
    elapsed = time.perf_counter() - start
    print(f"\n{len(files)} URDFs, {args.seconds:g} s passive runs, {elapsed:.0f} s wall; "
          f"fix refused {fix_failed}")
    print(f"{'engine':10} {'accepted before':>16} {'after':>6} {'stable before':>14} "
          f"{'after':>6}  (after: of {{fixed}} fixed files)")
    for e in engines:
        c = counts[e]
        print(f"{e:10} {c['accepted before']:>10}/{c['files']:<5} {c['accepted after']:>6} "
              f"{c['stable before']:>8}/{c['files']:<5} {c['stable after']:>6}  "
              f"(of {c['fixed']})")
    print(f"regressions: {len(worse)}")
    for line in worse:
        print("  " + line)
    if args.json:
        args.json.write_text(json.dumps({"rows": rows, "counts": counts,
                                         "regressions": worse}, indent=2))
    return 1 if worse else 0


if __name__ == "__main__":
    sys.exit(main())
