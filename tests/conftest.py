"""Shared fixtures: paths to shipped robots and to the example-robot-data collection."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from support.corpus import example_robot_data_dir

ROOT = Path(__file__).resolve().parents[1]


@pytest.fixture(scope="session")
def erd_dir() -> Path:
    found = example_robot_data_dir()
    if found is None:
        pytest.fail("example-robot-data is a dev dependency and must be installed")
    return found


@pytest.fixture
def rng() -> np.random.Generator:
    return np.random.default_rng(20061124)  # seeded: failures must reproduce


@pytest.fixture(scope="session")
def robots_dir() -> Path:
    return ROOT / "robots"


@pytest.fixture(autouse=True, scope="session")
def _private_cache_dir(tmp_path_factory):
    """No test touches the user's real mesh cache: it lives in a temporary folder."""
    with pytest.MonkeyPatch.context() as mp:
        mp.setenv("URDFINERTIA_CACHE_DIR", str(tmp_path_factory.mktemp("urdfinertia-cache")))
        yield

