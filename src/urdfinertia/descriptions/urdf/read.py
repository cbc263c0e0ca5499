"""Read a URDF with a hardened lxml parser into :mod:`urdf_model` objects.

Entities are never resolved, no DTD is loaded and nothing is fetched from the network;
documents that declare entities are refused outright (XXE, "billion laughs").

One bad element never sinks a robot: a ``<collision>``/``<visual>`` that cannot be read
(numbers that are not plain finite decimals, a zero or negative size, an unsupported
shape, an unexpanded ``$(...)``) is dropped from the model and a value not needed for
inertials (a joint origin, an existing ``<inertial>``, a negative existing mass) is
ignored, each recorded as a :class:`~urdfinertia.descriptions.model.Problem` in
:attr:`Robot.problems` with its line. Lenient where the reading is unambiguous (commas
between numbers), strict where it is not (4 numbers where 3 are needed). Only a document
that cannot be read as a whole (not XML, not a ``<robot>``, a nameless or duplicate link)
raises :class:`UrdfError`.
"""

from __future__ import annotations

import dataclasses
import math
import re
from pathlib import Path
from typing import Any

from lxml import etree

from urdfinertia.descriptions.formats import read_bytes
from urdfinertia.descriptions.model import (
    Box,
    Capsule,
    Cylinder,
    GeometryRef,
    Inertial,
    Joint,
    Link,
    Mesh,
    Origin,
    Problem,
    Robot,
    Shape,
    Sphere,
)
from urdfinertia.descriptions.xml import parse_document
from urdfinertia.errors import UrdfError

#: Largest magnitude of any number read (SI units: 1e9 m, kg or kg m^2 describe no robot);
#: keeps every product the maths forms far from float64 overflow (1e308).
MAX_MAGNITUDE = 1e9
#: Smallest non-zero magnitude read: float64's smallest normal number. A subnormal value
#: (``1e-320``) is what an underflow leaves, never a stated quantity; computing with it
#: underflows to zero (a kept mass of 1e-320 kg gave a tensor of principal moments
#: ``0, 3.5e-323, 3.5e-323``, not positive definite).
MIN_MAGNITUDE = 2.2250738585072014e-308


def in_range(value: float) -> bool:
    """Finite, at most :data:`MAX_MAGNITUDE` and not subnormal (zero is in range)."""
    magnitude = abs(value)
    return magnitude == 0.0 or MIN_MAGNITUDE <= magnitude <= MAX_MAGNITUDE
#: A decimal number as XML Schema writes a double, without NaN/INF (checked separately)
#: and without what Python's ``float`` also takes (``1_0``, non-ASCII digits, spaces).
_NUMBER = re.compile(r"[+-]?(?:[0-9]+(?:\.[0-9]*)?|\.[0-9]+)(?:[eE][+-]?[0-9]+)?\Z")
_NUMBER_MATCH = _NUMBER.match
#: Attribute texts already read without error, by (text, count): most are repeated ("0 0 0",
#: "1 1 1", the same inertia in mirrored links). Bounded: cleared when full.
_VALID_NUMBERS: dict[tuple[str, int], tuple[float, ...]] = {}
_MAX_VALID_NUMBERS = 1 << 16


def parse_xml(data: bytes, file: str | Path,
              notes: list[Problem] | None = None) -> etree._Element:
    """Parse URDF bytes into an lxml root element (:func:`xml.parse_document`)."""
    return parse_document(data, file, ("robot",), notes)


def read_urdf_bytes(path: str | Path) -> bytes:
    """The file's bytes, or a :class:`UrdfError` naming it."""
    return read_bytes(path)


def read_urdf(path: str | Path) -> tuple[Robot, bytes]:
    """Read ``path`` and return the robot model and the file's original bytes."""
    data = read_urdf_bytes(path)
    return robot_from_bytes(data, path), data


def robot_from_bytes(data: bytes, path: str | Path) -> Robot:
    notes: list[Problem] = []
    root = parse_xml(data, path, notes)
    robot = robot_from_element(root, Path(path), notes)
    signs = inertial_sign_problems(robot)
    if not signs:
        return robot
    return dataclasses.replace(robot, problems=robot.problems + tuple(signs))


