"""MJCF frames and geoms in the model's terms: poses, full-size shapes, mesh assets.

MuJoCo's sizes are halves: `box` half extents, `cylinder`/`capsule` radius and half
length of the cylindrical part, `ellipsoid` semi-axes, `sphere` radius. `fromto`
places a capsule or cylinder between two points (radius `size[0]`), and a box or
ellipsoid with x and y half sizes both `size[0]` (what MuJoCo's compiler does; tested).
A mesh geom integrates the asset's file as it lies in the geom frame after the asset's
`scale`, `refpos` and `refquat` (vertex' = conj(refquat) (scale * vertex - refpos)):
MuJoCo re-centres meshes for its own use but moves the geom frame to match, so the body
sees the same solid (tested against MuJoCo's `inertia="exact"`).
"""

from __future__ import annotations

import math
import os
from typing import TYPE_CHECKING

import numpy as np
from lxml import etree

from urdfinertia.descriptions.mjcf.numbers import GeomError, numbers
from urdfinertia.descriptions.mjcf.orientation import (
    axisangle_matrix,
    euler_matrix,
    fromto_frame,
    matrix_rpy,
    quat_matrix,
    xyaxes_matrix,
    zaxis_matrix,
)
from urdfinertia.descriptions.model import (
    Box,
    Capsule,
    Cylinder,
    Ellipsoid,
    GeometryRef,
    Mesh,
    Origin,
    Shape,
    Sphere,
)
from urdfinertia.rules import Rule

if TYPE_CHECKING:
    from urdfinertia.descriptions.mjcf.document import MjcfDocument

_ORIENTATIONS = ("quat", "axisangle", "euler", "xyaxes", "zaxis")
_NO_VOLUME = ("plane", "hfield")
"""Geom types with no volume: MuJoCo gives them no inertia either."""


def rotation(attrs: dict[str, str], own: dict[str, str] | etree._Attrib, doc: MjcfDocument,
             finite: bool = True) -> np.ndarray:
    """(3, 3) orientation of an element: its own alternative, else its class's."""
    given = [k for k in _ORIENTATIONS if k in own]
    if len(given) > 1:
        raise GeomError("more than one orientation (" + ", ".join(given) + ")")
    key = given[0] if given else next((k for k in _ORIENTATIONS if k in attrs), None)
    if key is None:
        return np.eye(3)
    text = attrs[key] if key not in own else own[key]
    scale = math.pi / 180.0 if doc.degrees else 1.0
    try:
        if key == "quat":
            return quat_matrix(numbers(text, 4, key, finite=finite))
        if key == "axisangle":
            v = numbers(text, 4, key, finite=finite)
            return axisangle_matrix(v[:3], v[3] * scale)
        if key == "euler":
            v = numbers(text, 3, key, finite=finite)
            return euler_matrix(tuple(a * scale for a in v), doc.eulerseq)
        if key == "xyaxes":
            return xyaxes_matrix(numbers(text, 6, key, finite=finite))
        return zaxis_matrix(numbers(text, 3, key, finite=finite))
    except GeomError:
        raise
    except ValueError as exc:  # a zero axis or quaternion
        raise GeomError(str(exc)) from None


def pose_attrs(attrs: dict[str, str], own: dict[str, str] | etree._Attrib, doc: MjcfDocument,
               finite: bool = True) -> np.ndarray:
    """(4, 4) pose of `pos` and orientation in the parent frame."""
    pose = np.eye(4)
    pose[:3, :3] = rotation(attrs, own, doc, finite)
    pose[:3, 3] = numbers(attrs.get("pos", "0 0 0"), 3, "pos", finite=finite)
    return pose


def _size(attrs: dict[str, str], count: int, kind: str) -> tuple[float, ...]:
    values = numbers(attrs.get("size", "0"), 3, "size", at_least=1)
    values = values + (0.0,) * (3 - len(values))
    if not all(v > 0 for v in values[:count]):
        raise GeomError(f'{kind} size="{attrs.get("size", "")}" needs {count} positive '
                        "number(s)", Rule.ZERO_SIZE_PRIMITIVE)
    return values


def _primitive(kind: str, attrs: dict[str, str]) -> tuple[Shape, np.ndarray | None]:
    """The full-size shape and, with `fromto`, its pose in the geom's parent frame."""
    pose = None
    if "fromto" in attrs and kind in ("capsule", "cylinder", "box", "ellipsoid"):
        try:
            centre, rot, half = fromto_frame(numbers(attrs["fromto"], 6, "fromto"))
        except GeomError:
            raise
        except ValueError as exc:
            raise GeomError(str(exc)) from None
        pose = np.eye(4)
        pose[:3, :3] = rot
        pose[:3, 3] = centre
        r = _size(attrs, 1, kind)[0]
        if kind == "capsule":
            return Capsule(r, 2 * half), pose
        if kind == "cylinder":
            return Cylinder(r, 2 * half), pose
        if kind == "box":
            return Box((2 * r, 2 * r, 2 * half)), pose
        return Ellipsoid((r, r, half)), pose
    if kind == "sphere":
        return Sphere(_size(attrs, 1, kind)[0]), pose
    if kind == "capsule":
        r, h, _ = _size(attrs, 2, kind)
        return Capsule(r, 2 * h), pose
    if kind == "cylinder":
        r, h, _ = _size(attrs, 2, kind)
        return Cylinder(r, 2 * h), pose
    if kind == "box":
        return Box(tuple(2 * v for v in _size(attrs, 3, kind))), pose  # type: ignore[arg-type]
    if kind == "ellipsoid":
        return Ellipsoid(_size(attrs, 3, kind)), pose  # type: ignore[arg-type]
    raise GeomError(f'type="{kind}" is not supported', Rule.UNSUPPORTED_GEOMETRY)


