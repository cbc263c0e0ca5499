"""How close the default ``fix`` comes to CAD tensors, and whether its error bar is honest.

Over every robot package found (``support.corpus.robot_packages``: URDF, SDFormat and
MJCF), each link whose inertial ``check`` finds plausible (no error or warning), with
geometry, is a CAD sample. Links are de-duplicated across robots and mirrored twins (same
mass and principal moments to 6 digits).

1. With the CAD values in place, the default ``fix`` must keep every such link: the count
   it changed is printed (target 0).
2. Each sample's tensor is withheld (zeroed; mass and CoM kept) and the default ``fix`` run.
   Per package and pooled: the median and p90 of the relative Frobenius error of the
   derived tensor about the CoM, and how often the error is inside the stated 80 % band.
   Side by side, on the same links:

   - ``prev``: the previous choice (MuJoCo's counted geoms, else collision, else visual;
     the visuals only when no collision element can be read);
   - ``mujoco``: MuJoCo's own inertia from geoms (``inertiafromgeom="true"``), scaled to
     the CAD mass (MJCF files only; bodies MuJoCo gives mass).

``--calibrate`` fits the 80th percentile of the error per kind of geometry, role and
centroid-to-CoM offset bin (the constants of ``urdfinertia.body.errorbar``), with the
coverage of each package under bands fitted on the other packages (leave one package
out), then on all packages.

Usage: ``nice python scripts/bench_cad.py [--max-files N] [--file-seconds S] [--calibrate]
[--packages P ...] [--samples FILE]``; ``--from-samples FILE ...`` reports saved samples
without measuring again (bands as calibrated now).
"""

from __future__ import annotations

import argparse
import contextlib
import dataclasses
import signal
import sys
from collections import defaultdict
from collections.abc import Callable, Iterator
from pathlib import Path

import numpy as np

from urdfinertia.analysis.check import check_robot
from urdfinertia.body import geometry_choice
from urdfinertia.body.errorbar import (
    BAND_LEVEL,
    BANDS,
    DENSE,
    DENSE_CELL,
    OFFSET_EDGES,
    band_key,
    is_dense,
    lookup_band,
    offset_bin,
)
from urdfinertia.body.options import FixOptions, select_geometry, weighable
from urdfinertia.cache.library import MeshLibrary, mesh_library
from urdfinertia.descriptions.formats import read_description
from urdfinertia.descriptions.inertial import RawInertial
from urdfinertia.descriptions.model import Link, Robot
from urdfinertia.errors import UrdfInertiaError
from urdfinertia.plan.fix import fix_robot

FORMATS = ("urdf", "sdf", "mjcf")
#: Fewer samples than this in a (kind, role, bin) cell: the cell takes its kind's band.
MIN_CELL = 12
#: Fitting quantiles tried by ``--calibrate``: the one whose cross-validated coverage is
#: nearest the stated level is used (the pooled 80th percentile of the other packages
#: under-covers a package harder than they are).
QUANTILES = (0.80, 0.85, 0.90)
#: Packages with at least this many links are judged on their own coverage.
BIG_PACKAGE = 10
#: The targets of the cross-validated coverage: pooled, and the floor of every package of
#: at least :data:`BIG_PACKAGE` links.
POOLED_TARGET = (0.75, 0.85)
PACKAGE_FLOOR = 0.60


def packages() -> dict[str, list[Path]]:
    sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))
    from support.corpus import robot_packages

    return robot_packages(FORMATS)


def package_dirs(package: str, path: Path) -> dict[str, Path]:
    if package == "example-robot-data":
        return {"example-robot-data": path.parents[2].parent}
    return {}


