"""Where the example-robot-data collection (a dev dependency) is installed."""

from __future__ import annotations

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
