"""Where the real robot collections the tests and scripts read are installed: example-robot-data
(a dev dependency) and the MJCF collections read as files."""

from __future__ import annotations

import importlib.util
import re
import sys
from pathlib import Path


def example_robot_data_dir() -> Path | None:
    """The ``share/example-robot-data`` folder of the installed PyPI package, if any."""
    for base in map(Path, sys.path):
        cand = base / "cmeel.prefix" / "share" / "example-robot-data"
        if cand.is_dir():
            return cand
    return None


def example_robot_data_robots() -> Path:
    """The collection's ``robots`` folder; exits with how to install it when missing."""
    found = example_robot_data_dir()
    if found is None:
        raise SystemExit("example-robot-data is not installed (pip install example-robot-data)")
    return found / "robots"


#: Packages that ship MJCF models inside them; they are read as files, never imported, so
#: ``pip install --no-deps NAME`` is enough (the test command installs them so).
MJCF_COLLECTIONS = ("dm_control", "robosuite", "gymnasium_robotics", "metaworld")
_USES_PATHS = re.compile(rb"meshdir|texturedir|assetdir|<include")


def mjcf_models_with_paths() -> list[tuple[str, Path]]:
    """Every installed collection's MJCF model that uses ``<compiler meshdir/texturedir/
    assetdir>`` or ``<include>``, as (``collection/relative/path.xml``, path)."""
    found = []
    for name in MJCF_COLLECTIONS:
        spec = importlib.util.find_spec(name)  # finds the folder, runs nothing
        if spec is None or not spec.submodule_search_locations:
            continue
        root = Path(next(iter(spec.submodule_search_locations)))
        for path in sorted(root.rglob("*.xml")):
            head = path.read_bytes()
            if b"<mujoco" in head and _USES_PATHS.search(head):
                found.append((f"{name}/{path.relative_to(root).as_posix()}", path))
    return found
