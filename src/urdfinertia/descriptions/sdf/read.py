"""Read an SDFormat document (`<sdf>`: models, or worlds holding models) into the model.

Every `<model>/<link>` becomes a [`Link`][urdfinertia.descriptions.model.Link] whose
geometry and inertial poses are in the link frame (`.poses` resolves `relative_to`
chains). Names: with one top-level model, its links keep their names and links of nested
models are scoped `nested::link`; with several top-level models every name starts with
its model's (`model::link`), as libsdformat scopes them. `<include>`d models are not
followed: the robot's notes say so.

Fault isolation: an element that cannot be read (unknown `relative_to`, a bad number, a
plane or heightmap, which have no volume) is dropped with a note on its link; an unreadable
`<inertial>` is reported and the link recomputed as if it had none. Only a document that
is not XML, is hostile, or holds no `<sdf>` root stops the reading.

Conventions (sdf/1.11/inertial.sdf): the inertial `<pose>` is the centre-of-mass frame C
relative to the link frame; `<inertia>` is about Co along C's axes, with products of
inertia "-m x y (not +m x y)": URDF's convention, so values pass through unchanged.
Omitted values take SDFormat's defaults (mass 1 kg, ixx = iyy = izz = 1 kg m^2).
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
from lxml import etree

from urdfinertia.descriptions.model import (
    Box,
    Capsule,
    Cylinder,
    Ellipsoid,
    GeometryRef,
    Inertial,
    Joint,
    Link,
    Mesh,
    Origin,
    Robot,
    Shape,
    Sphere,
)
from urdfinertia.descriptions.sdf.joints import joint_motion
from urdfinertia.descriptions.sdf.poses import MODEL_FRAME, Scope, matrix_rpy, parse_pose
from urdfinertia.descriptions.urdf.read import _NUMBER, in_range
from urdfinertia.descriptions.xml import parse_document
from urdfinertia.errors import UrdfError
from urdfinertia.findings import Finding
from urdfinertia.rules import Rule

DEFAULT_DENSITY = 1000.0
"""SDFormat 1.11's default density for automatic inertia, kg/m^3 (water)."""
_PREFIX_USE = re.compile(rb"</?([A-Za-z_][\w.\-]*):[A-Za-z_]")
_ROOT_TAG = re.compile(rb"<sdf\b")
_NO_VOLUME = {"plane": "a plane has no volume", "heightmap": "a heightmap is terrain",
              "image": "an extruded image is not supported", "polyline":
              "a polyline extrusion is not supported", "empty": "empty geometry",
              "cone": "a cone is not supported"}
"""Geometry that has no volume (or none this tool computes): dropped with a note."""
_INERTIA_KEYS = ("ixx", "ixy", "ixz", "iyy", "iyz", "izz")
_INERTIA_DEFAULTS = {"ixx": 1.0, "ixy": 0.0, "ixz": 0.0, "iyy": 1.0, "iyz": 0.0, "izz": 1.0}


#: a finding on a link before the link's name is known: (rule, message, line, element)
_Note = tuple[Rule, str, "int | None", "str | None"]


class _Dropped(Exception):
    """An element that is left out, with the reason and its rule (becomes a finding on its
    link)."""

    def __init__(self, cause: str, rule: Rule = Rule.VECTOR_UNPARSEABLE) -> None:
        super().__init__(cause)
        self.rule = rule


_LATE_DECLARATION = re.compile(rb"\A(\s+)(<\?xml\b[^>]*\?>)")


def _readable(data: bytes) -> bytes:
    """The bytes lxml is given: what libsdformat reads and libxml2 alone would refuse.

    An XML declaration after leading whitespace (TinyXML2 reads it) is blanked with spaces
    (it may only declare UTF-8 or ASCII: other encodings are refused below as usual), and
    undeclared prefixes are declared (`_declare_prefixes`). Line numbers are kept.
    """
    late = _LATE_DECLARATION.match(data)
    if late and not re.search(rb"encoding\s*=\s*[\"'](?!utf-?8|us-ascii|ascii)",
                              late.group(2), re.I):
        data = data[:late.start(2)] + b" " * len(late.group(2)) + data[late.end(2):]
    return _declare_prefixes(data)


