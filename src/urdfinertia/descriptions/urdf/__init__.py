"""URDF: reading into the robot model (once, leniently), byte-splicing of inertials.

Registers the `urdf` `DescriptionFormat` when
imported (the registry imports it on first use).
"""

from __future__ import annotations

from urdfinertia.descriptions.formats import DescriptionFormat, register_format


def _read(data, path):  # noqa: ANN001, ANN202 - the format's signature
    from urdfinertia.descriptions.urdf.read import robot_from_bytes

    return robot_from_bytes(data, path)


def _patch(data, new):  # noqa: ANN001, ANN202
    from urdfinertia.descriptions.urdf.write import patch_inertials

    return patch_inertials(data, new)


def _relocate(data, source_dir, output_dir):  # noqa: ANN001, ANN202
    from urdfinertia.descriptions.urdf.mesh_refs import relocate_mesh_refs

    return relocate_mesh_refs(data, source_dir, output_dir)


register_format(DescriptionFormat(
    name="urdf", roots=("robot",), suffixes=(".urdf",),
    read=_read, patch=_patch, relocate=_relocate,
))
