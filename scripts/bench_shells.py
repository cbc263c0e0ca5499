"""3-D printed robots: what a PLA shell with infill weighs against the written link masses.

    nice .venv/bin/python scripts/bench_shells.py [--wall 0.002] [--infill 0.2] [--closed-forms]

``--closed-forms`` first prints the wall volumes of test bodies against their exact
references (the figures of docs/shells.md; tests/inertia/test_shell.py and
tests/link/test_shell_*.py assert them).
``--grids`` first prints the voxel estimate of two SO-100 parts at several voxel sizes.

For every link of the printed arms and legs in the gathered corpus (mani-skill's SO-100
and Koch arms, upkie's legs), each visual drawn in the printed parts' colour is taken as
a PLA part (1240 kg/m^3) and computed three ways: solid, and as a shell of ``--wall`` m
with ``--infill`` (the spec's ``shell``/``infill``, :func:`urdfinertia.body.parts.shell_solids`).
The other visuals of the link (servos, bearings) are listed by volume only. The table
also gives the density the written mass implies if the whole link (all its visuals) were
one material: a CAD export with one material everywhere shows the same figure on every
link.
"""

from __future__ import annotations

import argparse
import sys
import time
import xml.etree.ElementTree as ET
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tests"))

from support.corpus import robot_packages  # noqa: E402

from urdfinertia.body.materials import material_density  # noqa: E402
from urdfinertia.body.parts import Walls, shape_solids, shell_solids  # noqa: E402
from urdfinertia.cache.library import mesh_library  # noqa: E402
from urdfinertia.descriptions.formats import read_description  # noqa: E402

PLA = material_density("PLA", {})
#: (corpus package, description file name, package:// name and its folder relative to
#: the file, colour of the printed parts in the file)
ROBOTS = (
    ("mani-skill", "so100.urdf", None, "white"),
    ("mani-skill", "follower_arm_v1.1.urdf", ("koch", "."), "white"),
    ("upkie-description", "upkie.urdf", ("upkie_description", ".."), "terracotta_light"),
)


def _colours(path: Path) -> dict[tuple[str, int], str]:
    """The material name of each (link, visual index) as written."""
    out = {}
    for link in ET.parse(path).getroot().iter("link"):
        for i, visual in enumerate(link.findall("visual")):
            material = visual.find("material")
            out[(link.get("name", ""), i)] = "" if material is None else material.get("name", "")
    return out


def closed_forms(t: float) -> None:
    """Each method's wall volume against an exact reference, with its stated error."""
    import numpy as np
    import trimesh

    from urdfinertia.body.shell_voxels import voxel_shell
    from urdfinertia.inertia import shell

    def sphere(r: float) -> float:
        return 4 / 3 * np.pi * (r**3 - (r - t) ** 3)

    box = trimesh.creation.box(extents=[0.1, 0.06, 0.04])
    ico = trimesh.creation.icosphere(subdivisions=4, radius=0.05)
    cyl = trimesh.creation.cylinder(radius=0.03, height=0.1, sections=64)
    rows = [
        ("sphere r 50 mm, closed form", shell.sphere_shell(0.05, t), sphere(0.05)),
        ("box 100x60x40 mm, closed form", shell.box_shell([0.1, 0.06, 0.04], t),
         0.1 * 0.06 * 0.04 - (0.1 - 2 * t) * (0.06 - 2 * t) * (0.04 - 2 * t)),
        ("ellipsoid 50 mm (sphere), tube integral",
         shell.ellipsoid_shell([0.05, 0.05, 0.05], t), sphere(0.05)),
        ("box mesh (12 faces), vertex offset", shell.mesh_shell(box.vertices, box.faces, t),
         shell.box_shell([0.1, 0.06, 0.04], t).wall[0]),
        ("cylinder mesh (64 sides), vertex offset",
         shell.mesh_shell(cyl.vertices, cyl.faces, t),
         # the 64-gon prism's inner body: apothem r cos(pi/n) - t, height L - 2t
         cyl.volume - 64 * (0.03 * np.cos(np.pi / 64) - t) ** 2 * np.tan(np.pi / 64)
         * (0.1 - 2 * t)),
        ("icosphere mesh (5120 faces) vs sphere", shell.mesh_shell(ico.vertices, ico.faces, t),
         sphere(0.05)),
        ("box mesh, voxel estimate", voxel_shell(box.vertices, box.faces, t),
         shell.box_shell([0.1, 0.06, 0.04], t).wall[0]),
        ("icosphere mesh, voxel estimate", voxel_shell(ico.vertices, ico.faces, t),
         shell.mesh_shell(ico.vertices, ico.faces, t).wall[0]),
    ]
    print(f"{'wall of':<42} {'cm3':>9} {'reference':>9} {'deviation':>10} {'stated':>8}")
    for label, found, reference in rows:
        print(f"{label:<42} {found.wall[0] * 1e6:9.4f} {reference * 1e6:9.4f} "
              f"{found.wall[0] / reference - 1:+10.2e} {found.error:8.1e}")
    print()


