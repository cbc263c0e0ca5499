"""Slips planted into real CAD inertials: how often ``fix`` finds the right edit.

Over the URDF robot packages found (``support.corpus.robot_packages``: example-robot-data,
pybullet_data, drake, robosuite and the gathered PyPI wheels), every link whose inertial
the default ``fix`` keeps as plausible, with geometry, is a CAD sample (de-duplicated across
robots and mirror twins: same mass and principal moments to 6 digits). Two experiments,
each judging the whole robot again as ``check`` and ``fix`` do
(:func:`urdfinertia.plan.fix.verdicts`), so the robot's other links are evidence:

**One slip on one link.** Into each sample one slip of each class is planted (a seeded
random variant: which entry, which power of ten, which direction). Per class:

- right: the link is corrected back to the CAD values (mass, CoM, tensor to 1e-9);
- wrong: it is corrected to something else (target: below 1 % of the planted slips);
- none, not flagged: the slip left the inertial valid and plausible, nothing is searched;
- none, unclear: flagged, but no edit is clearly the one (the tensor is then derived or
  repaired as without the search);
- and, across classes, how often planting on one link changed another link's verdict.

**A convention of the whole file.** Into every inertial of a robot with at least
``--min-samples`` CAD samples one convention is planted: every tensor about its link's
origin, every product with CAD's sign, every mass and tensor in grams, every mass in
grams. Per convention: the robots wholly corrected (every CAD sample whose values the
convention changes comes back exactly), and the samples right, wrong and missed.

Usage: ``nice python scripts/bench_slips.py [--max-files N] [--seed S] [--markdown]
[--only one|file]``
"""

from __future__ import annotations

import argparse
import dataclasses
import math
import sys
import time
from collections import Counter, defaultdict
from pathlib import Path

import numpy as np

from urdfinertia.body.options import FixOptions
from urdfinertia.cache.library import MeshLibrary
from urdfinertia.descriptions.formats import read_description
from urdfinertia.descriptions.inertial import RawInertial
from urdfinertia.descriptions.model import Inertial, Origin, Robot
from urdfinertia.inertia.rotation import rpy_matrix
from urdfinertia.inertia.slips import SLIP_CLASSES, decimal_shift
from urdfinertia.plan.fix import verdicts
from urdfinertia.plan.results import Action, LinkResult

OUTCOMES = ("right", "wrong", "none, not flagged", "none, unclear")
#: The whole-file conventions planted: name -> the slip class planted into every link.
CONVENTIONS = {"tensor about the link origin": "parallel-axis",
               "products with CAD's sign": "products-sign",
               "mass and tensor in grams": "inertial-unit",
               "mass in grams": "mass-up"}
#: Findings that say nothing about the planted values (the reader's, the meshes').
QUIET = {"geometry-unreadable", "mesh-unresolved", "lumped-mass", "massless-frame",
         "mesh-repaired", "geometry-not-body"}


def packages(max_files: int) -> dict[str, list[Path]]:
    sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))
    from support.corpus import robot_packages

    out = {}
    for name, files in robot_packages(("urdf",)).items():
        step = max(1, math.ceil(len(files) / max_files))
        out[name] = files[::step]
    return out


def _entries(i: Inertial) -> np.ndarray:
    return np.array([i.ixx, i.ixy, i.ixz, i.iyy, i.iyz, i.izz])


def _with(i: Inertial, mass: float | None = None, xyz: np.ndarray | None = None,
          rpy: np.ndarray | None = None, entries: np.ndarray | None = None) -> Inertial:
    e = _entries(i) if entries is None else entries
    origin = Origin(tuple(i.origin.xyz if xyz is None else xyz.tolist()),  # type: ignore[arg-type]
                    tuple(i.origin.rpy if rpy is None else rpy.tolist()))  # type: ignore[arg-type]
    return dataclasses.replace(i, origin=origin, mass=i.mass if mass is None else mass,
                               ixx=e[0], ixy=e[1], ixz=e[2], iyy=e[3], iyz=e[4], izz=e[5])


