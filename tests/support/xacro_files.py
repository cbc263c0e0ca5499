"""Helpers of the xacro tests: a document head, a file writer and clean xacro settings."""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path

import pytest

from urdfinertia.descriptions.xacro.expand import configure

HEAD = '<?xml version="1.0"?>\n<robot name="r" xmlns:xacro="http://www.ros.org/wiki/xacro">\n'


def write(folder: Path, name: str, text: str) -> Path:
    """``text`` written to ``folder/name`` (folders made); its path."""
    path = folder / name
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(text)
    return path


@pytest.fixture(autouse=True)
def clean_xacro_settings() -> Iterator[None]:
    """No xacro argument or package folder carried over from another test."""
    configure()
    yield
    configure()
