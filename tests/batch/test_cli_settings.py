"""cli/batch.py: the speed options' defaults (workers, per-mesh time budget)."""

from __future__ import annotations

import argparse
import os

import pytest

from urdfinertia.cli.batch import add_batch_arguments, available_cores, settings_from_args
from urdfinertia.mesh.limits import BUDGET_ENV_VAR, mesh_seconds


def parse(*argv: str) -> argparse.Namespace:
    p = argparse.ArgumentParser()
    add_batch_arguments(p)
    return p.parse_args(list(argv))


def test_jobs_default_to_the_usable_cores():
    expected = (len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity")
                else os.cpu_count())
    assert available_cores() == expected
    assert settings_from_args(parse()).jobs == expected
    assert settings_from_args(parse("-j", "1")).jobs == 1


def test_mesh_seconds_reaches_the_repair_through_the_environment(monkeypatch):
    monkeypatch.setenv(BUDGET_ENV_VAR, "")  # restored (removed) after the test
    settings_from_args(parse("--mesh-seconds", "0.5"))
    assert os.environ[BUDGET_ENV_VAR] == "0.5"  # inherited by worker processes
    assert mesh_seconds() == pytest.approx(0.5)
    settings_from_args(parse("--mesh-seconds", "0"))
    assert mesh_seconds() is None  # 0: no limit