def grids(t: float) -> None:
    """The voxel estimate of real parts (whose exact offset is refused) on finer grids."""
    from urdfinertia.body import shell_voxels
    from urdfinertia.mesh.read.load import load_mesh
    from urdfinertia.mesh.repair.pipeline import repair_mesh

    so100 = next((p for p in robot_packages(("urdf",)).get("mani-skill", [])
                  if p.name == "so100.urdf"), None)
    if so100 is None:
        print("mani-skill's so100.urdf is not in the corpus")
        return
    print(f"{'part':<16} {'voxel mm':>8} {'wall cm3':>9} {'stated':>7} {'s':>5}")
    for name in ("Moving_Jaw.stl", "Upper_Arm.stl"):
        repaired = repair_mesh(load_mesh(so100.parent / "meshes" / name))
        body = max(repaired.bodies, key=lambda b: len(b.faces))
        for per_wall, voxels in ((6, 1_000_000), (6, 6_000_000), (16, 6_000_000),
                                 (16, 20_000_000)):
            shell_voxels.VOXELS_PER_WALL = per_wall
            t0 = time.perf_counter()
            found = shell_voxels.voxel_shell(body.vertices, body.faces, t, voxels)
            size = found.method.split(", ")[1].split(" mm")[0]
            print(f"{name:<16} {size:>8} {found.wall[0] * 1e6:9.3f} {found.error:7.3f} "
                  f"{time.perf_counter() - t0:5.1f}")
    shell_voxels.VOXELS_PER_WALL = 6
    print()


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--wall", type=float, default=0.002, help="wall thickness, m")
    ap.add_argument("--infill", type=float, default=0.2, help="infill fraction 0..1")
    ap.add_argument("--closed-forms", action="store_true",
                    help="first the test bodies against exact references")
    ap.add_argument("--grids", action="store_true",
                    help="first two SO-100 parts' voxel estimates at several voxel sizes")
    args = ap.parse_args(argv)
    if args.closed_forms:
        closed_forms(args.wall)
    if args.grids:
        grids(args.wall)
    packages = robot_packages(("urdf",))
    walls = Walls(args.wall, args.infill)
    print(f"PLA {PLA:g} kg/m^3, {walls.label()}")
    print(f"{'robot/link':<34} {'written g':>9} {'printed cm3':>11} {'solid g':>8} "
          f"{'shell g':>8} {'+-%':>5} {'other cm3':>9} {'rho kg/m3':>9}  method")
    totals = [0.0, 0.0, 0.0]
    for package, name, pkg, colour in ROBOTS:
        path = next((p for p in packages.get(package, []) if p.name == name), None)
        if path is None:
            print(f"{package}/{name}: not in the corpus (scripts/gather_corpus.py)")
            continue
        robot, _ = read_description(path)
        meshes = mesh_library({pkg[0]: (path.parent / pkg[1]).resolve()} if pkg else {})
        colours = _colours(path)
        for link in robot.links:
            if link.inertial is None or not link.visuals:
                continue
            printed = [r for r in link.visuals if colours.get((link.name, r.index)) == colour]
            if not printed:
                continue
            others = [r for r in link.visuals if r not in printed]
            t0 = time.perf_counter()
            volume = solid_volume = other = 0.0
            shell_volume, error, methods = 0.0, 0.0, set()
            for ref in printed:
                solids = shape_solids(ref.shape, meshes, path.parent)
                volume += sum(b.unit.mass for b in solids)
                for b in shell_solids(ref.shape, walls, meshes, path.parent):
                    shell_volume += b.unit.mass
                    error += (b.uncertainty or 0.0) * b.unit.mass
                    methods.add(b.method if "solid" not in b.provenance else "kept solid")
            solid_volume = volume
            for ref in others:
                other += sum(b.unit.mass for b in shape_solids(ref.shape, meshes, path.parent))
            written = link.inertial.mass
            rho = written / (solid_volume + other) if solid_volume + other > 0 else 0.0
            label = f"{robot.name[:12]}/{link.name}"
            print(f"{label:<34} {written * 1e3:9.1f} {volume * 1e6:11.1f} "
                  f"{PLA * volume * 1e3:8.1f} {PLA * shell_volume * 1e3:8.1f} "
                  f"{100 * error / max(shell_volume, 1e-30):5.1f} {other * 1e6:9.1f} "
                  f"{rho:9.0f}  {'; '.join(sorted(methods))} "
                  f"({time.perf_counter() - t0:.1f} s)")
            totals[0] += written
            totals[1] += PLA * volume
            totals[2] += PLA * shell_volume
    print(f"{'all printed links':<34} {totals[0] * 1e3:9.1f} {'':>11} {totals[1] * 1e3:8.1f} "
          f"{totals[2] * 1e3:8.1f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
