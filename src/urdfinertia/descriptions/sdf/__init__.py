"""SDFormat: models (and worlds holding models) read into the robot model; inertials spliced.

Registers the ``sdf`` :class:`~urdfinertia.descriptions.formats.DescriptionFormat` (root
element ``<sdf>``; suffixes ``.sdf`` and ``.world``) when imported. :mod:`.poses` parses
poses and resolves ``relative_to`` frames, :mod:`.read` reads links, geometry and
inertials, :mod:`.write` splices new inertials into the document's own bytes.
"""

from __future__ import annotations

from urdfinertia.descriptions.formats import DescriptionFormat, register_format


def _read(data, path):  # noqa: ANN001, ANN202 - the format's signature
    from urdfinertia.descriptions.sdf.read import robot_from_bytes

    return robot_from_bytes(data, path)


def _read_lenient(data, path):  # noqa: ANN001, ANN202
    from urdfinertia.descriptions.sdf.read import robot_from_bytes

    return robot_from_bytes(data, path, lenient=True)


def _patch(data, new):  # noqa: ANN001, ANN202
    from urdfinertia.descriptions.sdf.write import patch_inertials

    return patch_inertials(data, new)


register_format(DescriptionFormat(
    name="sdf", roots=("sdf",), suffixes=(".sdf", ".world"),
    read=_read, read_lenient=_read_lenient, patch=_patch, isolates_links=True,
))