def _declare_prefixes(data: bytes) -> bytes:
    """Declare namespace prefixes the document uses but never declares (`drake:`).

    libsdformat and Drake read such documents (TinyXML has no namespaces); libxml2 refuses
    them. Declarations are added inside the `<sdf` start tag, on its line, so that line
    numbers stay those of the file; only the bytes given to lxml change, never the output.
    """
    used = set(_PREFIX_USE.findall(data)) - {b"xml", b"xmlns"}
    missing = [p for p in sorted(used) if b"xmlns:" + p not in data]
    root = _ROOT_TAG.search(data)
    if not missing or root is None:
        return data
    decl = b"".join(b' xmlns:%s="urn:urdfinertia:undeclared:%s"' % (p, p) for p in missing)
    return data[:root.end()] + decl + data[root.end():]


@dataclass
class _Ctx:
    path: Path
    robot_notes: list[Finding] = field(default_factory=list)
    """Findings about the document (and, for statics, the joints' motion)."""

    def note(self, rule: Rule, message: str, line: int | None = None,
             link: str | None = None, element: str | None = None) -> None:
        self.robot_notes.append(Finding(rule, link, message, line, element))

    def numbers(self, el: etree._Element, text: str, *, finite: bool = True
                ) -> tuple[float, ...]:
        parts = text.split()
        shown = text.strip() if len(text) <= 80 else text[:77] + "..."
        values = []
        for p in parts:
            if _NUMBER.match(p):
                v = float(p)
            elif not finite and p.lower().lstrip("+-") in ("nan", "inf", "infinity"):
                v = float(p)
            else:
                raise _Dropped(f"<{el.tag}>{shown}</{el.tag}> is not a number (line "
                               f"{el.sourceline})")
            if math.isfinite(v) and not in_range(v):
                raise _Dropped(f"<{el.tag}>{shown}</{el.tag}> is out of range (line "
                               f"{el.sourceline})")
            values.append(v)
        return tuple(values)

    def number(self, el: etree._Element, *, finite: bool = True) -> float:
        values = self.numbers(el, el.text or "", finite=finite)
        if len(values) != 1:
            raise _Dropped(f"<{el.tag}> needs one number (line {el.sourceline})")
        return values[0]

    def positive(self, parent: etree._Element, tag: str, n: int = 1,
                 default: tuple[float, ...] | None = None) -> tuple[float, ...]:
        el = _child(parent, tag)
        if el is None:
            if default is None:
                raise _Dropped(f"<{parent.tag}> has no <{tag}> (line {parent.sourceline})")
            return default
        values = self.numbers(el, el.text or "")
        if len(values) != n or not all(v > 0 for v in values):
            raise _Dropped(f"<{tag}>{(el.text or '').strip()}</{tag}> must be {n} positive "
                           f"number(s) (line {el.sourceline})")
        return values


def _children(el: etree._Element, tag: str) -> list[etree._Element]:
    return [c for c in el if isinstance(c.tag, str) and c.tag == tag]


def _child(el: etree._Element, tag: str) -> etree._Element | None:
    found = _children(el, tag)
    return found[0] if found else None


def _pose(el: etree._Element, ctx: _Ctx) -> tuple[np.ndarray, str | None]:
    pose = _child(el, "pose")
    try:
        return parse_pose(pose, ctx.numbers)
    except ValueError as exc:
        line = pose.sourceline if pose is not None else el.sourceline
        raise _Dropped(f"{exc} (line {line})") from None


def _origin(t: np.ndarray) -> Origin:
    return Origin(tuple(float(v) for v in t[:3, 3]), matrix_rpy(t[:3, :3]))  # type: ignore[arg-type]


def _bool(el: etree._Element | None, default: bool = False) -> bool:
    if el is None:
        return default
    return (el if isinstance(el, str) else (el.text or "")).strip().lower() in ("true", "1")


