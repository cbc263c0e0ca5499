"""OpenUSD (`.usd`, `.usda`, `.usdc`, `.usdz`): rigid bodies and their MassAPI read
into the robot model; corrected mass properties written as an override layer.

Registers the `usd` `DescriptionFormat` (by
suffix: USD files have no XML root) when imported. Reading needs OpenUSD's `pxr`, an
optional dependency (`.stage` says how to install it); the document bytes the
registry hands around are the asset's root layer for reading and, after
[`read_description`][urdfinertia.descriptions.formats.read_description], the override layer that
`patch` fills (`.write`).
"""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

from urdfinertia.descriptions.formats import DescriptionFormat, NewInertials, register_format

if TYPE_CHECKING:
    from urdfinertia.descriptions.model import Robot


def _read(data: bytes, path: Path) -> Robot:
    from urdfinertia.descriptions.usd.read import read

    return read(path).robot


def _expand(data: bytes, path: Path) -> bytes:
    from urdfinertia.descriptions.usd.read import read
    from urdfinertia.descriptions.usd.write import template

    found = read(path)
    return template(path, found.prim_paths, found.newton, found.meters_per_unit,
                    found.kilograms_per_unit, found.instances)


def _patch(data: bytes, new: NewInertials) -> bytes:
    from urdfinertia.descriptions.usd.write import patch

    return patch(data, new)


def _relocate(data: bytes, source: Path, output: Path) -> tuple[bytes, int]:
    from urdfinertia.descriptions.usd.write import relocate

    return relocate(data, source, output)


def _default_output(path: Path) -> Path:
    from urdfinertia.descriptions.usd.write import override_path

    return override_path(path)


def _write_in_place(path: Path, output: bytes) -> None:
    from urdfinertia.descriptions.usd.write import in_place

    in_place(path, output)


register_format(DescriptionFormat(
    name="usd", roots=(), suffixes=(".usd", ".usda", ".usdc", ".usdz"),
    read=_read, patch=_patch, expand=_expand,
    relocate=_relocate, default_output=_default_output, write_in_place=_write_in_place,
))
