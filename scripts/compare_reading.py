#!/usr/bin/env python
"""Mesh reading of this checkout against the reference COLLADA reader, side by side.

Every mesh is read twice in this one process with ``load_mesh``: as shipped, and with the
registry's COLLADA reader switched to trimesh's loader (``read_dae_trimesh``, the reader
before the direct one). The two must give the same vertex and face bytes, or the same
error message; the script prints the times of both and their ratio, measured in the same
run (the order of the two reads alternates from mesh to mesh), and exits 1 on any
difference.

Meshes: every mesh example-robot-data's descriptions reference (collision and visual, as
``fix --all`` and the checks read them), plus every ``.dae`` file of example-robot-data
and of the gathered corpus (``tests/support/corpus.corpus_root()``).

Usage: python scripts/compare_reading.py [--only-dae] [--limit N]
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))
from support.corpus import corpus_root, example_robot_data_dir  # noqa: E402

from urdfinertia.mesh.read import load as mesh_io  # noqa: E402
from urdfinertia.mesh.read.dae import read_dae, read_dae_trimesh  # noqa: E402


def referenced_meshes(robots: Path) -> list[Path]:
    """Every mesh ``fix --all`` and the geometry checks read from ``robots``."""
    from urdfinertia.batch.inputs import collect_jobs
    from urdfinertia.batch.tasks import mesh_needs
    from urdfinertia.body.options import FixOptions

    options = FixOptions(recompute="all")
    found: dict[Path, None] = {}
    for job in collect_jobs([robots], None):
        solids, points = mesh_needs(job.source, options)
        found.update(dict.fromkeys(solids))
        found.update(dict.fromkeys(points))
    return list(found)


def outcome(path: Path, reference: bool) -> tuple[float, tuple]:
    """(seconds, ("ok", vertex bytes, face bytes) or ("error", message)) of one read."""
    mesh_io._NATIVE[".dae"] = read_dae_trimesh if reference else read_dae
    start = time.perf_counter()
    try:
        mesh = mesh_io.load_mesh(path)
        result: tuple = ("ok", mesh.vertices.shape, mesh.vertices.tobytes(),
                         mesh.faces.dtype, mesh.faces.tobytes())
    except Exception as exc:  # noqa: BLE001 - errors are compared too
        result = ("error", str(exc))
    finally:
        mesh_io._NATIVE[".dae"] = read_dae
    return time.perf_counter() - start, result


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--only-dae", action="store_true", help="COLLADA files only")
    p.add_argument("--limit", type=int, help="at most N meshes (a quick look)")
    args = p.parse_args(argv)
    erd = example_robot_data_dir()
    paths: dict[Path, None] = {}
    if erd is not None:
        paths.update(dict.fromkeys(referenced_meshes(erd / "robots")))
        paths.update(dict.fromkeys(sorted(q for q in erd.rglob("*") if q.suffix.lower() == ".dae")))
    root = corpus_root()
    if root.is_dir():
        paths.update(dict.fromkeys(sorted(q for q in root.rglob("*")
                                          if q.suffix.lower() == ".dae" and q.is_file())))
    chosen = [q for q in paths if not args.only_dae or q.suffix.lower() == ".dae"]
    chosen = chosen[:args.limit] if args.limit else chosen
    times: dict[str, list[float]] = {}
    differ = errors = 0
    for reference in (False, True):  # imports (trimesh, pycollada, scipy) outside the times
        for warm in [q for q in chosen if q.suffix.lower() == ".dae"][:1]:
            outcome(warm, reference)
    for i, path in enumerate(chosen):
        order = (False, True) if i % 2 == 0 else (True, False)
        results = {}
        for reference in order:
            seconds, results[reference] = outcome(path, reference)
            row = times.setdefault(path.suffix.lower(), [0.0, 0.0, 0])
            row[1 if reference else 0] += seconds
        times[path.suffix.lower()][2] += 1
        if results[False] != results[True]:
            differ += 1
            print(f"DIFFERENT: {path}")
        elif results[False][0] == "error":
            errors += 1
    print(f"{len(chosen)} meshes ({errors} refused by both readers alike), "
          f"{differ} different")
    print(f"{'suffix':8} {'meshes':>6} {'this (s)':>9} {'reference (s)':>14} {'ratio':>6}")
    total = [0.0, 0.0]
    for suffix, (new, old, count) in sorted(times.items()):
        total[0] += new
        total[1] += old
        print(f"{suffix:8} {count:6d} {new:9.2f} {old:14.2f} {new / old:6.2f}")
    print(f"{'all':8} {len(chosen):6d} {total[0]:9.2f} {total[1]:14.2f} "
          f"{total[0] / max(total[1], 1e-9):6.2f}")
    return 1 if differ else 0


if __name__ == "__main__":
    sys.exit(main())
