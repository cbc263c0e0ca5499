"""Seeded mutation fuzzing of ``urdf-inertia check``, ``fix`` and ``fix --all``.

Mutates real descriptions (URDF, xacro, SDFormat, MJCF, USD) and meshes (STL, OBJ,
COLLADA, PLY, GLB) of the installed collections and prints, per command, how many runs
fell in each class (ok, clean error, crash, hang, input modified, half-written output,
invalid output, message without file:line, library noise) per format, then one line per
defective run. The same seed gives the same cases::

    python scripts/fuzz.py --seed 1 --cases 400 --timeout 60
    python scripts/fuzz.py --seed 1 --case 137 --keep    # one case again, files kept

Exit 1 when any run is a defect. Needs the dev extra (example-robot-data and the MJCF
collections: ``bash scripts/setup_venv.sh``); no network.
"""

from __future__ import annotations

import argparse
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "src"))
sys.path.insert(0, str(ROOT / "tests"))

from support.fuzz.cases import make_case  # noqa: E402
from support.fuzz.drive import run_case  # noqa: E402
from support.fuzz.runner import Runner  # noqa: E402
from support.fuzz.table import defect_lines, format_table  # noqa: E402


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--seed", type=int, default=1, help="generator seed (default 1)")
    p.add_argument("--cases", type=int, default=200, help="number of cases (default 200)")
    p.add_argument("--start", type=int, default=0, help="first case index (default 0)")
    p.add_argument("--case", type=int, action="append", default=[], metavar="I",
                   help="run only case I (repeatable)")
    p.add_argument("--timeout", type=float, default=60.0, metavar="T",
                   help="wall-clock seconds per command before it counts as a hang "
                        "(default 60)")
    p.add_argument("--memory-mb", type=int, default=4096,
                   help="address-space limit per command, MB (default 4096)")
    p.add_argument("--mesh-seconds", type=float, default=None,
                   help="the commands' --mesh-seconds (default: theirs, 10)")
    p.add_argument("--formats", nargs="+", default=None,
                   help="only these formats (urdf xacro sdf mjcf usd stl stl-ascii obj dae "
                        "ply glb)")
    p.add_argument("--work", type=Path, default=None,
                   help="folder for the cases (default: a temporary one)")
    p.add_argument("--keep", action="store_true", help="keep each case's files")
    p.add_argument("--src", type=Path, default=None,
                   help="import urdfinertia from this folder instead of this checkout's src "
                        "(an older revision's, unpacked with git archive REV src | tar -x): "
                        "the same cases measured on that code")
    p.add_argument("-v", "--verbose", action="store_true", help="a line per case")
    args = p.parse_args(argv)
    indices = args.case or list(range(args.start, args.start + args.cases))
    formats = tuple(args.formats) if args.formats else None
    with tempfile.TemporaryDirectory(prefix="urdfinertia-fuzz-") as tmp:
        work = args.work or Path(tmp)
        work.mkdir(parents=True, exist_ok=True)
        env = {"URDFINERTIA_CACHE_DIR": str(work / "cache")}
        if args.mesh_seconds is not None:
            env["URDFINERTIA_MESH_SECONDS"] = repr(args.mesh_seconds)
        results = []
        start = time.monotonic()
        with Runner(timeout=args.timeout, memory_mb=args.memory_mb, env=env,
                    src=args.src) as runner:
            package = runner.package
            for i in indices:
                case = make_case(args.seed, i, formats)
                result = run_case(runner, case, work, keep=args.keep)
                results.append(result)
                if args.verbose or result.defects:
                    classes = " ".join(f"{o.command}={o.cls}" for o in result.outcomes)
                    print(f"{case.label}: {classes}", file=sys.stderr, flush=True)
        elapsed = time.monotonic() - start
    print(f"seed {args.seed}, {len(results)} cases, timeout {args.timeout:g} s, "
          f"{elapsed:.0f} s in all; package {package}")
    print(format_table(results))
    defects = defect_lines(results)
    if defects:
        print(f"\n{len(defects)} defective run(s):")
        for line in defects:
            print(f"  {line}")
    return 1 if defects else 0


if __name__ == "__main__":
    sys.exit(main())