def _mesh(attrs: dict[str, str], doc: MjcfDocument) -> tuple[Shape, np.ndarray, str | None]:
    """The mesh shape of a mesh geom and the mesh file's pose in the geom frame."""
    name = attrs.get("mesh")
    if not name:
        raise GeomError('type="mesh" without a mesh attribute', Rule.MISSING_ATTRIBUTE)
    asset = doc.meshes.get(name)
    if asset is None:
        raise GeomError(f"no <mesh name=\"{name}\"> among the assets", Rule.MESH_UNRESOLVED)
    a = asset.attrs
    if "file" not in a:
        raise GeomError(f"mesh '{name}' has inline vertex data (only mesh files are read)",
                        Rule.UNSUPPORTED_GEOMETRY)
    inertia = a.get("inertia", "legacy")
    if inertia == "shell":
        raise GeomError(f"mesh '{name}' has inertia=\"shell\" (surface mass): not supported",
                        Rule.UNSUPPORTED_GEOMETRY)
    scale = numbers(a.get("scale", "1 1 1"), 3, "scale")
    if any(s == 0 for s in scale):
        raise GeomError(f"mesh '{name}' has a zero scale component", Rule.ZERO_SIZE_PRIMITIVE)
    refpos = np.array(numbers(a.get("refpos", "0 0 0"), 3, "refpos"))
    try:
        refrot = quat_matrix(numbers(a.get("refquat", "1 0 0 0"), 4, "refquat"))
    except ValueError as exc:
        raise GeomError(str(exc)) from None
    file = a["file"].replace("\\", "/")
    meshdir = doc.meshdir.replace("\\", "/")
    rel = file if os.path.isabs(file) or not meshdir else f"{meshdir.rstrip('/')}/{file}"
    if not os.path.isabs(rel) and not asset.source.main:
        # MuJoCo looks for a mesh declared in an included file under the main model's
        # folder (with meshdir) first, then beside the included file (without meshdir)
        model_dir = doc.path.parent
        beside = asset.source.path.parent / file
        if not (model_dir / rel).is_file() and beside.is_file():
            rel = os.path.relpath(beside, model_dir).replace("\\", "/")
    pose = np.eye(4)
    pose[:3, :3] = refrot.T
    pose[:3, 3] = -refrot.T @ refpos
    note = None
    if inertia == "convex":
        note = f"mesh '{name}': MuJoCo's inertia=\"convex\" would use the hull; the mesh " \
               "itself is integrated"
    return Mesh(rel, scale), pose, note  # type: ignore[arg-type]


def geom_ref(el: etree._Element, attrs: dict[str, str], doc: MjcfDocument, frame: np.ndarray,
             ) -> tuple[GeometryRef, int, str | None] | None:
    """A geom as a `GeometryRef` (index 0), its `group` and a note; None when it
    has no volume (plane, height field)."""
    kind = attrs.get("type", "sphere")
    if kind in _NO_VOLUME:
        return None
    if attrs.get("shellinertia", "false") == "true":
        raise GeomError('shellinertia="true" (surface mass) is not supported',
                        Rule.UNSUPPORTED_GEOMETRY)
    note = None
    pose = pose_attrs(attrs, el.attrib, doc)
    if kind == "mesh":
        shape, mesh_pose, note = _mesh(attrs, doc)
        pose = pose @ mesh_pose
    elif "mesh" in attrs:
        raise GeomError(f'type="{kind}" fitted to mesh \'{attrs["mesh"]}\' (MuJoCo\'s '
                        "fitting) is not supported")
    else:
        shape, fromto_pose = _primitive(kind, attrs)
        if fromto_pose is not None:
            pose = fromto_pose
    pose = frame @ pose
    role = "visual" if _int(attrs, "contype", 1) == 0 and _int(attrs, "conaffinity", 1) == 0 \
        else "collision"
    density = numbers(attrs["density"], 1, "density")[0] if "density" in attrs else None
    mass = numbers(attrs["mass"], 1, "mass")[0] if "mass" in attrs else None
    if (density is not None and density < 0) or (mass is not None and mass < 0):
        raise GeomError("negative density or mass")
    origin = Origin(tuple(float(v) for v in pose[:3, 3]), matrix_rpy(pose[:3, :3]))  # type: ignore[arg-type]
    ref = GeometryRef(role, 0, attrs.get("name"), origin, shape, el.sourceline,
                      density=density, mass=mass)
    return ref, _int(attrs, "group", 0), note


def _int(attrs: dict[str, str], key: str, default: int) -> int:
    text = attrs.get(key)
    if text is None:
        return default
    try:
        return int(text.strip())
    except ValueError:
        raise GeomError(f'{key}="{text}" is not an integer') from None
