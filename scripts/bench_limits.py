"""Time and peak memory of `check` on generated serial chains of boxes, against a 10-link
baseline measured in the same run.

    PYTHONPATH=src python scripts/bench_limits.py [--links 10 100 300 1000]

Each size runs in its own process (peak memory, `resource.getrusage`'s ru_maxrss, is per
process). Prints one row per chain: links, seconds of `check`, seconds of its statics
alone, peak MiB, the configurations the statics sampled and whether it coarsened them,
and time and memory as ratios to the 10-link chain.
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
import tempfile
from pathlib import Path

_CHILD = """
import json, resource, sys, time
from urdfinertia import check
from urdfinertia.analysis.statics import robot_statics, verdict_bodies
start = time.perf_counter()
result = check(sys.argv[1])
seconds = time.perf_counter() - start
peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024  # kB on Linux
start = time.perf_counter()  # the statics' share, again on the same verdicts
held = robot_statics(result.robot, verdict_bodies(result.links))
statics = time.perf_counter() - start
print(json.dumps({"seconds": seconds, "peak_mib": peak, "statics_seconds": statics,
                  "configurations": held.configurations if held else 0,
                  "coarsened": bool(held and held.note)}))
"""


def chain_urdf(links: int) -> str:
    """A serial chain of `links` boxes (1 kg, 0.1 m long) on y-axis revolute joints whose
    effort (1 N m) every gravity load exceeds: every joint asks for refinement, the
    statics' worst case."""
    parts = ['<?xml version="1.0"?>', '<robot name="chain">']
    for i in range(links):
        parts.append(
            f'<link name="l{i}"><inertial><origin xyz="0 0 0.05"/><mass value="1"/>'
            '<inertia ixx="0.00104" ixy="0" ixz="0" iyy="0.00104" iyz="0" izz="0.00042"/>'
            '</inertial><collision><origin xyz="0 0 0.05"/><geometry>'
            '<box size="0.05 0.05 0.1"/></geometry></collision></link>')
        if i:
            parts.append(
                f'<joint name="j{i}" type="revolute"><parent link="l{i - 1}"/>'
                f'<child link="l{i}"/><origin xyz="0 0 0.1"/><axis xyz="0 1 0"/>'
                '<limit lower="-1" upper="1" effort="1" velocity="1"/></joint>')
    parts.append("</robot>")
    return "\n".join(parts)


def measure(links: int, folder: Path) -> dict:
    path = folder / f"chain{links}.urdf"
    path.write_text(chain_urdf(links), encoding="utf-8")
    done = subprocess.run([sys.executable, "-c", _CHILD, str(path)], capture_output=True,
                          text=True, check=True)
    return json.loads(done.stdout.strip().splitlines()[-1])


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--links", type=int, nargs="+", default=[10, 100, 300, 1000])
    args = parser.parse_args(argv)
    sizes = sorted(set(args.links) | {10})
    with tempfile.TemporaryDirectory() as tmp:
        rows = {n: measure(n, Path(tmp)) for n in sizes}
    base = rows[10]
    print(f"{'links':>6} {'seconds':>8} {'statics':>8} {'peak MiB':>9} {'configs':>8} "
          f"{'coarse':>6} {'x time':>7} {'x memory':>8}")
    for n, r in rows.items():
        coarse = "yes" if r["coarsened"] else "no"
        print(f"{n:>6} {r['seconds']:>8.2f} {r['statics_seconds']:>8.2f} "
              f"{r['peak_mib']:>9.0f} {r['configurations']:>8} {coarse:>6} "
              f"{r['seconds'] / base['seconds']:>7.1f} "
              f"{r['peak_mib'] / base['peak_mib']:>8.2f}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
