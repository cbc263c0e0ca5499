"""The batch tests exercise worker processes even on tiny meshes."""

from __future__ import annotations

import pytest


@pytest.fixture(autouse=True)
def _workers_for_any_work(monkeypatch):
    """Batch tests with ``jobs > 1`` exercise the worker processes even on tiny meshes (a real
    run keeps small work in one process: ``batch.run.WORKERS_FROM_BYTES``)."""
    from urdfinertia.batch import run

    monkeypatch.setattr(run, "WORKERS_FROM_BYTES", 0)
