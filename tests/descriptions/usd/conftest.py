"""The USD tests need OpenUSD's ``pxr`` (the dev extra installs it). They are skipped only
when ``pxr`` is not installed at all: a ``pxr`` that is installed but fails to load (two
providers in one environment) fails them."""

from __future__ import annotations

import importlib.util
from pathlib import Path

import pytest

HERE = Path(__file__).resolve().parent


def pytest_collection_modifyitems(config, items):  # noqa: ANN001, ANN201
    if importlib.util.find_spec("pxr") is not None:
        return
    skip = pytest.mark.skip(reason="OpenUSD's pxr is not installed (pip install usd-core)")
    for item in items:
        if HERE in Path(str(item.fspath)).resolve().parents:
            item.add_marker(skip)