#: Negative diagonal moments down to this (kg m^2) are CAD round-off of 0 (iCub has
#: ``ixx="-5.42101e-20"``) and are accepted; ``fix`` replaces them anyway.
NEGATIVE_MOMENT_ROUNDOFF = 1e-12


def inertial_sign_problems(robot: Robot) -> list[Problem]:
    """An existing ``<inertial>`` with a negative mass or diagonal moment, as problems.

    Such values describe no body in any frame (a diagonal entry of a positive
    semi-definite tensor is never negative): ``fix`` does not keep them (kind "ignored").
    A zero mass is a common placeholder and is accepted. The linter (:mod:`lenient`)
    reports them as findings instead.
    """
    out = []
    for link in robot.links:
        inertial = link.inertial
        if inertial is None:
            continue
        def ignored(cause: str, inertial: Inertial = inertial, link: Link = link) -> Problem:
            return Problem("negative-inertial", cause, line=inertial.line, link=link.name,
                           element="inertial", kind="ignored")

        if inertial.mass < 0:
            out.append(ignored(f"<mass value=\"{inertial.mass:g}\"> is negative"))
        for key in ("ixx", "iyy", "izz"):
            value = getattr(inertial, key)
            if value < -NEGATIVE_MOMENT_ROUNDOFF:
                out.append(ignored(f"<inertia {key}=\"{value:g}\"> is negative"))
    return out


def robot_from_element(root: etree._Element, path: Path,
                       notes: list[Problem] | None = None) -> Robot:
    """The robot of a parsed ``<robot>``; ``notes``: problems found before (parsing)."""
    problems: list[Problem] = list(notes or ())
    links: list[Link] = []
    seen: set[str] = set()
    for el in _children(root, "link"):
        link = _link(el, path, problems)
        if link.name in seen:
            raise UrdfError(f"duplicate link name '{link.name}'", file=path, line=el.sourceline)
        seen.add(link.name)
        links.append(link)
    joints = tuple(_joint(el, path, problems) for el in _children(root, "joint"))
    return Robot(name=root.get("name", ""), links=tuple(links), joints=joints, path=path,
                 problems=tuple(problems))


def _children(el: etree._Element, tag: str) -> list[etree._Element]:
    return [c for c in el if isinstance(c.tag, str) and c.tag == tag]


#: Numbers separated by commas (and spaces): read as urdfdom's neighbours do, with a note.
_COMMAS = re.compile(r"\s*,\s*|\s+")


