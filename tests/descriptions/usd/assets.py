"""The converted robots kept in tests/data/usd and the sources they were converted from
(by scripts/convert_usd.py)."""

from __future__ import annotations

import shutil
from pathlib import Path

from support.corpus import example_robot_data_robots

DATA = Path(__file__).resolve().parents[2] / "data" / "usd"


def asset(name: str) -> Path:
    """The root layer of a converted robot."""
    return sorted((DATA / name).glob("*.usda"))[0]


def all_assets() -> list[str]:
    """The converted robots (``handmade`` holds assets written by hand, no source)."""
    return sorted(p.name for p in DATA.iterdir() if p.is_dir() and p.name != "handmade")


def source(name: str) -> Path:
    """The URDF or MJCF a kept asset was converted from."""
    import pybullet_data

    erd = example_robot_data_robots()
    pb = Path(pybullet_data.getDataPath())
    return {
        "double_pendulum": erd / "double_pendulum_description/urdf/double_pendulum_simple.urdf",
        "simple_humanoid": erd / "simple_humanoid_description/urdf/"
                                 "simple_humanoid_classical.urdf",
        "cartpole": pb / "cartpole.urdf",
        "spirit40": pb / "quadruped/spirit40.urdf",
        "ant_mjcf": pb / "mjcf/ant.xml",
        "pendulum_mjcf": pb / "mjcf/inverted_double_pendulum.xml",
    }[name]


def copy(name: str, folder: Path) -> Path:
    """A private copy of a converted robot (fix writes beside it); its root layer."""
    shutil.copytree(DATA / name, folder / name)
    return folder / name / asset(name).name
