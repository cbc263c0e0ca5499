"""How close the default ``fix`` comes to CAD tensors, and whether its error bar is honest.

Over the robot packages found (example-robot-data, and every package folder under
``/work/corpus/urdf`` when present), each link whose inertial ``check`` finds plausible
(no error or warning), with geometry, is a CAD sample. Links are de-duplicated across
robots and mirrored twins (same mass and principal moments to 6 digits).

1. With the CAD values in place, the default ``fix`` must keep every such link: the count
   it changed is printed (target 0).
2. Each sample's tensor is withheld (zeroed; mass and CoM kept) and the default ``fix`` run:
   printed are the median, p75 and p90 of the relative Frobenius error of the derived
   tensor about the CoM, how often the CoM was kept exactly, and how often the error is
   inside the stated 80 % band, per package and pooled.

``--calibrate`` also prints each offset bin's 80th percentile (the constants of
``urdfinertia.link.errorbar``), on half of the packages, with the coverage on the others.

Usage: ``nice python scripts/bench_cad.py [--max-files N] [--calibrate]``
"""

from __future__ import annotations

import argparse
import dataclasses
import sys
import zlib
from collections import defaultdict
from pathlib import Path

import numpy as np

from urdfinertia.analysis.check import check_robot
from urdfinertia.cache.library import MeshLibrary
from urdfinertia.descriptions.formats import read_description
from urdfinertia.descriptions.inertial import RawInertial
from urdfinertia.errors import UrdfInertiaError
from urdfinertia.link.errorbar import OFFSET_EDGES
from urdfinertia.link.fix import fix_robot
from urdfinertia.link.options import FixOptions

CORPUS = Path("/work/corpus/urdf")


def packages() -> dict[str, list[Path]]:
    sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))
    from support.corpus import example_robot_data_dir

    out: dict[str, list[Path]] = {}
    erd = example_robot_data_dir()
    if erd is not None:
        out["example-robot-data"] = sorted((erd / "robots").rglob("*.urdf"))
    if CORPUS.is_dir():
        for d in sorted(CORPUS.iterdir()):
            if d.is_dir() and not d.name.startswith("_") and d.name != "example-robot-data":
                files = sorted(d.rglob("*.urdf"))
                if files:
                    out[d.name] = files
    return out


def package_dirs(package: str, path: Path) -> dict[str, Path]:
    if package == "example-robot-data":
        return {"example-robot-data": path.parents[2].parent}
    return {}


@dataclasses.dataclass
class Sample:
    package: str
    error: float
    com_kept: bool
    band: float
    offset: float | None


def run_file(package: str, path: Path, seen: set, meshes: MeshLibrary,
             ) -> tuple[list[Sample], int, int]:
    robot, data = read_description(path, lenient=True)
    findings = check_robot(robot, meshes=meshes)
    flagged = {f.link for f in findings if f.severity in ("error", "warning")}
    plausible = [lk for lk in robot.links if lk.inertial is not None and lk.name not in flagged
                 and (lk.collisions or lk.visuals) and lk.inertial.mass > 0]
    # 1. CAD values in place: the default fix must keep every plausible link
    result = fix_robot(robot, data, FixOptions(), meshes)
    changed = sum(r.assembly is not None for r in result.links
                  if r.name in {lk.name for lk in plausible})
    # 2. tensors withheld
    withheld = {}
    for lk in plausible:
        raw = RawInertial.from_inertial(lk.inertial)
        moments = np.linalg.eigvalsh(raw.inertia)
        key = (f"{raw.mass:.6g}", *(f"{m:.6g}" for m in moments))
        if key in seen:
            continue
        seen.add(key)
        withheld[lk.name] = raw
    if not withheld:
        return [], changed, len(plausible)
    zero = dict(ixx=0.0, ixy=0.0, ixz=0.0, iyy=0.0, iyz=0.0, izz=0.0)
    links = tuple(dataclasses.replace(lk, inertial=dataclasses.replace(lk.inertial, **zero))
                  if lk.name in withheld else lk for lk in robot.links)
    result = fix_robot(dataclasses.replace(robot, links=links), data, FixOptions(), meshes)
    out = []
    for r in result.links:
        cad = withheld.get(r.name)
        if cad is None or r.assembly is None or r.error_bar is None:
            continue
        got = r.assembly.total
        err = float(np.linalg.norm(got.inertia - cad.inertia) / np.linalg.norm(cad.inertia))
        out.append(Sample(package, err, bool(np.array_equal(got.com, cad.com)),
                          r.error_bar.band, r.error_bar.offset))
    return out, changed, len(plausible)