def _shape(geometry: etree._Element, ctx: _Ctx, notes: list[_Note], label: str) -> Shape:
    kids = [c for c in geometry if isinstance(c.tag, str)]
    if len(kids) != 1:
        raise _Dropped(f"<geometry> must hold exactly one shape (line {geometry.sourceline})",
                       Rule.UNSUPPORTED_GEOMETRY)
    el = kids[0]
    kind = el.tag
    if kind == "box":
        return Box(ctx.positive(el, "size", 3, (1.0, 1.0, 1.0)))  # type: ignore[arg-type]
    if kind == "sphere":
        return Sphere(ctx.positive(el, "radius", 1, (1.0,))[0])
    if kind == "cylinder":
        return Cylinder(ctx.positive(el, "radius", 1, (1.0,))[0],
                        ctx.positive(el, "length", 1, (1.0,))[0])
    if kind == "capsule":
        radius = ctx.positive(el, "radius", 1, (0.5,))[0]
        length_el = _child(el, "length")
        length = ctx.number(length_el) if length_el is not None else 1.0
        if length < 0:
            raise _Dropped(f"<capsule> length must be >= 0 (line {el.sourceline})",
                           Rule.ZERO_SIZE_PRIMITIVE)
        return Capsule(radius, length)
    if kind == "ellipsoid":
        return Ellipsoid(ctx.positive(el, "radii", 3, (1.0, 1.0, 1.0)))  # type: ignore[arg-type]
    if kind == "mesh":
        uri_el = _child(el, "uri")
        uri = (uri_el.text or "").strip() if uri_el is not None else ""
        if not uri:
            raise _Dropped(f"<mesh> has no <uri> (line {el.sourceline})", Rule.MISSING_ATTRIBUTE)
        scale_el = _child(el, "scale")
        scale = ctx.numbers(scale_el, scale_el.text or "") if scale_el is not None else (
            1.0, 1.0, 1.0)
        if len(scale) != 3 or any(s == 0 for s in scale):
            raise _Dropped(f"<mesh><scale> must be 3 non-zero numbers (line {el.sourceline})",
                           Rule.ZERO_SIZE_PRIMITIVE)
        submesh = _child(el, "submesh")
        if submesh is not None:
            name_el = _child(submesh, "name")
            name = (name_el.text or "").strip() if name_el is not None else ""
            notes.append((Rule.READER_NOTE, f"<submesh> '{name}' not honoured: the whole "
                          "mesh file is used", submesh.sourceline, label))
        return Mesh(uri, (scale[0], scale[1], scale[2]))
    if kind in _NO_VOLUME:
        raise _Dropped(f"<{kind}> (line {el.sourceline}): {_NO_VOLUME[kind]}",
                       Rule.UNSUPPORTED_GEOMETRY)
    raise _Dropped(f"unsupported geometry <{kind}> (line {el.sourceline})",
                   Rule.UNSUPPORTED_GEOMETRY)


@dataclass
class _ModelFrames:
    """One model's scope with its place in the top-level model's frame."""

    scope: Scope
    in_top: np.ndarray
    prefix: str


def _build_scope(model_el: etree._Element, ctx: _Ctx, name: str) -> Scope:
    """Pass 1: every frame of a model (and of its nested models), unresolved."""
    scope = Scope(name)
    for el in model_el:
        if not isinstance(el.tag, str) or el.tag not in ("link", "joint", "frame", "model"):
            continue
        frame_name = el.get("name") or ""
        try:
            t, rel = _pose(el, ctx)
        except _Dropped as exc:
            ctx.note(Rule.VALUE_UNREADABLE, f"<{el.tag} name='{frame_name}'> pose "
                     f"unreadable, taken as identity: {exc}", el.sourceline)
            t, rel = np.eye(4), None
        if el.tag == "joint":
            child = _child(el, "child")
            default = (child.text or "").strip() if child is not None else MODEL_FRAME
        elif el.tag == "frame":
            default = el.get("attached_to") or MODEL_FRAME
        else:
            default = MODEL_FRAME
        try:
            scope.add(frame_name, t, rel or default, el.sourceline)
        except UrdfError as exc:
            ctx.note(Rule.DUPLICATE_NAME, exc.cause, el.sourceline)
            continue
        if el.tag == "model":
            scope.nested[frame_name] = _build_scope(el, ctx, frame_name)
            if el.get("placement_frame"):
                ctx.note(Rule.READER_NOTE, f"model '{frame_name}': placement_frame not "
                         "honoured (its pose is taken as the model frame's)", el.sourceline)
    return scope


def _in_link(scope: Scope, link_pose: np.ndarray, t: np.ndarray, rel: str | None,
             ) -> np.ndarray:
    """Pose `t` (relative to `rel`, default: the link) in the link frame."""
    if rel is None:
        return t
    found: np.ndarray = np.linalg.inv(link_pose) @ scope.in_model(rel) @ t
    return found


def _geometry(link_el: etree._Element, role: str, scope: Scope, link_pose: np.ndarray,
              ctx: _Ctx, notes: list[_Note], density: float | None,
              ) -> tuple[GeometryRef, ...]:
    refs = []
    for index, el in enumerate(_children(link_el, role)):
        name = el.get("name")
        label = f"{role}[{index}]" + (f" '{name}'" if name else "")
        try:
            geo = _child(el, "geometry")
            if geo is None:
                raise _Dropped(f"no <geometry> (line {el.sourceline})", Rule.UNSUPPORTED_GEOMETRY)
            shape = _shape(geo, ctx, notes, label)
            t, rel = _pose(el, ctx)
            try:
                pose = _in_link(scope, link_pose, t, rel)
            except UrdfError as exc:
                raise _Dropped(f"{exc.cause} (line {el.sourceline})") from None
            rho = density
            density_el = _child(el, "density") if role == "collision" else None
            if density_el is not None and density is not None:
                rho = ctx.number(density_el)
                if not rho > 0:
                    raise _Dropped(f"<density> must be positive (line {el.sourceline})")
        except _Dropped as exc:
            notes.append((exc.rule, f"dropped: {exc}", el.sourceline, label))
            continue
        refs.append(GeometryRef(role, index, name, _origin(pose), shape, el.sourceline,
                                density=rho, relative=rho is not None))
    return tuple(refs)