def plant(slip: str, i: Inertial, rng: np.random.Generator) -> tuple[Inertial, str]:
    """The inertial ``i`` with one slip of class ``slip`` made in it, and its name."""
    e = _entries(i)
    sign = int(rng.choice([-1, 1]))
    if slip == "entry-power":
        nonzero = [k for k in range(6) if e[k] != 0]
        which = int(rng.choice(nonzero))
        k = int(rng.choice([x for x in range(-9, 10) if x != 0]))
        e = e.copy()
        e[which] = decimal_shift(e[which], k)[0]
        return _with(i, entries=e), f"entry {which} x1e{k:+d}"
    if slip == "mass-unit":
        return _with(i, mass=decimal_shift(i.mass, 3 * sign)[0]), f"mass x1e{3 * sign:+d}"
    if slip == "inertial-unit":  # the whole inertial in grams
        return (_with(i, mass=decimal_shift(i.mass, 3)[0], entries=decimal_shift(e, 3)),
                "mass and tensor x1e+3")
    if slip == "tensor-unit":
        k = int(rng.choice([3, 6, 9])) * sign
        return _with(i, entries=decimal_shift(e, k)), f"tensor x1e{k:+d}"
    if slip == "com-unit":
        return (_with(i, xyz=decimal_shift(np.asarray(i.origin.xyz), 3 * sign)),
                f"com x1e{3 * sign:+d}")
    if slip == "products-sign":
        e = e.copy()
        e[[1, 2, 4]] *= -1
        return _with(i, entries=e), "products negated"
    if slip == "product-sign":
        nonzero = [k for k in (1, 2, 4) if e[k] != 0] or [1]
        which = int(rng.choice(nonzero))
        e = e.copy()
        e[which] *= -1
        return _with(i, entries=e), f"entry {which} negated"
    if slip == "order":
        if rng.random() < 0.5:  # MuJoCo's fullinertia order read as URDF's
            return _with(i, entries=np.array([e[0], e[3], e[5], e[1], e[2], e[4]])), \
                "diagonal first"
        a, b = [int(x) for x in rng.choice([1, 2, 4], size=2, replace=False)]
        e = e.copy()
        e[[a, b]] = e[[b, a]]
        return _with(i, entries=e), f"products {a}/{b} swapped"
    if slip == "parallel-axis":
        raw = RawInertial.from_inertial(i)
        c = raw.com
        about_origin = raw.inertia + i.mass * (float(c @ c) * np.eye(3) - np.outer(c, c))
        rot = rpy_matrix(i.origin.rpy)
        t = rot.T @ about_origin @ rot
        return _with(i, entries=np.array([t[0, 0], t[0, 1], t[0, 2], t[1, 1], t[1, 2],
                                          t[2, 2]])), "about the link origin"
    if slip == "rpy":
        truth = RawInertial.from_inertial(i).inertia
        rpy = rng.uniform(-math.pi / 2, math.pi / 2, 3)
        if rng.random() < 0.5:  # entries along the link's axes, an rpy written as well
            t = truth
            name = "rpy ignored"
        else:  # the rotation given the other way round
            rot = rpy_matrix(rpy)
            t = rot @ truth @ rot.T
            name = "rpy inverted"
        return _with(i, rpy=rpy, entries=np.array([t[0, 0], t[0, 1], t[0, 2], t[1, 1],
                                                   t[1, 2], t[2, 2]])), name
    raise ValueError(slip)


def recovers(r: LinkResult, original: Inertial) -> bool:
    """The correction gives back the CAD values (mass, CoM, tensor in the link frame)."""
    after = r.after
    if after is None:
        return False
    raw = RawInertial.from_inertial(original)
    scale = float(np.abs(raw.inertia).max())
    return (math.isclose(after.mass, raw.mass, rel_tol=1e-9)
            and np.allclose(after.com, raw.com, rtol=1e-9, atol=1e-12)
            and np.allclose(after.inertia, raw.inertia, rtol=1e-9, atol=1e-9 * scale))


