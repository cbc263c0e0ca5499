"""Run check and fix (and the write-back planning) over real xacro sources; print counts.

Usage::

    PYTHONPATH=src python scripts/bench_xacro.py [LIST_OR_FOLDER ...] [--no-plan]

Inputs: tab-separated lists of xacro files (path in the third column) and/or folders
searched for ``*.xacro``; by default every xacro file of the robot packages found
(``support.corpus.robot_packages``: installed ones and ``scripts/gather_corpus.py``'s);
example-robot-data's xacro files are added when it is installed.
Nothing is written: ``fix`` runs in memory and write-back is planned, not applied.

Printed: files; expanded OK (with and without links: a macro library has none); xacro
errors by cause; check outcomes (exit 0/1, errors); fix outcomes (fixed, error by cause);
write-back plans (links written / reported / unchanged); crashes (must be 0). Time of the
hooked in-process expansion against the ``xacro`` package's own ``xacro.process`` on the
files it can expand without ROS (no ``$(find)``), measured in the same run.
"""

from __future__ import annotations

import argparse
import re
import sys
import time
import traceback
from collections import Counter
from pathlib import Path

_CAUSES = [
    ("package not found", "package not found ($(find) of a package not shipped)"),
    ("No such file", "missing include or file"),
    ("is not defined", "undefined property or argument"),
    ("Undefined substitution argument", "undefined $(arg)"),
    ("not URLs", "URL refused"),
    ("entity", "entity declaration refused"),
    ("root element", "not a <robot> document"),
    ("mesh file not found", "mesh file not found"),
    ("Undefined parameters", "macro called without a parameter"),
]


def cause_of(message: str) -> str:
    for needle, name in _CAUSES:
        if needle in message:
            return name
    return re.sub(r"^.*?: (?:link '[^']*': )?", "", message)[:70]


def inputs(items: list[str]) -> list[Path]:
    files: dict[Path, None] = {}
    for item in items:
        path = Path(item)
        if path.is_dir():
            files.update((p, None) for p in sorted(path.rglob("*.xacro")))
        elif path.is_file() and path.suffix in (".txt", ".tsv"):
            for line in path.read_text().splitlines():
                parts = line.split("\t")
                if len(parts) >= 3 and not line.startswith("#") and Path(parts[2]).is_file():
                    files[Path(parts[2])] = None
        elif path.is_file():
            files[path] = None
    try:
        import example_robot_data

        root = Path(example_robot_data.getModelPath("ur_description/urdf/ur5_robot.urdf"))
        files.update((p, None) for p in sorted(root.rglob("*.xacro")))
    except Exception:  # noqa: BLE001 - optional
        pass
    return list(files)


