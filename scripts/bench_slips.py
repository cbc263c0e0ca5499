"""Slips planted into real CAD inertials: how often ``fix`` finds the right edit.

Over the URDF robot packages found (``support.corpus.robot_packages``: example-robot-data,
pybullet_data, drake, robosuite and the gathered PyPI wheels), every link whose inertial
the default policy keeps as plausible, with geometry, is a CAD sample (de-duplicated across
robots and mirror twins: same mass and principal moments to 6 digits). Into each sample one
slip of each class is planted (a seeded random variant: which entry, which power of ten,
which direction) and the link judged again as ``check`` and ``fix`` do
(:func:`urdfinertia.plan.policy.decide_link`). Printed per class:

- right: an edit is proposed and gives back the CAD values (mass, CoM, tensor to 1e-9);
- wrong: an edit is proposed that does not (target: below 2 % of the planted slips);
- none, not flagged: the slip left the inertial valid and plausible, so nothing is searched;
- none, unclear: flagged, but no edit is clearly the one (the tensor is then derived or
  repaired as without the search).

Then every proposal on the robots as shipped (nothing planted), for a person to judge, and
the false-alarm rate: the search run on every clean sample as if ``check`` had flagged it
(``check`` does not: a clean link is never searched), and the proposals on all links.

``--twins`` lists instead the copies and mirror twins ``check`` reports over the same
robots (de-duplicated by file name).

Usage: ``nice python scripts/bench_slips.py [--max-files N] [--seed S] [--markdown]
[--twins]``
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

from urdfinertia.body.bounds import BoundsCache
from urdfinertia.body.options import FixOptions
from urdfinertia.cache.library import MeshLibrary
from urdfinertia.descriptions.formats import read_description
from urdfinertia.descriptions.inertial import RawInertial
from urdfinertia.descriptions.kinematics import Kinematics
from urdfinertia.descriptions.model import Inertial, Link, Origin, Robot
from urdfinertia.inertia.rotation import rpy_matrix
from urdfinertia.inertia.slips import SLIP_CLASSES, decimal_shift
from urdfinertia.judge.slips import find_slip
from urdfinertia.plan.policy import Decision, decide_link
from urdfinertia.plan.results import Action

OUTCOMES = ("right", "wrong", "none, not flagged", "none, unclear")


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


def recovers(decision: Decision, original: Inertial) -> bool:
    """The proposal gives back the CAD values (mass, CoM, tensor in the link frame)."""
    assert decision.slip is not None
    after = decision.slip.after
    raw = RawInertial.from_inertial(original)
    scale = float(np.abs(raw.inertia).max())
    return (math.isclose(after.mass, raw.mass, rel_tol=1e-9)
            and np.allclose(after.com, raw.com, rtol=1e-9, atol=1e-12)
            and np.allclose(after.inertia, raw.inertia, rtol=1e-9, atol=1e-9 * scale))


def outcome(decision: Decision, original: Inertial) -> str:
    if decision.slip is not None:
        return "right" if recovers(decision, original) else "wrong"
    flagged = {f.code for f in decision.findings if f.link == decision.link} - {
        "geometry-unreadable", "mesh-unresolved", "lumped-mass", "massless-frame"}
    return "none, unclear" if flagged else "none, not flagged"


def _key(i: Inertial) -> tuple:
    moments = np.linalg.eigvalsh(RawInertial.from_inertial(i).inertia)
    return (round(i.mass, 6), *np.round(moments / max(moments[-1], 1e-300), 6))


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--max-files", type=int, default=40, help="files per package (spread)")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--markdown", action="store_true", help="tables for docs/slips.md")
    ap.add_argument("--twins", action="store_true",
                    help="only list the copies and mirror twins check reports, per robot")
    args = ap.parse_args(argv)
    if args.twins:
        return list_twins(args.max_files, args.markdown)
    rng = np.random.default_rng(args.seed)
    options = FixOptions()
    meshes = MeshLibrary()
    counts: dict[str, Counter] = defaultdict(Counter)
    wrong: list[str] = []
    shipped: list[tuple[str, str, str, str]] = []
    seen: set[tuple] = set()
    samples = links_judged = 0
    clean_alarms: list[str] = []
    t0 = time.perf_counter()
    for package, files in packages(args.max_files).items():
        for path in files:
            try:
                robot, _ = read_description(path)
            except Exception:  # noqa: BLE001  (a file the reader refuses is not a sample)
                continue
            kin = Kinematics(robot)
            cache = BoundsCache(meshes)
            for link in robot.links:
                if link.inertial is None or not (link.collisions or link.visuals):
                    continue
                try:
                    d = decide_link(link, robot, kin, options, meshes, cache, path.parent)
                except Exception:  # noqa: BLE001
                    continue
                links_judged += 1
                if d.slip is not None:
                    shipped.append((package, path.name, link.name, d.slip.sentence()))
                if not (d.action == Action.KEEP and d.why == "plausible"):
                    continue
                key = _key(link.inertial)
                if key in seen:
                    continue
                seen.add(key)
                samples += 1
                # the search itself on a clean link, as if check had flagged it
                alarm = find_slip(link, {"inertia-vs-geometry"}, meshes, cache, options,
                                  path.parent)
                if alarm is not None:
                    clean_alarms.append(f"{package} {path.name} {link.name}: "
                                        f"{alarm.sentence()}")
                for slip in SLIP_CLASSES:
                    planted, name = plant(slip, link.inertial, rng)
                    judged = _judge(robot, kin, link, planted, options, meshes, cache, path)
                    if judged is None:
                        continue
                    result = outcome(judged, link.inertial)
                    counts[slip][result] += 1
                    if result == "wrong":
                        assert judged.slip is not None
                        wrong.append(f"{package} {path.name} {link.name}: planted {name}, "
                                     f"proposed {judged.slip.edit}")
    elapsed = time.perf_counter() - t0
    _print(counts, wrong, shipped, samples, links_judged, clean_alarms, elapsed,
           args.markdown)
    return 0


def list_twins(max_files: int, markdown: bool) -> int:
    """Every copy and mirror-twin finding over the corpus (robots de-duplicated by name)."""
    from urdfinertia.judge.twins import twin_findings

    meshes, seen, rows, robots = MeshLibrary(), set(), [], 0
    for package, files in packages(max_files).items():
        for path in files:
            try:
                robot, _ = read_description(path)
            except Exception:  # noqa: BLE001
                continue
            if path.name in seen:
                continue
            seen.add(path.name)
            robots += 1
            for f in twin_findings(robot, meshes, FixOptions()):
                rows.append([package, path.name, f.link or "", f.code, f.message])
    counts = Counter(r[3] for r in rows)
    print(f"{robots} robots: {counts['inertial-copied']} copies, "
          f"{counts['twins-disagree']} twins that disagree")
    _table(["package", "file", "link", "code", "message"], rows, markdown)
    return 0


def _judge(robot: Robot, kin: Kinematics, link: Link, planted: Inertial,
           options: FixOptions, meshes: MeshLibrary, cache: BoundsCache,
           path: Path) -> Decision | None:
    try:
        return decide_link(dataclasses.replace(link, inertial=planted), robot, kin, options,
                           meshes, cache, path.parent)
    except Exception:  # noqa: BLE001  (an inertial the model refuses: not a sample)
        return None


def _print(counts: dict[str, Counter], wrong: list[str], shipped: list, samples: int,
           links_judged: int, clean_alarms: list[str], elapsed: float, markdown: bool) -> None:
    total: Counter = Counter()
    for c in counts.values():
        total.update(c)
    head = ["slip class", "planted", *OUTCOMES]
    rows = []
    for slip in [*SLIP_CLASSES, "all"]:
        c = total if slip == "all" else counts[slip]
        n = sum(c.values())
        rows.append([slip, str(n), *(f"{c[o]} ({100 * c[o] / max(n, 1):.1f} %)"
                                     for o in OUTCOMES)])
    print(f"{samples} clean CAD samples (de-duplicated) out of {links_judged} links judged; "
          f"{sum(total.values())} slips planted; {elapsed:.0f} s")
    _table(head, rows, markdown)
    n = sum(total.values())
    print(f"\nwrong proposals: {total['wrong']} of {n} planted "
          f"({100 * total['wrong'] / max(n, 1):.2f} %; target below 2 %)")
    for line in wrong[:30]:
        print("  " + line)
    print(f"\nproposals on the robots as shipped: {len(shipped)} of {links_judged} links "
          f"({100 * len(shipped) / max(links_judged, 1):.2f} %)")
    print(f"false alarms: the search run on each of the {samples} clean samples as if "
          f"flagged proposes an edit on {len(clean_alarms)} "
          f"({100 * len(clean_alarms) / max(samples, 1):.2f} %)")
    for line in clean_alarms:
        print("  " + line)
    _table(["package", "file", "link", "proposal"], [list(s) for s in shipped], markdown)


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