def _inertial(el: etree._Element, scope: Scope, link_pose: np.ndarray, ctx: _Ctx,
              ) -> Inertial:
    finite = False  # the inertial exactly as written, for the judgement
    mass_el = _child(el, "mass")
    mass = ctx.number(mass_el, finite=finite) if mass_el is not None else 1.0
    values = dict(_INERTIA_DEFAULTS)
    inertia_el = _child(el, "inertia")
    if inertia_el is not None:
        for key in _INERTIA_KEYS:
            item = _child(inertia_el, key)
            if item is not None:
                values[key] = ctx.number(item, finite=finite)
    t, rel = _pose(el, ctx)
    try:
        pose = _in_link(scope, link_pose, t, rel)
    except UrdfError as exc:
        raise _Dropped(exc.cause) from None
    origin = _origin(pose) if np.all(np.isfinite(pose)) else Origin(
        (float(t[0, 3]), float(t[1, 3]), float(t[2, 3])), (0.0, 0.0, 0.0))
    return Inertial(origin, mass, values["ixx"], values["ixy"], values["ixz"], values["iyy"],
                    values["iyz"], values["izz"], line=el.sourceline)


def _uses_density(link_el: etree._Element) -> bool:
    """Whether any collision states a `<density>`: then densities weigh the parts."""
    return any(_child(c, "density") is not None for c in _children(link_el, "collision"))


def _link(el: etree._Element, frames: _ModelFrames, ctx: _Ctx) -> tuple[Link, np.ndarray]:
    local = el.get("name") or ""
    scope = frames.scope
    notes: list[_Note] = []
    try:
        link_pose = scope.in_model(local)
    except UrdfError as exc:
        notes.append((Rule.VALUE_UNREADABLE, f"link pose cannot be resolved ({exc.cause}): "
                      "taken as the model frame", el.sourceline, "pose"))
        link_pose = np.eye(4)
    inertial_el = _child(el, "inertial")
    auto = inertial_el is not None and _bool(inertial_el.get("auto"))
    inertial = None
    if inertial_el is not None:
        try:
            inertial = _inertial(inertial_el, scope, link_pose, ctx)
        except _Dropped as exc:
            notes.append((exc.rule, f"<inertial> unreadable, recomputed as if absent: {exc}",
                          inertial_el.sourceline, "inertial"))
    density: float | None = None
    if auto or _uses_density(el):
        # SDFormat 1.11: collision <density>, else the inertial's <density>, else water
        own = _child(inertial_el, "density") if inertial_el is not None else None
        density = DEFAULT_DENSITY
        if own is not None:
            try:
                density = ctx.number(own)
            except _Dropped as exc:
                notes.append((exc.rule, f"<inertial><density> unreadable, "
                              f"{DEFAULT_DENSITY:g} used: {exc}", own.sourceline, "inertial"))
    if auto:
        has_mass = inertial_el is not None and _child(inertial_el, "mass") is not None
        notes.append((Rule.READER_NOTE, '<inertial auto="true">: computed from the '
                      "collisions as Gazebo does (fix writes the values and drops auto, "
                      "unless --keep-auto)", inertial_el.sourceline if inertial_el is not None
                      else None, "inertial"))
        if not has_mass:
            inertial = None  # the mass comes from the densities, as Gazebo computes it
    collisions = _geometry(el, "collision", scope, link_pose, ctx, notes, density)
    visuals = _geometry(el, "visual", scope, link_pose, ctx, notes, None)
    link = Link(name=frames.prefix + local, collisions=collisions, visuals=visuals,
                inertial=inertial, line=el.sourceline, auto_inertial=auto)
    for rule, message, line, element in notes:
        ctx.note(rule, message, line, link.name, element)
    return link, frames.in_top @ link_pose