def expansion_times(path: Path, expand_xacro) -> tuple[float, float]:  # noqa: ANN001
    """Best of 3 of the hooked expansion and of ``xacro.process``, interleaved."""
    import contextlib
    import io

    import xacro

    ours, theirs = [], []
    for _ in range(3):
        t0 = time.perf_counter()
        expand_xacro(path)
        t1 = time.perf_counter()
        with contextlib.redirect_stderr(io.StringIO()):
            xacro.process(str(path), verbosity=0)
        t2 = time.perf_counter()
        ours.append(t1 - t0)
        theirs.append(t2 - t1)
    return min(ours), min(theirs)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("inputs", nargs="*")
    ap.add_argument("--no-plan", action="store_true", help="skip write-back planning")
    args = ap.parse_args(argv)

    from urdfinertia.analysis.check import check_robot
    from urdfinertia.body.options import FixOptions
    from urdfinertia.cache.library import MeshLibrary
    from urdfinertia.descriptions.formats import read_description
    from urdfinertia.descriptions.xacro import expansion
    from urdfinertia.descriptions.xacro.expand import current_settings, expand_xacro
    from urdfinertia.descriptions.xacro.writeback import plan_write_back
    from urdfinertia.errors import UrdfInertiaError
    from urdfinertia.plan.fix import fix_robot

    if args.inputs:
        files = inputs(args.inputs)
    else:
        sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))
        from support.corpus import robot_packages

        files = inputs([str(f) for fs in robot_packages(("xacro",)).values() for f in fs])
    counts: Counter[str] = Counter()
    xacro_errors: Counter[str] = Counter()
    fix_errors: Counter[str] = Counter()
    plans: Counter[str] = Counter()
    crashes: list[str] = []
    ours = theirs = 0.0
    compared = 0
    options = FixOptions()
    for path in files:
        counts["files"] += 1
        try:
            robot, document = read_description(path)
        except UrdfInertiaError as exc:
            xacro_errors[cause_of(str(exc))] += 1
            continue
        except Exception:  # noqa: BLE001 - a crash is what this counts
            crashes.append(f"{path}: read: {traceback.format_exc().splitlines()[-1]}")
            continue
        counts["expanded OK"] += 1
        if not robot.links:
            counts["expanded, no links (macro library)"] += 1
            continue
        counts["expanded with links"] += 1
        counts["links"] += len(robot.links)
        if b"$(find" not in path.read_bytes():
            try:
                a, b = expansion_times(path, expand_xacro)
                ours, theirs, compared = ours + a, theirs + b, compared + 1
            except BaseException:  # noqa: BLE001 - the plain package may fail (sys.exit)
                pass
        meshes = MeshLibrary(options.package_dirs, options.max_faces)
        try:
            findings = check_robot(robot, meshes=meshes, options=options)
            errors = sum(f.severity == "error" for f in findings)
            counts["check exit 1" if errors else "check exit 0"] += 1
        except UrdfInertiaError as exc:
            counts["check error"] += 1
            fix_errors["check: " + cause_of(str(exc))] += 1
        except Exception:  # noqa: BLE001
            crashes.append(f"{path}: check: {traceback.format_exc().splitlines()[-1]}")
        try:
            strict, document = read_description(path)
            result = fix_robot(strict, document, options, meshes)
            counts["fix OK"] += 1
            counts["fix changed" if result.changed else "fix unchanged"] += 1
        except UrdfInertiaError as exc:
            fix_errors[cause_of(str(exc))] += 1
            continue
        except Exception:  # noqa: BLE001
            crashes.append(f"{path}: fix: {traceback.format_exc().splitlines()[-1]}")
            continue
        if args.no_plan:
            continue
        try:
            t0 = time.perf_counter()
            exp = expansion(path.read_bytes(), path)
            plan = plan_write_back(path, exp, result.output, current_settings())
            counts["write-back plans"] += 1
            counts["write-back seconds x1000"] += round(1000 * (time.perf_counter() - t0))
            for outcome in plan.outcomes:
                plans[outcome.status] += 1
                if outcome.status == "reported":
                    why = next((w for w in ("shared", "computed", "structure", "no ")
                                if w in outcome.detail), "other")
                    plans[f"reported because: {why.strip()}"] += 1
        except UrdfInertiaError as exc:
            plans["plan error: " + cause_of(str(exc))] += 1
        except Exception:  # noqa: BLE001
            crashes.append(f"{path}: plan: {traceback.format_exc().splitlines()[-1]}")

    def show(title: str, counter: Counter[str]) -> None:
        print(title)
        for key, n in counter.most_common():
            print(f"  {n:5d}  {key}")

    show("files", counts)
    show("xacro errors by cause", xacro_errors)
    show("fix/check errors by cause", fix_errors)
    show("write-back plans: links", plans)
    if compared:
        print(f"expansion time over {compared} files without $(find) (best of 3 each): "
              f"hooked in-process {ours:.3f} s, xacro.process (baseline, same run) "
              f"{theirs:.3f} s")
    print(f"crashes: {len(crashes)}")
    for line in crashes[:20]:
        print("  " + line)
    return 1 if crashes else 0


if __name__ == "__main__":
    sys.exit(main())