def outcome(r: LinkResult, original: Inertial) -> str:
    if r.action == Action.CORRECT:
        return "right" if recovers(r, original) else "wrong"
    flagged = {f.code for f in r.findings if f.severity != "info"} - QUIET
    return "none, unclear" if flagged else "none, not flagged"


def _key(i: Inertial) -> tuple:
    moments = np.linalg.eigvalsh(RawInertial.from_inertial(i).inertia)
    return (round(i.mass, 6), *np.round(moments / max(moments[-1], 1e-300), 6))


def with_inertials(robot: Robot, planted: dict[str, Inertial]) -> Robot:
    """``robot`` with the inertials of ``planted`` in place of its own."""
    links = tuple(dataclasses.replace(lk, inertial=planted[lk.name]) if lk.name in planted
                  else lk for lk in robot.links)
    return dataclasses.replace(robot, links=links)


def judged(robot: Robot, options: FixOptions, meshes: MeshLibrary,
           ) -> dict[str, LinkResult] | None:
    try:
        return {r.name: r for r in verdicts(robot, options, meshes).links}
    except Exception:  # noqa: BLE001  (a robot the model refuses: not a sample)
        return None


def _verdict(r: LinkResult) -> tuple:
    after = r.after
    values = None if after is None else (round(after.mass, 12),
                                         *np.round(after.inertia.ravel(), 15))
    return (r.action, values)


def plant_file(convention: str, robot: Robot, rng: np.random.Generator,
               ) -> dict[str, Inertial]:
    """Every inertial of ``robot`` with the convention's slip made in it."""
    slip = CONVENTIONS[convention]
    out = {}
    for link in robot.links:
        i = link.inertial
        if i is None or not i.mass > 0:
            continue
        if slip == "mass-up":
            out[link.name] = _with(i, mass=decimal_shift(i.mass, 3)[0])
        else:
            out[link.name] = plant(slip, i, rng)[0]
    return out


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--max-files", type=int, default=40, help="files per package (spread)")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--min-samples", type=int, default=3,
                    help="CAD samples a robot needs for the whole-file experiment")
    ap.add_argument("--only", choices=("one", "file"), help="run one experiment only")
    ap.add_argument("--markdown", action="store_true", help="tables for docs/slips.md")
    args = ap.parse_args(argv)
    rng = np.random.default_rng(args.seed)
    options = FixOptions()
    meshes = MeshLibrary()
    counts: dict[str, Counter] = defaultdict(Counter)
    files: dict[str, Counter] = defaultdict(Counter)
    wrong: list[str] = []
    shipped: list[list[str]] = []
    seen: set[tuple] = set()
    samples = links_judged = planted_runs = collateral = 0
    t0 = time.perf_counter()
    for package, paths in packages(args.max_files).items():
        for path in paths:
            try:
                robot, _ = read_description(path)
            except Exception:  # noqa: BLE001  (a file the reader refuses is not a sample)
                continue
            clean = judged(robot, options, meshes)
            if clean is None:
                continue
            links_judged += len(clean)
            shipped += [[package, path.name, r.name, r.decision] for r in clean.values()
                        if r.action == Action.CORRECT]
            cad = [lk for lk in robot.links if lk.inertial is not None
                   and (lk.collisions or lk.visuals) and clean[lk.name].action == Action.KEEP
                   and clean[lk.name].why == "plausible"]
            if args.only != "file":
                for link in cad:
                    key = _key(link.inertial)
                    if key in seen:
                        continue
                    seen.add(key)
                    samples += 1
                    for slip in SLIP_CLASSES:
                        planted, name = plant(slip, link.inertial, rng)
                        after = judged(with_inertials(robot, {link.name: planted}), options,
                                       meshes)
                        if after is None:
                            continue
                        planted_runs += 1
                        result = outcome(after[link.name], link.inertial)
                        counts[slip][result] += 1
                        collateral += any(_verdict(after[n]) != _verdict(clean[n])
                                          for n in clean if n != link.name)
                        if result == "wrong":
                            wrong.append(f"{package} {path.name} {link.name}: planted "
                                         f"{name}, got {after[link.name].decision}")
            if args.only != "one" and len(cad) >= args.min_samples:
                for convention in CONVENTIONS:
                    planted_all = plant_file(convention, robot, rng)
                    after = judged(with_inertials(robot, planted_all), options, meshes)
                    if after is None:
                        continue
                    changed = [lk for lk in cad if planted_all[lk.name] != lk.inertial]
                    results = Counter(outcome(after[lk.name], lk.inertial) for lk in changed)
                    c = files[convention]
                    c["robots"] += 1
                    c["wholly corrected"] += results["right"] == len(changed) > 0
                    c["samples"] += len(changed)
                    for k, v in results.items():
                        c[k] += v
                    wrong += [f"{package} {path.name} {lk.name}: planted {convention} on the "
                              f"file, got {after[lk.name].decision}" for lk in changed
                              if outcome(after[lk.name], lk.inertial) == "wrong"]
    elapsed = time.perf_counter() - t0
    _print(counts, files, wrong, shipped, samples, links_judged, planted_runs, collateral,
           elapsed, args.markdown)
    return 0


