"""No false errors on MJCF models MuJoCo loads: a seeded slice of the installed
collections (``scripts/mjcf_errors.py`` runs all of them), every error ``check`` reports
set against MuJoCo's compiled model of the same file."""

from __future__ import annotations

import importlib.util
import subprocess
import sys
from pathlib import Path

import pytest

SCRIPT = Path(__file__).resolve().parents[3] / "scripts" / "mjcf_errors.py"

pytestmark = pytest.mark.corpus


@pytest.mark.skipif(importlib.util.find_spec("mujoco") is None, reason="needs mujoco")
@pytest.mark.parametrize("seed", [1, 2])
def test_no_error_on_a_body_mujoco_compiles_valid(seed):
    if not any(importlib.util.find_spec(n) for n in ("dm_control", "robosuite",
                                                      "gymnasium_robotics", "metaworld")):
        pytest.skip("no MJCF collection installed")
    done = subprocess.run([sys.executable, str(SCRIPT), "--sample", "8", "--seed", str(seed)],
                          capture_output=True, text=True, timeout=900)
    last = done.stdout.strip().splitlines()[-1]
    assert done.returncode == 0, done.stdout[-3000:]
    assert "models load in MuJoCo; " in last and " 0 on bodies MuJoCo compiles valid" in last
    loaded = int(last.split(" of ")[0])
    assert loaded > 0, last