class _Ctx:
    """Where we are, for error messages; collects the problems read past."""

    def __init__(self, path: Path, link: str | None, problems: list[Problem]) -> None:
        self.path = path
        self.link = link
        self.problems = problems

    def error(self, cause: str, el: etree._Element, code: str = "bad-number") -> UrdfError:
        return UrdfError(cause, file=self.path, line=el.sourceline, link=self.link, code=code)

    def note(self, exc: UrdfError, element: str | None, kind: str) -> None:
        self.problems.append(Problem(exc.code, exc.cause,
                                     line=exc.line, link=self.link, element=element,
                                     kind=kind))

    def floats(self, el: etree._Element, attr: str, n: int, default: str | None = None,
               ) -> tuple[float, ...]:
        text = el.get(attr, default)
        if text is None:
            raise self.error(f"<{el.tag}> is missing attribute '{attr}'", el,
                             "missing-attribute")
        known = _VALID_NUMBERS.get((text, n))
        if known is not None:
            return known
        shown = text if len(text) <= 80 else text[:77] + "..."
        if "$(" in text:
            raise self.error(f"<{el.tag} {attr}=\"{shown}\"> holds an unexpanded "
                             "substitution $(...): run xacro first", el,
                             "unexpanded-substitution")
        parts = text.split()
        commas = "," in text
        if commas:  # "1.57, 1.30 1.57": one reading only, so it is read (with a note)
            parts = [p for p in _COMMAS.split(text.strip()) if p]
        if len(parts) != n:
            raise self.error(f"<{el.tag} {attr}=\"{shown}\"> needs {n} numbers", el)
        if not all(map(_NUMBER_MATCH, parts)):
            raise self.error(f"<{el.tag} {attr}=\"{shown}\"> is not a number", el)
        values = tuple(map(float, parts))
        if not all(map(math.isfinite, values)):
            raise self.error(f"<{el.tag} {attr}=\"{shown}\"> is out of range (not finite)",
                             el)
        if values and max(map(abs, values)) > MAX_MAGNITUDE:  # all finite here
            raise self.error(f"<{el.tag} {attr}=\"{shown}\"> is out of range (magnitude "
                             f"above {MAX_MAGNITUDE:g})", el)
        if not all(map(in_range, values)):
            raise self.error(f"<{el.tag} {attr}=\"{shown}\"> is out of range (subnormal: "
                             f"non-zero below {MIN_MAGNITUDE:.3g})", el)
        if commas:
            self.problems.append(Problem(
                "comma-vector", f"<{el.tag} {attr}=\"{shown}\"> separates numbers with "
                "commas (urdfdom refuses it): read as spaces", line=el.sourceline,
                link=self.link, kind="lenient"))
            return values
        if len(_VALID_NUMBERS) >= _MAX_VALID_NUMBERS:
            _VALID_NUMBERS.clear()
        _VALID_NUMBERS[text, n] = values
        return values

    def positive(self, el: etree._Element, attr: str, n: int = 1) -> tuple[float, ...]:
        values = self.floats(el, attr, n)
        if not all(v > 0 for v in values):
            raise self.error(f"<{el.tag} {attr}=\"{el.get(attr)}\"> must be positive", el,
                             "zero-size")
        return values


def _origin(parent: etree._Element, ctx: _Ctx) -> Origin:
    found = _children(parent, "origin")
    if not found:
        return Origin()
    el = found[0]
    return Origin(ctx.floats(el, "xyz", 3, "0 0 0"), ctx.floats(el, "rpy", 3, "0 0 0"))  # type: ignore[arg-type]


def _shape(geometry: etree._Element, ctx: _Ctx) -> Shape:
    kids = [c for c in geometry if isinstance(c.tag, str)]
    if len(kids) != 1:
        raise ctx.error("<geometry> must hold exactly one shape", geometry,
                        "unsupported-shape")
    el = kids[0]
    if el.tag == "box":
        return Box(ctx.positive(el, "size", 3))  # type: ignore[arg-type]
    if el.tag == "cylinder":
        return Cylinder(ctx.positive(el, "radius")[0], ctx.positive(el, "length")[0])
    if el.tag == "sphere":
        return Sphere(ctx.positive(el, "radius")[0])
    if el.tag == "capsule":
        radius = ctx.positive(el, "radius")[0]
        length = ctx.floats(el, "length", 1)[0]
        if length < 0:
            raise ctx.error(f"<capsule length=\"{el.get('length')}\"> must be >= 0", el,
                            "zero-size")
        return Capsule(radius, length)
    if el.tag == "mesh":
        filename = el.get("filename")
        if not filename:
            raise ctx.error("<mesh> is missing attribute 'filename'", el,
                            "missing-attribute")
        if "$(" in filename:
            raise ctx.error(f"<mesh filename=\"{filename}\"> holds an unexpanded "
                            "substitution $(...): run xacro first", el,
                            "unexpanded-substitution")
        scale = ctx.floats(el, "scale", 3, "1 1 1")
        if any(s == 0 for s in scale):
            raise ctx.error(f"<mesh scale=\"{el.get('scale')}\"> has a zero component", el,
                            "zero-size")
        return Mesh(filename, scale)  # type: ignore[arg-type]
    raise ctx.error(f"unsupported geometry <{el.tag}>", el, "unsupported-shape")