def _collect(model_el: etree._Element, frames: _ModelFrames, ctx: _Ctx, links: list[Link],
             poses: dict[str, np.ndarray], joints: list[tuple[etree._Element, _ModelFrames]],
             ) -> None:
    """Pass 2: the links of a model and of its nested models, in document order."""
    for el in model_el:
        if not isinstance(el.tag, str):
            continue
        if el.tag == "link":
            link, pose = _link(el, frames, ctx)
            if link.name in poses:
                ctx.note(Rule.DUPLICATE_NAME, f"second link named '{link.name}' ignored",
                         el.sourceline)
                continue
            links.append(link)
            poses[link.name] = pose
        elif el.tag == "joint":
            joints.append((el, frames))
        elif el.tag == "model":
            name = el.get("name") or ""
            scope = frames.scope.nested.get(name)
            if scope is None:
                continue
            try:
                in_top = frames.in_top @ frames.scope.in_model(name)
            except UrdfError as exc:
                ctx.note(Rule.VALUE_UNREADABLE, f"model '{name}': {exc.cause}; taken at its "
                         "parent's frame", el.sourceline)
                in_top = frames.in_top
            _collect(el, _ModelFrames(scope, in_top, f"{frames.prefix}{name}::"), ctx, links,
                     poses, joints)
        elif el.tag == "include":
            _note_include(el, ctx)


def _note_include(el: etree._Element, ctx: _Ctx) -> None:
    uri = _child(el, "uri")
    shown = (uri.text or "").strip() if uri is not None else "?"
    ctx.note(Rule.INCLUDE_NOT_FOLLOWED, f"<include> of '{shown}' (line {el.sourceline}) not "
             "processed: fix the included file itself", el.sourceline)


def _joint(el: etree._Element, frames: _ModelFrames, poses: dict[str, np.ndarray],
           ctx: _Ctx, version: tuple[int, ...]) -> Joint | None:
    prefix = frames.prefix
    parent_el, child_el = _child(el, "parent"), _child(el, "child")
    parent = prefix + (parent_el.text or "").strip() if parent_el is not None else ""
    child = prefix + (child_el.text or "").strip() if child_el is not None else ""
    if parent not in poses or child not in poses:
        return None  # the world, or a frame: no link-to-link transform to record
    origin = _origin(np.linalg.inv(poses[parent]) @ poses[child])
    name = prefix + (el.get("name") or "")
    motion = joint_motion(el, frames.scope, child[len(prefix):], name, version,
                          ctx.robot_notes)
    return Joint(name, el.get("type") or "", parent, child, origin, el.sourceline,
                 **motion)  # type: ignore[arg-type]


def _version(text: str | None) -> tuple[int, ...]:
    """`<sdf version="1.6">` as (1, 6); the newest rules (1.11) when unreadable."""
    try:
        return tuple(int(p) for p in (text or "").strip().split("."))
    except ValueError:
        return (1, 11)


def robot_from_bytes(data: bytes, path: str | Path) -> Robot:
    """The robot model of an SDFormat document (its first `<model>`, nested models included).

    Parameters
    ----------
    data : bytes
        The document.
    path : str or Path
        Where it was read from (URIs resolve from its folder).

    Returns
    -------
    Robot
        The robot model: inertial values exactly as written, what was read past in
        `robot.findings`.

    Raises
    ------
    UrdfError
        When the document is not SDFormat or has no model.
    """
    path = Path(path)
    ctx = _Ctx(path)
    root = parse_document(_readable(data), path, ("sdf",), ctx.robot_notes)
    models: list[etree._Element] = []
    for el in root:
        if not isinstance(el.tag, str):
            continue
        if el.tag == "model":
            models.append(el)
        elif el.tag == "world":
            models.extend(_children(el, "model"))
            for inc in _children(el, "include"):
                _note_include(inc, ctx)
    links: list[Link] = []
    poses: dict[str, np.ndarray] = {}
    joints: list[tuple[etree._Element, _ModelFrames]] = []
    several = len(models) > 1
    for model_el in models:
        name = model_el.get("name") or ""
        scope = _build_scope(model_el, ctx, name)
        frames = _ModelFrames(scope, np.eye(4), f"{name}::" if several else "")
        _collect(model_el, frames, ctx, links, poses, joints)
    if not models:
        ctx.note(Rule.READER_NOTE, "no <model> in the document: nothing to compute")
    version = _version(root.get("version"))
    built = [j for j in (_joint(el, frames, poses, ctx, version) for el, frames in joints)
             if j is not None]
    name = models[0].get("name", "") if len(models) == 1 else path.stem
    return Robot(name=name, links=tuple(links), joints=tuple(built), path=path, format="sdf",
                 findings=tuple(dict.fromkeys(ctx.robot_notes)))
