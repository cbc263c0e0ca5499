#!/usr/bin/env python
"""Peak memory of `urdf-inertia fix` on one mesh at the default face limit, per format.

Writes a closed UV sphere of just under ``--faces`` triangles (default: the default
``--max-faces``, 1,000,000) as binary STL, ASCII STL, OBJ, GLB and COLLADA, a one-link URDF
for each, and runs ``urdf-inertia fix -q --no-cache`` on it in a fresh child process. Peak
memory is the child's ``getrusage(RUSAGE_CHILDREN).ru_maxrss`` (Linux: KiB), read after it
exits; wall time is printed too. Also checks that every format gives the same mass.

Usage: python scripts/bench_memory.py [--faces N] [--formats stl,obj,...]
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
import tempfile
import time
from pathlib import Path

FORMATS = ("stl", "stl-ascii", "obj", "glb", "dae")

URDF = """<?xml version="1.0"?>
<robot name="sphere">
  <link name="ball">
    <collision><geometry><mesh filename="{mesh}"/></geometry></collision>
  </link>
</robot>
"""


def sphere(faces: int):
    """A UV sphere (radius 0.1 m) with at most ``faces`` triangles (closed once welded)."""
    import trimesh

    # trimesh's UV sphere with count (rows, cols) has 4 cols (rows - 2) triangles
    rows = int((faces / 4) ** 0.5) + 2
    cols = faces // (4 * (rows - 2))
    mesh = trimesh.creation.uv_sphere(radius=0.1, count=[rows, cols])
    while len(mesh.faces) > faces:  # trimesh may round the counts up
        cols -= 1
        mesh = trimesh.creation.uv_sphere(radius=0.1, count=[rows, cols])
    return mesh


def write(mesh, fmt: str, folder: Path) -> Path:
    import trimesh

    if fmt == "stl-ascii":
        path = folder / "ball_ascii.stl"
        path.write_text(trimesh.exchange.stl.export_stl_ascii(mesh))
    else:
        path = folder / f"ball.{fmt}"
        mesh.export(path)
    return path


def run_fix(urdf: Path, out: Path) -> tuple[float, float, str]:
    """Fix ``urdf`` in a fresh child process: (wall s, the child's peak RSS MB, output)."""
    start = time.perf_counter()
    proc = subprocess.run([sys.executable, __file__, "--child", str(urdf), str(out)],
                          capture_output=True, text=True)
    wall = time.perf_counter() - start
    if proc.returncode != 0:
        sys.exit(f"fix failed on {urdf}:\n{proc.stderr}")
    return wall, json.loads(proc.stdout.strip().splitlines()[-1])["peak_mb"], out.read_text()


def child(urdf: str, out: str) -> int:
    from bench import own_peak_mb  # scripts/bench.py, next to this script

    from urdfinertia.cli import main as cli_main

    code = cli_main(["fix", "--all", urdf, "-o", out, "-q", "--no-cache"])
    print(json.dumps({"peak_mb": own_peak_mb()}))
    return code



def main() -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--faces", type=int, default=1_000_000)
    p.add_argument("--formats", default=",".join(FORMATS))
    p.add_argument("--child", nargs=2, help=argparse.SUPPRESS)
    args = p.parse_args()
    if args.child:
        return child(*args.child)
    mesh = sphere(args.faces)
    print(f"closed UV sphere: {len(mesh.faces):,} faces, {len(mesh.vertices):,} vertices")
    print("| format | file MB | wall s | peak RSS MB | mass kg |")
    print("|---|---:|---:|---:|---:|")
    masses = []
    with tempfile.TemporaryDirectory(prefix="urdfinertia-mem-") as tmp:
        folder = Path(tmp)
        for fmt in args.formats.split(","):
            path = write(mesh, fmt, folder)
            urdf = folder / f"{path.stem}_{fmt}.urdf"
            urdf.write_text(URDF.format(mesh=path.name))
            wall, peak, text = run_fix(urdf, folder / f"out_{fmt}.urdf")
            mass = float(text.split('<mass value="')[1].split('"')[0])
            masses.append(mass)
            print(f"| {fmt} | {path.stat().st_size / 1e6:.0f} | {wall:.1f} | {peak:.0f} | "
                  f"{mass:.6g} |")
    spread = (max(masses) - min(masses)) / max(masses)
    print(json.dumps({"same_mass_across_formats": spread < 1e-6, "spread": spread}))
    return 0 if spread < 1e-6 else 1


if __name__ == "__main__":
    sys.exit(main())
