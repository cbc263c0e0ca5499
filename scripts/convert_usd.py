"""Convert real robots to OpenUSD with the converters users run, and check them.

URDFs go through ``urdf_usd_converter`` (PyPI ``urdf-usd-converter``), MJCF through
``mujoco_usd_converter`` (PyPI ``mujoco-usd-converter``, which pins its own MuJoCo: install
it in a separate environment and name its executable with ``--mujoco-converter``).
Each converted asset is then read by ``urdf-inertia check``; the script prints one line
per robot (links read, bodies with a complete MassAPI, findings) and the totals.

  python scripts/convert_usd.py --all OUT             every example-robot-data URDF
  python scripts/convert_usd.py --tests               the small assets in tests/data/usd

The small test assets: robots whose geometry is primitives only (a few kB each),
converted with their physics in the converter's payload layer ``Payload/Physics.usda``.
"""

from __future__ import annotations

import argparse
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent / "tests"))

from support.corpus import example_robot_data_robots  # noqa: E402

TESTS_OUT = HERE.parent / "tests" / "data" / "usd"


def pybullet_data() -> Path:
    import pybullet_data as pd

    return Path(pd.getDataPath())


def test_sources() -> list[tuple[str, Path, str]]:
    """(name, source, kind) of the small assets kept in the tests' data."""
    erd = example_robot_data_robots()
    pb = pybullet_data()
    return [
        ("double_pendulum", erd / "double_pendulum_description/urdf/double_pendulum_simple.urdf",
         "urdf"),
        ("simple_humanoid", erd / "simple_humanoid_description/urdf/"
         "simple_humanoid_classical.urdf", "urdf"),
        ("cartpole", pb / "cartpole.urdf", "urdf"),
        ("spirit40", pb / "quadruped/spirit40.urdf", "urdf"),
        ("ant_mjcf", pb / "mjcf/ant.xml", "mjcf"),
        ("pendulum_mjcf", pb / "mjcf/inverted_double_pendulum.xml", "mjcf"),
    ]


def convert(source: Path, out: Path, kind: str, mujoco_converter: str | None) -> Path:
    """The converted asset's root layer (``out/<robot>.usda``)."""
    if out.exists():
        shutil.rmtree(out)
    if kind == "urdf":
        exe = shutil.which("urdf_usd_converter") or str(Path(sys.executable).parent /
                                                        "urdf_usd_converter")
        cmd = [exe, str(source), str(out)]
        robots = example_robot_data_robots()
        if robots in source.parents:  # package://example-robot-data/robots/...
            cmd += ["--package", f"example-robot-data={robots.parent}"]
    else:
        exe = mujoco_converter or shutil.which("mujoco_usd_converter")
        if exe is None:
            raise RuntimeError("mujoco_usd_converter not found (--mujoco-converter PATH)")
        cmd = [exe, str(source), str(out)]
    done = subprocess.run(cmd, capture_output=True, text=True, timeout=600)
    roots = sorted(out.glob("*.usd*")) if out.is_dir() else []
    if done.returncode != 0 or not roots:
        tail = (done.stderr or done.stdout).strip().splitlines()[-1:] or ["no output"]
        raise RuntimeError(f"converter failed: {tail[0]}")
    return roots[0]


def check(asset: Path, geometry: bool = True) -> str:
    from urdfinertia.analysis.check import check_robot
    from urdfinertia.cache.library import MeshLibrary
    from urdfinertia.descriptions.formats import read_description

    robot, _ = read_description(asset)
    findings = check_robot(robot, meshes=MeshLibrary() if geometry else None)
    complete = sum(1 for link in robot.links if link.inertial is not None)
    return (f"{len(robot.links)} bodies, {complete} with a complete MassAPI, "
            f"{len(findings)} findings")


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--all", type=Path, metavar="OUT",
                   help="convert every example-robot-data URDF into OUT and check each")
    p.add_argument("--tests", action="store_true", help="rebuild tests/data/usd")
    p.add_argument("--mujoco-converter", help="mujoco_usd_converter executable")
    p.add_argument("--no-geometry", action="store_true",
                   help="check the values only (no mesh integration): reading is what is "
                        "tested, fast on large meshes")
    args = p.parse_args(argv)
    jobs: list[tuple[str, Path, str, Path]] = []
    if args.tests:
        jobs += [(n, s, k, TESTS_OUT / n) for n, s, k in test_sources()]
    if args.all is not None:
        for urdf in sorted(example_robot_data_robots().rglob("*.urdf")):
            name = f"{urdf.parent.parent.name}-{urdf.stem}"
            jobs.append((name, urdf, "urdf", args.all / name))
    if not jobs:
        p.error("give --all OUT and/or --tests")
    converted = read = failed = 0
    for name, source, kind, out in jobs:
        try:
            asset = convert(source, out, kind, args.mujoco_converter)
        except (RuntimeError, subprocess.TimeoutExpired) as exc:
            print(f"{name}: not converted: {exc}", flush=True)
            failed += 1
            continue
        converted += 1
        try:
            print(f"{name}: {check(asset, not args.no_geometry)}", flush=True)
            read += 1
        except Exception as exc:  # noqa: BLE001 - the figure is how many read
            print(f"{name}: converted, NOT READ: {exc}")
    print(f"converted {converted} of {len(jobs)} ({failed} refused by the converter); "
          f"read {read} of {converted}")
    return 0 if read == converted else 1


if __name__ == "__main__":
    tempfile.tempdir = None
    sys.exit(main())