def _print(counts: dict[str, Counter], files: dict[str, Counter], wrong: list[str],
           shipped: list[list[str]], samples: int, links_judged: int, planted_runs: int,
           collateral: int, elapsed: float, markdown: bool) -> None:
    total: Counter = Counter()
    for c in counts.values():
        total.update(c)
    print(f"{samples} clean CAD samples (de-duplicated) out of {links_judged} links judged; "
          f"{sum(total.values())} one-link slips planted; {elapsed:.0f} s")
    if total:
        rows = []
        for slip in [*SLIP_CLASSES, "all"]:
            c = total if slip == "all" else counts[slip]
            n = sum(c.values())
            rows.append([slip, str(n), *(f"{c[o]} ({100 * c[o] / max(n, 1):.1f} %)"
                                         for o in OUTCOMES)])
        _table(["slip class", "planted", *OUTCOMES], rows, markdown)
        n = sum(total.values())
        print(f"\nwrong corrections: {total['wrong']} of {n} planted "
              f"({100 * total['wrong'] / max(n, 1):.2f} %; target below 1 %); planting on one "
              f"link changed another link's verdict in {collateral} of {planted_runs} runs")
    if files:
        rows = []
        for convention, c in files.items():
            n = max(c["samples"], 1)
            whole = c["wholly corrected"]
            rows.append([convention, str(c["robots"]),
                         f"{whole} ({100 * whole / max(c['robots'], 1):.0f} %)",
                         str(c["samples"]), f"{c['right']} ({100 * c['right'] / n:.1f} %)",
                         f"{c['wrong']} ({100 * c['wrong'] / n:.1f} %)",
                         f"{c['none, not flagged'] + c['none, unclear']} "
                         f"({100 * (c['none, not flagged'] + c['none, unclear']) / n:.1f} %)"])
        print("\nwhole-file conventions planted:")
        _table(["convention", "robots", "wholly corrected", "CAD samples", "right", "wrong",
                "missed"], rows, markdown)
    for line in wrong[:40]:
        print("  " + line)
    print(f"\ncorrections on the robots as shipped: {len(shipped)} of {links_judged} links "
          f"({100 * len(shipped) / max(links_judged, 1):.2f} %)")
    _table(["package", "file", "link", "decision"], shipped, markdown)


def _table(head: list[str], rows: list[list[str]], markdown: bool) -> None:
    if markdown:
        print("| " + " | ".join(head) + " |")
        print("|" + "|".join("---" for _ in head) + "|")
        for r in rows:
            print("| " + " | ".join(r) + " |")
        return
    widths = [max(len(str(x)) for x in col) for col in zip(head, *rows, strict=False)]
    for r in [head, *rows]:
        print("  ".join(str(x).ljust(w) for x, w in zip(r, widths, strict=False)))


if __name__ == "__main__":
    raise SystemExit(main())
