"""Density and structure priors measured on CAD robots: measure, fit, report, write.

Over every robot package found (``support.corpus.robot_packages``: URDF, SDFormat and
MJCF, installed or gathered by ``scripts/gather_corpus.py``), every CAD-valued link
(``bench_cad.py``'s: plausible per ``check``, with geometry; de-duplicated across robots and
mirrored twins) is measured (``priors_corpus.py``), then, cross-validated by package
(each package predicted by a model fitted on the others):

1. **mass**, every inertial withheld: the effective density (CAD mass over the volume of
   the geometry ``fix`` integrates when there is no inertial) modelled from what is known
   without CAD (``urdfinertia.priors.features``), against a constant 1000 kg/m^3 on the
   same geometry, ``fix`` as it runs today (which leaves massless root and fixed links
   empty) and MuJoCo's inertia from geoms (MJCF): per-link and robot-total errors and the
   bands' coverage;
2. **tensor**, mass and CoM kept: the structure prior (``urdfinertia.priors.structure``)
   against the default ``fix``, the homogeneous body on the same geometry, the best
   homogeneous body among the link's geometries (the per-link oracle, which knows CAD) and
   MuJoCo's inertia from geoms scaled to the CAD mass.

``--write`` regenerates ``src/urdfinertia/data/priors.json`` from the fit on every
package; ``--fixture`` the test sample ``tests/data/priors/sample.json``.

Usage: ``nice python scripts/bench_priors.py --samples FILE [--file-seconds S]
[--packages P ...]`` measures and reports; ``--from-samples FILE`` reports saved samples;
either with ``--write`` and ``--fixture``; ``--check FILE ...`` prints the written
priors for held-out descriptions (no inertials needed).
"""

from __future__ import annotations

import argparse
import json
import sys
from collections import defaultdict
from pathlib import Path

from bench_cad import _file_name, _time_limit, package_dirs, packages
from priors_check import check_files
from priors_corpus import measure_file
from priors_report import report
from priors_write import write_fixture, write_table

from urdfinertia.cache.library import mesh_library
from urdfinertia.errors import UrdfInertiaError

ROOT = Path(__file__).resolve().parents[1]


#: installed distributions whose robot descriptions the corpus reads (their versions are
#: recorded with the samples; the gathered wheels are pinned in ``gather_corpus.py``)
INSTALLED = ("example-robot-data", "pybullet", "drake", "dm_control", "robosuite",
             "gymnasium_robotics", "metaworld", "mujoco")


def corpus_versions() -> dict[str, str]:
    """The versions of every distribution the corpus comes from."""
    import importlib.metadata

    from gather_corpus import WHEELS

    out = dict(WHEELS)
    for name in INSTALLED:
        try:
            out[name] = importlib.metadata.version(name)
        except importlib.metadata.PackageNotFoundError:
            continue
    return dict(sorted(out.items()))


def measure(out: Path, only: list[str] | None, max_files: int, file_seconds: int,
            command: str) -> None:
    """Write one JSON line per description file with CAD links to ``out``, after a header
    line recording the command, the date and the corpus's versions."""
    import datetime

    found = packages()
    seen: set = set()
    skipped: dict[str, int] = defaultdict(int)
    with open(out, "w") as f:
        f.write(json.dumps({"measured": {"command": command,
                                         "date": datetime.date.today().isoformat(),
                                         "versions": corpus_versions()}}) + "\n")
        for package, files in sorted(found.items(), key=lambda kv: (len(kv[1]), kv[0])):
            if only is not None and package not in only:
                continue
            files = files[:max_files or None]
            print(f"{package}: {len(files)} file(s)", file=sys.stderr, flush=True)
            n = 0
            for path in files:
                meshes = mesh_library(package_dirs(package, path))
                try:
                    with _time_limit(file_seconds):
                        record = measure_file(package, path, seen, meshes)
                except (UrdfInertiaError, ValueError, RecursionError, OSError,
                        TimeoutError) as exc:
                    if not skipped[package] or isinstance(exc, TimeoutError):
                        print(f"  skipped {_file_name(path)}: {exc}", file=sys.stderr)
                    skipped[package] += 1
                    continue
                if record is not None:
                    f.write(json.dumps(record) + "\n")
                    f.flush()
                    n += sum(s["unique"] for s in record["samples"])
            print(f"  {n} unique CAD links", file=sys.stderr, flush=True)
    print(f"files skipped (unreadable, not robots, over --file-seconds): {dict(skipped)}")


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--samples", type=Path, help="measure into this JSON lines file")
    ap.add_argument("--from-samples", type=Path, help="report these samples, measure nothing")
    ap.add_argument("--packages", nargs="*", default=None, help="only these packages")
    ap.add_argument("--max-files", type=int, default=0, help="per package (0: all)")
    ap.add_argument("--file-seconds", type=int, default=0,
                    help="skip a file that takes longer than this (0: no limit)")
    ap.add_argument("--write", action="store_true",
                    help="write src/urdfinertia/data/priors.json from the fit")
    ap.add_argument("--fixture", action="store_true",
                    help="write the test sample tests/data/priors/sample.json")
    ap.add_argument("--check", type=Path, nargs="*", default=None,
                    help="print the packaged priors for these descriptions")
    ap.add_argument("--package-dir", action="append", default=[], metavar="NAME=PATH",
                    help="where package:// URIs of --check files resolve")
    args = ap.parse_args(argv)
    if args.check is not None:
        dirs = dict(x.split("=", 1) for x in args.package_dir)
        return check_files(args.check, {k: Path(v) for k, v in dirs.items()})
    command = "python scripts/bench_priors.py " + " ".join(
        Path(a).name if a.startswith("/") else a for a in (argv or sys.argv[1:]))
    if args.from_samples is not None:
        source = args.from_samples
    elif args.samples is not None:
        measure(args.samples, args.packages, args.max_files, args.file_seconds, command)
        source = args.samples
    else:
        ap.error("--samples, --from-samples or --check is needed")
    lines = [json.loads(x) for x in source.read_text().splitlines() if x.strip()]
    header = next((x["measured"] for x in lines if "measured" in x), {})
    records = [x for x in lines if "samples" in x]
    if not records:
        print("no CAD links measured: nothing to report")
        return 0
    result = report(records)
    if args.write:
        path = ROOT / "src" / "urdfinertia" / "data" / "priors.json"
        write_table(result, path, command, header)
        print(f"\nwrote {path.relative_to(ROOT)}")
    if args.fixture:
        path = ROOT / "tests" / "data" / "priors" / "sample.json"
        write_fixture(result, path)
        print(f"wrote {path.relative_to(ROOT)}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