@dataclasses.dataclass
class Sample:
    package: str
    error: float
    band: float
    offset: float | None
    kind: str
    role: str
    prev: float | None = None  # the previous choice's error
    mujoco: float | None = None  # MuJoCo's inertia from geoms, scaled to the CAD mass
    file: str = ""
    link: str = ""
    density: float | None = None  # kept mass over the chosen geometry's volume, kg/m^3

    @property
    def key(self) -> tuple[str | None, str | None, int | None]:
        return (*band_key(self.kind, self.role), None if self.offset is None
                else offset_bin(self.offset))

    def cells(self, dense_apart: bool) -> tuple[tuple, ...]:
        """The :data:`BANDS` cells this sample is fitted into, finest first."""
        if dense_apart and is_dense(self.density):
            return (DENSE_CELL,)
        kind, role, b = self.key
        return ((kind, role, b), (kind, None, b), (None, None, b))


def _previous_sets(link: Link) -> list[tuple[str, tuple]]:
    role, refs = select_geometry(link, "auto")
    sets = [(role, refs)] if refs else []
    if role == "collision" and link.visuals:
        sets.append(("visual", weighable(link.visuals)))
    return sets


_CHOOSE = geometry_choice.choose


def _first(candidates, mass, com):  # type: ignore[no-untyped-def]
    best = candidates[0]
    return best, _CHOOSE([best], mass, com)[1]


def run_fix(robot: Robot, data: bytes, meshes: MeshLibrary, previous: bool):  # type: ignore[no-untyped-def]
    """The default fix; ``previous``: with the previous choice of geometry."""
    if not previous:
        return fix_robot(robot, data, FixOptions(), meshes)
    saved: tuple[Callable, Callable] = (geometry_choice.candidate_sets, geometry_choice.choose)
    geometry_choice.candidate_sets = _previous_sets  # type: ignore[assignment]
    geometry_choice.choose = _first  # type: ignore[assignment]
    try:
        return fix_robot(robot, data, FixOptions(), meshes)
    finally:
        geometry_choice.candidate_sets, geometry_choice.choose = saved  # type: ignore[assignment]


