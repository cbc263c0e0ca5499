"""Run ``check`` over every example-robot-data URDF and summarise the findings.

    .venv/bin/python scripts/bench_check_corpus.py [--no-geometry] [--json PATH]

Prints one line per URDF (links, errors, warnings, seconds), then the corpus totals per
finding code (findings and distinct robots), and, with geometry, the links breaking the
triangle inequality. Nothing is written unless ``--json`` is given. Also cross-checks
with MuJoCo when it is installed: each URDF, stripped of its geometry, is loaded by MuJoCo
(which refuses non-positive-definite tensors, A + B < C and massless moving bodies), and
its verdict is set against whether ``check`` reports an error.
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from collections import Counter, defaultdict
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tests"))

from support.corpus import example_robot_data_dir  # noqa: E402

from urdfinertia.analysis.check import check_robot  # noqa: E402
from urdfinertia.cache.library import MeshLibrary  # noqa: E402
from urdfinertia.descriptions.formats import read_description  # noqa: E402
from urdfinertia.errors import UrdfInertiaError  # noqa: E402


def mujoco_verdict(path: Path) -> str:
    """"ok", "inertia" (refused for mass/inertia) or "other" (refused for another reason)."""
    try:
        import mujoco
    except ImportError:
        return "n/a"
    from lxml import etree

    # Geometry removed: MuJoCo then judges the inertials alone (and needs no mesh file).
    root = etree.fromstring(path.read_bytes(), etree.XMLParser(resolve_entities=False))
    for el in root.xpath("/robot/link/visual | /robot/link/collision"):
        el.getparent().remove(el)
    try:
        mujoco.MjModel.from_xml_string(etree.tostring(root).decode())
    except Exception as exc:  # mujoco raises ValueError with the compiler's message
        text = str(exc)
        return "inertia" if ("inertia" in text or "mass" in text) else "other"
    return "ok"


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--no-geometry", action="store_true", help="value checks only")
    ap.add_argument("--no-mujoco", action="store_true", help="skip the MuJoCo cross-check")
    ap.add_argument("--json", type=Path, help="write every finding here")
    args = ap.parse_args(argv)
    erd = example_robot_data_dir()
    if erd is None:
        print("example-robot-data is not installed", file=sys.stderr)
        return 2
    paths = sorted(erd.rglob("*.urdf"))
    meshes = None if args.no_geometry else MeshLibrary()
    by_code: Counter[tuple[str, str]] = Counter()
    robots_by_code: dict[tuple[str, str], set[str]] = defaultdict(set)
    all_findings = []
    links_total = 0
    mj = Counter()
    agree = Counter()
    t_all = time.perf_counter()
    for path in paths:
        rel = str(path.relative_to(erd / "robots"))
        t0 = time.perf_counter()
        try:
            robot, _ = read_description(path)
        except UrdfInertiaError as exc:
            print(f"{rel}: unreadable: {exc.cause}")
            continue
        found = check_robot(robot, meshes=meshes)
        dt = time.perf_counter() - t0
        links_total += len(robot.links)
        sev = Counter(f.severity for f in found)
        verdict = "n/a" if args.no_mujoco else mujoco_verdict(path)
        mj[verdict] += 1
        if verdict in ("ok", "inertia"):
            agree[(verdict, sev["error"] > 0)] += 1
        print(f"{rel:60s} {len(robot.links):4d} links {sev['error']:3d} E {sev['warning']:3d} W "
              f"{sev['info']:3d} I  {dt:6.2f} s  mujoco: {verdict}", flush=True)
        for f in found:
            by_code[(f.severity, f.code)] += 1
            robots_by_code[(f.severity, f.code)].add(rel)
            all_findings.append({"file": rel, **vars(f)})
    elapsed = time.perf_counter() - t_all
    print(f"\n{len(paths)} URDFs, {links_total} links, {elapsed:.1f} s "
          f"({'values only' if args.no_geometry else 'with geometry'})")
    print(f"{'severity':8s} {'code':32s} {'findings':>8s} {'URDFs':>6s}")
    for (sev, code), n in sorted(by_code.items()):
        print(f"{sev:8s} {code:32s} {n:8d} {len(robots_by_code[(sev, code)]):6d}")
    if not args.no_mujoco:
        print(f"\nMuJoCo loads: {dict(mj)}")
        print("check errors vs MuJoCo (verdict, check has an error): "
              + ", ".join(f"{k}: {v}" for k, v in sorted(agree.items())))
    if args.json is not None:
        args.json.write_text(json.dumps(all_findings, indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main())
