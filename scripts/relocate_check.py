"""Fix every MJCF model of the installed collections that uses compiler folders or includes,
save it into another folder, and compile the output there with MuJoCo.

Usage: python scripts/relocate_check.py [--limit N]

The collections (dm_control, robosuite, gymnasium_robotics, metaworld) are read as files:
``pip install --no-deps NAME`` is enough. Prints one line per model that fails and the
counts: models that compile where they lie, models ``fix`` writes, and outputs that compile
from the other folder (the same outputs saved without relocation as the baseline).
"""

from __future__ import annotations

import argparse
import sys
import tempfile
import time
from pathlib import Path

import mujoco

from urdfinertia.body.options import FixOptions
from urdfinertia.errors import UrdfInertiaError
from urdfinertia.plan.fix import fix_file

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))
from support.corpus import mjcf_models_with_paths  # noqa: E402


def models() -> list[Path]:
    return [path for _, path in mjcf_models_with_paths()]


def compiles(path: Path) -> str | None:
    try:
        mujoco.MjModel.from_xml_path(str(path))
    except ValueError as exc:
        return str(exc).splitlines()[0]
    return None


def main() -> int:
    ap = argparse.ArgumentParser()
    ap.add_argument("--limit", type=int, default=0)
    args = ap.parse_args()
    paths = models()[: args.limit or None]
    out_root = Path(tempfile.mkdtemp(prefix="relocate_check"))
    counts = {"models": 0, "compile_in_place": 0, "written": 0, "relocated_ok": 0,
              "baseline_ok": 0}
    start = time.perf_counter()
    for i, path in enumerate(paths):
        counts["models"] += 1
        if compiles(path) is not None:
            continue
        counts["compile_in_place"] += 1
        try:
            result = fix_file(path, FixOptions())
        except UrdfInertiaError as exc:
            print(f"not fixed: {path}: {exc.cause}", flush=True)
            continue
        counts["written"] += 1
        out = out_root / f"{i}" / "elsewhere" / path.name
        out.parent.mkdir(parents=True)
        result.save(out)
        error = compiles(out)
        if error is None:
            counts["relocated_ok"] += 1
        base = out.with_name("baseline.xml")
        result.save(base, keep_mesh_paths=True)
        counts["baseline_ok"] += compiles(base) is None
        print(f"{'ok' if error is None else 'FAILS from another folder'}: {path}"
              f"{': ' + error if error else ''}", flush=True)
    print(f"{counts['models']} models with compiler folders or includes; "
          f"{counts['compile_in_place']} compile where they lie; {counts['written']} "
          f"written by fix; {counts['relocated_ok']} of {counts['written']} compile from "
          f"another folder (baseline without relocation: {counts['baseline_ok']}); "
          f"{time.perf_counter() - start:.0f} s")
    return 0 if counts["relocated_ok"] == counts["written"] else 1


if __name__ == "__main__":
    sys.exit(main())
