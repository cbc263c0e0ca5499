"""SDFormat: models (and worlds holding models) read into the robot model; inertials spliced.

Registers the `sdf` `DescriptionFormat` (root
element `<sdf>`; suffixes `.sdf` and `.world`) when imported. `.poses` parses
poses and resolves `relative_to` frames, `.read` reads links, geometry and
inertials, `.write` splices new inertials into the document's own bytes.
"""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

from urdfinertia.descriptions.formats import DescriptionFormat, NewInertials, register_format

if TYPE_CHECKING:
    from urdfinertia.descriptions.model import Robot


def _read(data: bytes, path: Path) -> Robot:
    from urdfinertia.descriptions.sdf.read import robot_from_bytes

    return robot_from_bytes(data, path)


def _patch(data: bytes, new: NewInertials) -> bytes:
    from urdfinertia.descriptions.sdf.write import patch_inertials

    return patch_inertials(data, new)


def _relocate(data: bytes, source_dir: Path, output_dir: Path) -> tuple[bytes, int]:
    from urdfinertia.descriptions.sdf.relocate import relocate_sdf_refs

    return relocate_sdf_refs(data, source_dir, output_dir)


register_format(DescriptionFormat(
    name="sdf", roots=("sdf",), suffixes=(".sdf", ".world"),
    read=_read, patch=_patch, relocate=_relocate,
))
