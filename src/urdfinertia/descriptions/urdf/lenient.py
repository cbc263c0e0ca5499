"""Inertials exactly as written, including values no simulator accepts.

:func:`urdf_read.read_urdf` ignores an ``<inertial>`` holding non-finite numbers or absurd
magnitudes (it recomputes it). A linter must instead judge a ``nan``, ``inf`` or a mass of
``6e9`` (mm^3 taken as m^3) as a finding on its link, so :func:`read_urdf_lenient` reads
the document the same way but lets such values through inside ``<inertial>`` (into
:class:`urdf_model.Inertial`, which holds plain floats). Elements dropped and values
ignored are in :attr:`Robot.problems`, as for ``fix``.
"""

from __future__ import annotations

import dataclasses
import math
from pathlib import Path

from urdfinertia.descriptions.model import Origin, Problem, Robot
from urdfinertia.descriptions.urdf.read import (
    in_range,
    parse_xml,
    read_urdf_bytes,
    robot_from_element,
)

_INERTIA_KEYS = ("ixx", "ixy", "ixz", "iyy", "iyz", "izz")


def read_urdf_lenient(path: str | Path) -> tuple[Robot, bytes]:
    """Like :func:`urdf_read.read_urdf`, but non-finite inertial values are kept as NaN/inf."""
    data = read_urdf_bytes(path)
    return robot_from_bytes_lenient(data, path), data


def robot_from_bytes_lenient(data: bytes, path: str | Path) -> Robot:
    path = Path(path)
    notes: list[Problem] = []
    root = parse_xml(data, path, notes)
    kept: dict[str, dict[str, tuple[float, ...]]] = {}
    for link_el in root.iterchildren("link"):
        for inertial_el in link_el.iterchildren("inertial"):
            found = _neutralise(inertial_el)
            if found:
                kept[link_el.get("name", "")] = found
            break  # the reader uses the first <inertial> only
    robot = robot_from_element(root, path, notes)
    if not kept:
        return robot
    links = tuple(_restore(link, kept[link.name]) if link.name in kept else link
                  for link in robot.links)
    return dataclasses.replace(robot, links=links)


def _non_finite(text: str | None) -> tuple[float, ...] | None:
    if text is None:
        return None
    try:
        values = tuple(float(p) for p in text.split())
    except ValueError:
        return None  # not numbers at all: the strict reader reports it
    readable = all(math.isfinite(v) and in_range(v) for v in values)
    return None if readable else values


def _neutralise(inertial_el) -> dict[str, tuple[float, ...]]:
    """Replace non-finite and out-of-range numbers by zeros in the tree; return what they
    were."""
    found: dict[str, tuple[float, ...]] = {}
    for child in inertial_el:
        keys: tuple[str, ...]
        if child.tag == "mass":
            keys = ("value",)
        elif child.tag == "inertia":
            keys = _INERTIA_KEYS
        elif child.tag == "origin":
            keys = ("xyz", "rpy")
        else:
            continue
        for key in keys:
            values = _non_finite(child.get(key))
            if values is not None:
                found[f"{child.tag}.{key}"] = values
                child.set(key, " ".join("0" for _ in values))
    return found


def _restore(link, found: dict[str, tuple[float, ...]]):
    inertial = link.inertial
    if inertial is None:
        return link
    changes: dict[str, object] = {}
    origin = inertial.origin
    if "origin.xyz" in found:
        origin = dataclasses.replace(origin, xyz=found["origin.xyz"])
    if "origin.rpy" in found:
        origin = dataclasses.replace(origin, rpy=found["origin.rpy"])
    if origin is not inertial.origin:
        changes["origin"] = Origin(origin.xyz, origin.rpy)
    if "mass.value" in found:
        changes["mass"] = found["mass.value"][0]
    for key in _INERTIA_KEYS:
        if f"inertia.{key}" in found:
            changes[key] = found[f"inertia.{key}"][0]
    return dataclasses.replace(link, inertial=dataclasses.replace(inertial, **changes))