def _geometry_refs(link_el: etree._Element, role: str, ctx: _Ctx) -> tuple[GeometryRef, ...]:
    """The link's readable elements of ``role``; each unreadable one is dropped with a
    problem (its index stays its position in the file, so labels match the document)."""
    refs = []
    for index, el in enumerate(_children(link_el, role)):
        name = el.get("name")
        try:
            geo = _children(el, "geometry")
            if not geo:
                raise ctx.error(f"<{role}> has no <geometry>", el, "unsupported-shape")
            refs.append(GeometryRef(role, index, name, _origin(el, ctx),
                                    _shape(geo[0], ctx), el.sourceline))
        except UrdfError as exc:
            label = f"{role}[{index}]" + (f" '{name}'" if name else "")
            ctx.note(exc, label, "dropped")
    return tuple(refs)


def _inertial(link_el: etree._Element, ctx: _Ctx) -> Inertial | None:
    found = _children(link_el, "inertial")
    if not found:
        return None
    el = found[0]
    mass_el = _children(el, "mass")
    inertia_el = _children(el, "inertia")
    if not mass_el:
        raise ctx.error("<inertial> has no <mass>", el, "missing-attribute")
    mass = ctx.floats(mass_el[0], "value", 1)[0]
    if inertia_el:
        values = [ctx.floats(inertia_el[0], k, 1, "0")[0]
                  for k in ("ixx", "ixy", "ixz", "iyy", "iyz", "izz")]
    else:
        values = [0.0] * 6
    ixx, ixy, ixz, iyy, iyz, izz = values
    return Inertial(_origin(el, ctx), mass, ixx, ixy, ixz, iyy, iyz, izz, line=el.sourceline)


def _link(el: etree._Element, path: Path, problems: list[Problem]) -> Link:
    name = el.get("name")
    if not name:
        raise UrdfError("<link> without a name", file=path, line=el.sourceline)
    ctx = _Ctx(path, name, problems)
    try:
        inertial = _inertial(el, ctx)
    except UrdfError as exc:  # fix recomputes it; left as written if it cannot
        ctx.note(exc, "inertial", "ignored")
        inertial = None
    return Link(
        name=name,
        collisions=_geometry_refs(el, "collision", ctx),
        visuals=_geometry_refs(el, "visual", ctx),
        inertial=inertial,
        line=el.sourceline,
    )


def _joint(el: etree._Element, path: Path, problems: list[Problem]) -> Joint:
    ctx = _Ctx(path, None, problems)
    parent = _children(el, "parent")
    child = _children(el, "child")
    name = el.get("name", "")
    try:
        origin = _origin(el, ctx)
    except UrdfError as exc:  # not needed for inertials: a note, never a refusal
        ctx.note(exc, f"joint '{name}' origin", "ignored")
        origin = Origin()
    return Joint(
        name=name,
        type=el.get("type", ""),
        parent=parent[0].get("link", "") if parent else "",
        child=child[0].get("link", "") if child else "",
        origin=origin,
        line=el.sourceline,
        **_joint_motion(el),
    )


def _number(text: str | None) -> float | None:
    try:
        value = float(text) if text is not None else None
    except ValueError:
        return None
    return value if value is not None and math.isfinite(value) else None


def _joint_motion(el: etree._Element) -> dict[str, Any]:
    """Axis, limits and mimic of a joint (statics only: an unreadable value is left out)."""
    out: dict[str, Any] = {}
    axis = el.find("axis")
    if axis is not None:
        parts = [_number(x) for x in (axis.get("xyz") or "").split()]
        if len(parts) == 3 and all(x is not None for x in parts):
            out["axis"] = tuple(float(x) for x in parts if x is not None)
    limit = el.find("limit")
    if limit is not None:
        for key in ("lower", "upper", "effort"):
            out[key] = _number(limit.get(key))
    mimic = el.find("mimic")
    if mimic is not None and mimic.get("joint"):
        multiplier = _number(mimic.get("multiplier"))
        out["mimic"] = (mimic.get("joint"), 1.0 if multiplier is None else multiplier,
                        _number(mimic.get("offset")) or 0.0)
    return out