def _mujoco_tensors(path: Path) -> dict[str, tuple[float, np.ndarray]] | None:
    """Body name -> (mass, tensor about its CoM, body axes) MuJoCo computes from geoms."""
    try:
        import mujoco
    except ImportError:
        return None
    try:
        spec = mujoco.MjSpec.from_file(str(path))
        spec.compiler.inertiafromgeom = mujoco.mjtInertiaFromGeom.mjINERTIAFROMGEOM_TRUE
        model = spec.compile()
    except Exception:  # noqa: BLE001  (any file MuJoCo cannot compile: no column)
        return None
    out = {}
    for i in range(1, model.nbody):
        name = mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_BODY, i)
        w, x, y, z = model.body_iquat[i]
        r = np.array([
            [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
            [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
            [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]])
        out[name or f"body#{i}"] = (float(model.body_mass[i]),
                                    r @ np.diag(model.body_inertia[i]) @ r.T)
    return out


def _file_name(path: Path) -> str:
    """The description as ``folder/name`` (many robots are each a ``robot.xml``)."""
    return f"{path.parent.name}/{path.name}"


def _err(got: np.ndarray, cad: np.ndarray) -> float:
    return float(np.linalg.norm(got - cad) / np.linalg.norm(cad))


def plausible_links(robot: Robot, meshes: MeshLibrary) -> list[Link]:
    """The robot's CAD samples: links whose inertial ``check`` finds plausible (no error or
    warning), with geometry, a positive mass, and writable."""
    findings = check_robot(robot, meshes=meshes)
    flagged = {f.link for f in findings if f.severity in ("error", "warning")}
    return [lk for lk in robot.links if lk.inertial is not None and lk.name not in flagged
            and (lk.collisions or lk.visuals) and lk.inertial.mass > 0
            and lk.read_only is None]


def link_key(raw: RawInertial) -> tuple[str, ...]:
    """What de-duplicates links across robots and mirrored twins: the mass and principal
    moments to 6 digits."""
    moments = np.linalg.eigvalsh(raw.inertia)
    return (f"{raw.mass:.6g}", *(f"{m:.6g}" for m in moments))


def run_file(package: str, path: Path, seen: set, meshes: MeshLibrary,
             ) -> tuple[list[Sample], int, int]:
    robot, data = read_description(path)
    plausible = plausible_links(robot, meshes)
    # 1. CAD values in place: the default fix must keep every plausible link
    result = fix_robot(robot, data, FixOptions(), meshes)
    names = {lk.name for lk in plausible}
    changed = sum(r.changed for r in result.links if r.name in names)
    # 2. tensors withheld
    withheld = {}
    for lk in plausible:
        raw = RawInertial.from_inertial(lk.inertial)
        key = link_key(raw)
        if key in seen:
            continue
        seen.add(key)
        withheld[lk.name] = raw
    if not withheld:
        return [], changed, len(plausible)
    zero = dict(ixx=0.0, ixy=0.0, ixz=0.0, iyy=0.0, iyz=0.0, izz=0.0)
    links = tuple(dataclasses.replace(lk, inertial=dataclasses.replace(lk.inertial, **zero))
                  if lk.name in withheld else lk for lk in robot.links)
    damaged = dataclasses.replace(robot, links=links)
    new = fix_robot(damaged, data, FixOptions(), meshes)
    old = {r.name: r for r in run_fix(damaged, data, meshes, previous=True).links}
    engine = _mujoco_tensors(path) if robot.format == "mjcf" else None
    if DUMP is not None:
        _dump_candidates(package, path, damaged, withheld, meshes)
    out = []
    for r in new.links:
        cad = withheld.get(r.name)
        if cad is None or r.assembly is None or r.error_bar is None or r.choice is None:
            continue
        s = Sample(package, _err(r.assembly.total.inertia, cad.inertia), r.error_bar.band,
                   r.error_bar.offset, r.choice.kind, r.choice.role, file=_file_name(path),
                   link=r.name, density=r.choice.density)
        prev = old.get(r.name)
        if prev is not None and prev.assembly is not None:
            s.prev = _err(prev.assembly.total.inertia, cad.inertia)
        if engine is not None and r.name in engine and engine[r.name][0] > 0:
            mass, tensor = engine[r.name]
            s.mujoco = _err(tensor * (cad.mass / mass), cad.inertia)
        out.append(s)
    return out, changed, len(plausible)


#: ``--dump``: where every candidate geometry of every sample is written (JSON lines)
DUMP: Path | None = None


def _dump_candidates(package: str, path: Path, robot: Robot, withheld: dict,
                     meshes: MeshLibrary) -> None:
    """Each sample's candidate geometries, their features and errors (for tuning)."""
    import json

    from urdfinertia.body.assemble import assemble
    from urdfinertia.body.mass import MassSource

    base = path.parent
    rows = []
    for link in robot.links:
        cad = withheld.get(link.name)
        if cad is None:
            continue
        for role, refs in geometry_choice.candidate_sets(link):
            try:
                c = geometry_choice.evaluate(link, role, refs, meshes, base)
                if c is None:
                    continue
                got = assemble(list(c.parts), MassSource("kept", cad.mass)).total
            except (UrdfInertiaError, ValueError):
                continue
            box = _box(refs, meshes, base)
            rows.append({"package": package, "file": _file_name(path), "link": link.name,
                         "role": role, "kind": c.kind, "volume": c.volume,
                         "dropped": len(c.dropped), "diagonal": c.diagonal,
                         "offset": float(np.linalg.norm(c.centroid - cad.com)),
                         "mass": cad.mass, "error": _err(got.inertia, cad.inertia),
                         "elements": len(refs), "centroid": c.centroid.tolist(),
                         "com": np.asarray(cad.com).tolist(),
                         "box": None if box is None else [box[0].tolist(), box[1].tolist()],
                         "moments": np.linalg.eigvalsh(got.inertia).tolist(),
                         "cad_moments": np.linalg.eigvalsh(cad.inertia).tolist()})
    with open(DUMP, "a") as f:
        for row in rows:
            f.write(json.dumps(row) + "\n")


def _box(refs: tuple, meshes: MeshLibrary, base: Path) -> tuple | None:
    from urdfinertia.body.bounds import BoundsCache, link_bounds

    try:
        return link_bounds(refs, BoundsCache(meshes), base)
    except UrdfInertiaError:
        return None


def _pct(values: list[float], q: float) -> str:
    return f"{np.percentile(values, q):6.1%}" if values else f"{'-':>6s}"


def line(name: str, s: list[Sample]) -> str:
    e = [x.error for x in s]
    inside = np.mean([x.error <= x.band for x in s])
    prev = [x.prev for x in s if x.prev is not None]
    both = [x for x in s if x.mujoco is not None]
    mj = [x.mujoco for x in both if x.mujoco is not None]
    ours_mj = [x.error for x in both]
    return (f"{name:20s} {len(s):5d}  {_pct(e, 50)} {_pct(e, 90)} {inside:6.1%}   "
            f"{_pct(prev, 50)} {_pct(prev, 90)}   {len(both):4d} {_pct(mj, 50)} "
            f"{_pct(ours_mj, 50)}")


HEADER = (f"{'package':20s} {'links':>5s}  {'median':>6s} {'p90':>6s} {'in 80%':>6s}   "
          f"{'prev50':>6s} {'prev90':>6s}   {'n mj':>4s} {'mj 50':>6s} {'ours50':>6s}")


def fit_bands(samples: list[Sample], quantile: float = BAND_LEVEL) -> dict[tuple, float]:
    """The ``quantile`` of the error per (kind, role, bin) cell; cells with fewer than
    :data:`MIN_CELL` samples are left out (they take coarser cells' bands)."""
    fitted = [s for s in samples if s.offset is not None]
    # dense geometry has its own cell when there are enough such links to fit one
    apart = sum(is_dense(s.density) for s in fitted) >= MIN_CELL
    cells: dict[tuple, list[float]] = defaultdict(list)
    for s in fitted:
        for key in s.cells(apart):
            cells[key].append(s.error)
    return {k: float(np.percentile(v, 100 * quantile)) for k, v in cells.items()
            if len(v) >= MIN_CELL or k[0] is None}


def band_of(bands: dict[tuple, float], s: Sample) -> float:
    if s.offset is None:
        return s.band  # CoM derived too: the model band, not fitted here
    return lookup_band(bands, s.kind, s.role, s.offset, s.density)


def cross_validated(samples: list[Sample], quantile: float) -> dict[str, list[bool]]:
    """Per package, whether each link's error is inside the band fitted (at ``quantile``)
    on the other packages."""
    out: dict[str, list[bool]] = {}
    for package in sorted({s.package for s in samples}):
        fit = [s for s in samples if s.package != package and s.offset is not None]
        if not fit:
            continue
        bands = fit_bands(fit, quantile)
        out[package] = [s.error <= band_of(bands, s) for s in samples if s.package == package]
    return out


def calibrate(samples: list[Sample]) -> float:
    """Print the cross-validated coverage per package for a few fitting quantiles; return
    the lowest (narrowest bands) that meets the targets (:data:`POOLED_TARGET` pooled, no
    package of at least :data:`BIG_PACKAGE` links below :data:`PACKAGE_FLOOR`), else the
    one whose pooled coverage is nearest the stated level."""
    print(f"\ncross-validation by package (bands fitted on the other packages), stated level "
          f"{BAND_LEVEL:.0%}, offset bins {OFFSET_EDGES}, cells of at least {MIN_CELL}, "
          f"dense above {DENSE:.0f} kg/m3:")
    nearest, gap = BAND_LEVEL, np.inf
    meets: list[float] = []
    for quantile in QUANTILES:
        cv = cross_validated(samples, quantile)
        pooled = float(np.mean([x for v in cv.values() for x in v]))
        per = ", ".join(f"{p} {np.mean(v):.0%} (n={len(v)})" for p, v in cv.items())
        big = {p: float(np.mean(v)) for p, v in cv.items() if len(v) >= BIG_PACKAGE}
        low = min(big, key=big.__getitem__) if big else None
        print(f"  fitted at p{100 * quantile:.0f}: pooled {pooled:.1%}; {per}")
        if low is not None:
            print(f"    lowest of the {len(big)} packages of at least {BIG_PACKAGE} links: "
                  f"{low} {big[low]:.0%}")
        if POOLED_TARGET[0] <= pooled <= POOLED_TARGET[1] and (
                low is None or big[low] >= PACKAGE_FLOOR):
            meets.append(quantile)
        if abs(pooled - BAND_LEVEL) < gap:
            nearest, gap = quantile, abs(pooled - BAND_LEVEL)
    if meets:
        print(f"  the lowest that meets the targets: fitted at p{100 * min(meets):.0f}")
        return min(meets)
    print(f"  none meets the targets; nearest the stated level: fitted at p{100 * nearest:.0f}")
    return nearest


def print_bands(samples: list[Sample], quantile: float) -> None:
    bands = fit_bands(samples, quantile)
    print(f"\nBANDS fitted on all packages at p{100 * quantile:.0f} (kind, role, offset "
          "bin): band (n)")
    counts: dict[tuple, int] = defaultdict(int)
    apart = DENSE_CELL in bands
    for s in samples:
        if s.offset is not None:
            for key in s.cells(apart):
                counts[key] += 1
    inside: dict[str, list[bool]] = defaultdict(list)
    for s in samples:
        inside[s.package].append(s.error <= band_of(bands, s))
    pooled = [x for v in inside.values() for x in v]
    print(f"coverage with these bands (in sample): pooled {np.mean(pooled):.1%}; " + ", ".join(
        f"{p} {np.mean(v):.0%}" for p, v in sorted(inside.items())))
    print("band widths by geometry used (median and p90 of the stated band, coverage):")
    kinds: dict[str, list[Sample]] = defaultdict(list)
    for s in samples:
        if s.offset is not None:
            dense = f" above {DENSE:.0f} kg/m3" if apart and is_dense(s.density) else ""
            kinds[f"{s.kind}/{band_key(s.kind, s.role)[1]}{dense}"].append(s)
    for k, group in sorted(kinds.items()):
        widths = [band_of(bands, s) for s in group]
        errors = [s.error for s in group]
        covered = np.mean([e <= w for e, w in zip(errors, widths, strict=True)])
        print(f"  {k:20s} n={len(group):4d}  band median {np.median(widths):5.0%}, p90 "
              f"{np.percentile(widths, 90):5.0%}; error median {np.median(errors):5.1%}; "
              f"covered {covered:.0%}")
    print("BANDS = {")
    for key, value in sorted(bands.items(), key=str):
        print(f"    {key!r}: {value:.2f},  # n={counts[key]}")
    print("}")


@contextlib.contextmanager
def _time_limit(seconds: int) -> Iterator[None]:
    """Raise TimeoutError in the body after ``seconds`` (0: never; POSIX only)."""
    if seconds <= 0:
        yield
        return

    def expired(signum: int, frame: object) -> None:
        raise TimeoutError(f"took longer than {seconds} s")

    previous = signal.signal(signal.SIGALRM, expired)
    signal.alarm(seconds)
    try:
        yield
    finally:
        signal.alarm(0)
        signal.signal(signal.SIGALRM, previous)


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--max-files", type=int, default=0, help="per package (0: all)")
    ap.add_argument("--calibrate", action="store_true")
    ap.add_argument("--packages", nargs="*", default=None, help="only these packages")
    ap.add_argument("--dump", type=Path, default=None,
                    help="append every sample's candidate geometries and errors (JSON lines)")
    ap.add_argument("--samples", type=Path, default=None,
                    help="append every sample (package, link, errors, band) as JSON lines")
    ap.add_argument("--file-seconds", type=int, default=0,
                    help="skip a file that takes longer than this (0: no limit)")
    ap.add_argument("--from-samples", type=Path, nargs="*", default=None,
                    help="measure nothing: report the samples of these --samples files, "
                    "bands as calibrated now")
    args = ap.parse_args()
    if args.from_samples is not None:
        samples = [x for path in args.from_samples for x in read_samples(path)]
        report(samples, args.calibrate)
        return 0
    global DUMP
    DUMP = args.dump
    found = packages()
    if not found:
        print("no robot packages found: nothing to measure")
        return 0
    samples = []
    seen: set = set()
    changed = plausible = 0
    skipped: dict[str, int] = defaultdict(int)
    # the smaller packages first: a run stopped early has measured the most packages
    for package, files in sorted(found.items(), key=lambda kv: (len(kv[1]), kv[0])):
        if args.packages is not None and package not in args.packages:
            continue
        files = files[:args.max_files or None]
        print(f"{package}: {len(files)} file(s)", file=sys.stderr, flush=True)
        for path in files:
            meshes = mesh_library(package_dirs(package, path))
            try:
                with _time_limit(args.file_seconds):
                    got, c, p = run_file(package, path, seen, meshes)
            except (UrdfInertiaError, ValueError, RecursionError, OSError,
                    TimeoutError) as exc:
                if not skipped[package] or isinstance(exc, TimeoutError):
                    print(f"  skipped {_file_name(path)}: {exc}", file=sys.stderr)
                skipped[package] += 1
                continue
            samples += got
            if args.samples is not None:
                import json

                with open(args.samples, "a") as f:
                    for x in got:
                        f.write(json.dumps(dataclasses.asdict(x)) + "\n")
            changed += c
            plausible += p
        mine = [x for x in samples if x.package == package]
        if mine:
            print("  " + line(package, mine), file=sys.stderr, flush=True)
    print(f"CAD values in place: the default fix changed {changed} of {plausible} plausible "
          "links (target 0)")
    print(f"files skipped (unreadable, missing meshes, over --file-seconds): {dict(skipped)}")
    report(samples, args.calibrate)
    return 0


def read_samples(path: Path) -> list[Sample]:
    """The samples of a ``--samples`` file, each band read again from the bands in use."""
    import json

    out = []
    for text in path.read_text().splitlines():
        x = Sample(**json.loads(text))
        if x.offset is not None:
            x.band = lookup_band(BANDS, x.kind, x.role, x.offset, x.density)
        out.append(x)
    return out


def report(samples: list[Sample], calibrate_bands: bool) -> None:
    """The tables: per package, pooled, by geometry used; the calibration if asked."""
    print("errors: relative Frobenius, tensor about the CoM; prev: the previous choice "
          "(collision first); mj: MuJoCo's inertia from geoms scaled to the CAD mass, "
          "ours50 on the same links")
    print(HEADER)
    by: dict[str, list[Sample]] = defaultdict(list)
    for s in samples:
        by[s.package].append(s)
    for package, group in sorted(by.items()):
        print(line(package, group))
    if samples:
        print(line("pooled", samples))
        kinds: dict[str, list[Sample]] = defaultdict(list)
        for s in samples:
            kinds[f"{s.kind}/{s.role}"].append(s)
        print("\nby geometry used:")
        for k, group in sorted(kinds.items()):
            print(line(k, group))
    if calibrate_bands and samples:
        print_bands(samples, calibrate(samples))


if __name__ == "__main__":
    raise SystemExit(main())
