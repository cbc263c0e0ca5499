"""Cross-check the repaired volume of open meshes against their winding numbers.

    python scripts/winding_check.py NAME_OR_PATH... [--grid 20]

For each mesh (a path, or a file name looked up in example-robot-data's ``robots``
folder) prints the volume of the repaired solid, the convex hull's volume (no solid can
exceed it) and an independent estimate that needs no closed surface: the volume of the
grid cells, over the bounding box, where the generalized winding number of the file's
welded triangles (Jacobson et al. 2013) exceeds 1/2. The grid estimate's resolution is
the box over ``--grid`` per axis, so it tells large disagreements (a cap folded out to
the hull), not small ones.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "src"))
sys.path.insert(0, str(ROOT / "tests"))

from support.corpus import example_robot_data_robots  # noqa: E402

from urdfinertia.mesh.read.load import load_mesh  # noqa: E402
from urdfinertia.mesh.repair.graph import weld_vertices  # noqa: E402
from urdfinertia.mesh.repair.pipeline import repair_mesh  # noqa: E402
from urdfinertia.mesh.repair.winding import winding_numbers  # noqa: E402
from urdfinertia.mesh.solids import integrate_repaired  # noqa: E402


def find(name: str) -> Path:
    if Path(name).is_file():
        return Path(name)
    return next(example_robot_data_robots().rglob(name))


def grid_volume(vertices: np.ndarray, faces: np.ndarray, n: int) -> float:
    """Volume of the cells whose centre has winding number above 1/2 (sign by majority)."""
    lo, hi = vertices.min(axis=0), vertices.max(axis=0)
    axes = [lo[k] + (hi[k] - lo[k]) * (np.arange(n) + 0.5) / n for k in range(3)]
    points = np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1).reshape(-1, 3)
    welded_v, welded_f = weld_vertices(vertices, faces, 1e-9 * np.linalg.norm(hi - lo))
    w = winding_numbers(points, welded_v, welded_f)
    if np.median(w[np.abs(w) > 0.5]) < 0:  # the file's faces point inward
        w = -w
    return float(np.count_nonzero(w > 0.5) * np.prod((hi - lo) / n))


def main(argv: list[str] | None = None) -> int:
    from scipy.spatial import ConvexHull

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("meshes", nargs="+")
    parser.add_argument("--grid", type=int, default=20)
    args = parser.parse_args(argv)
    print(f"{'mesh':45s} {'faces':>7s} {'repaired':>10s} {'hull':>10s} "
          f"{'winding':>10s}  (m^3)")
    for name in args.meshes:
        mesh = load_mesh(find(name))
        v, f = np.asarray(mesh.vertices), np.asarray(mesh.faces)
        repaired = sum(s.volume for s in integrate_repaired(repair_mesh(mesh)).solids)
        hull = ConvexHull(v[np.unique(f)]).volume
        print(f"{name[-45:]:45s} {len(f):7d} {repaired:10.4g} {hull:10.4g} "
              f"{grid_volume(v, f, args.grid):10.4g}", flush=True)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