def line(name: str, s: list[Sample]) -> str:
    e = np.array([x.error for x in s])
    inside = np.mean([x.error <= x.band for x in s])
    kept = np.mean([x.com_kept for x in s])
    return (f"{name:32s} {len(s):5d}  {np.median(e):6.1%} {np.percentile(e, 75):6.1%} "
            f"{np.percentile(e, 90):6.1%}   {kept:6.1%}   {inside:6.1%}")


def calibrate(samples: list[Sample]) -> None:
    half = [zlib.crc32(s.package.encode()) % 2 for s in samples]
    for fold in (0, 1):
        fit = [s for s, h in zip(samples, half, strict=True) if h == fold]
        test = [s for s, h in zip(samples, half, strict=True) if h != fold]
        edges = (0.0, *OFFSET_EDGES, np.inf)
        bands = []
        for lo, hi in zip(edges[:-1], edges[1:], strict=True):
            e = [s.error for s in fit if s.offset is not None and lo <= s.offset < hi]
            bands.append(float(np.percentile(e, 80)) if e else float("nan"))
        model = [s.error for s in fit if s.offset is None]
        p80 = float(np.percentile(model, 80)) if model else float("nan")

        def band(s: Sample, bands=bands, p80=p80) -> float:
            if s.offset is None:
                return p80
            i = int(np.searchsorted(OFFSET_EDGES, s.offset, side="right"))
            return bands[i]

        cover = np.mean([s.error <= band(s) for s in test]) if test else float("nan")
        print(f"fold {fold}: fitted on {len(fit)} links; offset-bin p80 "
              f"{[round(b, 3) for b in bands]}, model p80 {p80:.3f}; "
              f"coverage on the other {len(test)}: {cover:.1%}")
    all_bins = []
    edges = (0.0, *OFFSET_EDGES, np.inf)
    for lo, hi in zip(edges[:-1], edges[1:], strict=True):
        e = [s.error for s in samples if s.offset is not None and lo <= s.offset < hi]
        all_bins.append((len(e), round(float(np.percentile(e, 80)), 3) if e else None))
    model = [s.error for s in samples if s.offset is None]
    print(f"pooled: offset-bin (n, p80) {all_bins}; model (n={len(model)}) p80 "
          f"{np.percentile(model, 80) if model else float('nan'):.3f}")


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--max-files", type=int, default=0, help="per package (0: all)")
    ap.add_argument("--calibrate", action="store_true")
    ap.add_argument("--packages", nargs="*", default=None, help="only these packages")
    args = ap.parse_args()
    found = packages()
    if not found:
        print("no robot packages found: nothing to measure")
        return 0
    samples: list[Sample] = []
    seen: set = set()
    changed = plausible = 0
    skipped: dict[str, int] = defaultdict(int)
    for package, files in found.items():
        if args.packages is not None and package not in args.packages:
            continue
        print(f"{package}: {len(files[:args.max_files or None])} file(s)", file=sys.stderr,
              flush=True)
        for path in files[:args.max_files or None]:
            meshes = MeshLibrary(package_dirs(package, path))
            try:
                got, c, p = run_file(package, path, seen, meshes)
            except (UrdfInertiaError, ValueError, RecursionError):
                skipped[package] += 1
                continue
            samples += got
            changed += c
            plausible += p
        mine = [x for x in samples if x.package == package]
        if mine:
            print("  " + line(package, mine), file=sys.stderr, flush=True)
    print(f"CAD values in place: the default fix changed {changed} of {plausible} plausible "
          "links (target 0)")
    print(f"files skipped (unreadable, missing meshes): {dict(skipped)}")
    print(f"{'package':32s} {'links':>5s}  {'median':>6s} {'p75':>6s} {'p90':>6s}   "
          f"{'CoM kept':>8s} {'in 80% band':>11s}")
    by: dict[str, list[Sample]] = defaultdict(list)
    for s in samples:
        by[s.package].append(s)
    for package, s in sorted(by.items()):
        print(line(package, s))
    if samples:
        print(line("pooled", samples))
    if args.calibrate and samples:
        calibrate(samples)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
