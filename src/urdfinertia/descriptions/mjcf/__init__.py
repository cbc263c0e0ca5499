"""MJCF (MuJoCo): reading bodies, geoms and inertials into the robot model; byte-splicing of
`<inertial>` elements back into the document.

Registers the `mjcf` `DescriptionFormat` (root
element `<mujoco>`) when imported (the registry imports it on first use).
"""

from __future__ import annotations

from urdfinertia.descriptions.formats import DescriptionFormat, register_format


def _read(data, path):  # noqa: ANN001, ANN202 - the format's signature
    from urdfinertia.descriptions.mjcf.read import robot_from_bytes

    return robot_from_bytes(data, path)


def _patch(data, new):  # noqa: ANN001, ANN202
    from urdfinertia.descriptions.mjcf.write import patch_inertials

    return patch_inertials(data, new)


def _relocate(data, source_dir, output_dir):  # noqa: ANN001, ANN202
    from urdfinertia.descriptions.mjcf.relocate import relocate_mjcf_refs

    return relocate_mjcf_refs(data, source_dir, output_dir)


register_format(DescriptionFormat(
    name="mjcf", roots=("mujoco",), suffixes=(".xml", ".mjcf"),
    read=_read, patch=_patch, relocate=_relocate,
))
