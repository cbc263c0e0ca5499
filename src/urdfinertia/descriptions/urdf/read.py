"""Read a URDF with a hardened lxml parser into `urdf_model` objects.

Entities are never resolved, no DTD is loaded and nothing is fetched from the network;
documents that declare entities are refused outright (XXE, "billion laughs").

One reading, lenient: the document is read once, and every value carries its own
validity. The `<inertial>` is read exactly as written, values no simulator accepts
included (NaN, infinite, negative, absurd magnitudes; a number that cannot be read is NaN,
with a finding), so that the judgement sees what the author wrote. One bad element never
sinks a robot: a `<collision>`/`<visual>` that cannot be read (numbers that are not
plain finite decimals, a zero or negative size, an unsupported shape, an unexpanded
`$(...)`) is dropped from the model and a value not needed for inertials (a joint
origin) is taken as its default, each recorded as a
[`Finding`][urdfinertia.findings.Finding] in `Robot.findings` with its line. Lenient where the
reading is unambiguous (commas between numbers), strict where it is not (4
numbers where 3 are needed). Only a document that cannot be read as a whole (not XML, not
a `<robot>`, a nameless or duplicate link) raises `UrdfError`.
"""

from __future__ import annotations

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
    Robot,
    Shape,
    Sphere,
)
from urdfinertia.descriptions.xml import parse_document
from urdfinertia.errors import UrdfError
from urdfinertia.findings import Finding
from urdfinertia.rules import Rule

MAX_MAGNITUDE = 1e9
"""Largest magnitude of any number read (SI units: 1e9 m, kg or kg m^2 describe no robot); keeps
every product the maths forms far from float64 overflow (1e308).
"""
MIN_MAGNITUDE = 2.2250738585072014e-308
"""Smallest non-zero magnitude read: float64's smallest normal number. A subnormal value
(`1e-320`) is what an underflow leaves, never a stated quantity; computing with it
underflows to zero (a kept mass of 1e-320 kg gave a tensor of principal moments
`0, 3.5e-323, 3.5e-323`, not positive definite).
"""


def in_range(value: float) -> bool:
    """Finite, at most `MAX_MAGNITUDE` and not subnormal (zero is in range)."""
    magnitude = abs(value)
    return magnitude == 0.0 or MIN_MAGNITUDE <= magnitude <= MAX_MAGNITUDE


#: A decimal number as XML Schema writes a double, without NaN/INF (checked separately)
#: and without what Python's ``float`` also takes (``1_0``, non-ASCII digits, spaces).
_NUMBER = re.compile(r"[+-]?(?:[0-9]+(?:\.[0-9]*)?|\.[0-9]+)(?:[eE][+-]?[0-9]+)?\Z")
"""A decimal number as XML Schema writes a double, without NaN/INF (checked separately) and without
what Python's `float` also takes (`1_0`, non-ASCII digits, spaces).
"""
_NUMBER_MATCH = _NUMBER.match
_VALID_NUMBERS: dict[tuple[str, int], tuple[float, ...]] = {}
"""Attribute texts already read without error, by (text, count): most are repeated ("0 0 0", "1 1
1", the same inertia in mirrored links). Bounded: cleared when full.
"""
_MAX_VALID_NUMBERS = 1 << 16


def parse_xml(data: bytes, file: str | Path,
              notes: list[Finding] | None = None) -> etree._Element:
    """Parse URDF bytes into an lxml root element ([`xml.parse_document`][xml.parse_document])."""
    return parse_document(data, file, ("robot",), notes)


def read_urdf_bytes(path: str | Path) -> bytes:
    """The file's bytes, or a `UrdfError` naming it."""
    return read_bytes(path)


def read_urdf(path: str | Path) -> tuple[Robot, bytes]:
    """Read `path` and return the robot model and the file's original bytes."""
    data = read_urdf_bytes(path)
    return robot_from_bytes(data, path), data


def robot_from_bytes(data: bytes, path: str | Path) -> Robot:
    """The robot model of a URDF document (the module doc says how it reads).

    Parameters
    ----------
    data : bytes
        The document.
    path : str or Path
        Where it was read from (relative mesh references resolve from its folder).

    Returns
    -------
    Robot
        The robot model; what was read past is in `robot.findings`.

    Raises
    ------
    UrdfError
        When the document cannot be read as a URDF at all.
    """
    notes: list[Finding] = []
    root = parse_xml(data, path, notes)
    return robot_from_element(root, Path(path), notes)


def robot_from_element(root: etree._Element, path: Path,
                       notes: list[Finding] | None = None) -> Robot:
    """The robot of a parsed `<robot>`; `notes`: findings made before (parsing)."""
    problems: list[Finding] = list(notes or ())
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
                 findings=tuple(problems))


def _children(el: etree._Element, tag: str) -> list[etree._Element]:
    return [c for c in el if isinstance(c.tag, str) and c.tag == tag]


_COMMAS = re.compile(r"\s*,\s*|\s+")
"""Numbers separated by commas (and spaces): read as urdfdom's neighbours do, with a note."""


class _Ctx:
    """Where we are, for error messages; collects the findings of what was read past."""

    def __init__(self, path: Path, link: str | None, problems: list[Finding]) -> None:
        self.path = path
        self.link = link
        self.problems = problems

    def error(self, cause: str, el: etree._Element,
              rule: Rule = Rule.VECTOR_UNPARSEABLE) -> UrdfError:
        return UrdfError(cause, file=self.path, line=el.sourceline, link=self.link,
                         rule=rule)

    def note(self, exc: UrdfError, element: str | None, rule: Rule | None = None) -> None:
        """``exc`` as a finding on ``element`` (``rule``: instead of the error's own)."""
        self.problems.append(Finding(rule or exc.rule, self.link, exc.cause, exc.line,
                                     element))

    def raw(self, el: etree._Element, attr: str, n: int, default: str) -> tuple[float, ...]:
        """``n`` numbers exactly as written, for the ``<inertial>``: NaN, infinities and
        any magnitude are kept for the judgement; text that is not ``n`` numbers is read
        as NaN with a finding (``vector-unparseable``), so that the value is judged, not
        lost."""
        text = el.get(attr, default)
        parts = [p for p in _COMMAS.split(text.strip()) if p]
        values = [_float_or_none(p) for p in parts]
        if len(parts) != n or any(v is None for v in values):
            shown = text if len(text) <= 80 else text[:77] + "..."
            self.problems.append(Finding(
                Rule.VECTOR_UNPARSEABLE, self.link, f"<{el.tag} {attr}=\"{shown}\"> needs "
                f"{n} number{'s' if n > 1 else ''}: read as not a number", el.sourceline,
                "inertial"))
            return (math.nan,) * n
        if "," in text:
            self.problems.append(Finding(
                Rule.VECTOR_COMMAS, self.link, f"<{el.tag} {attr}=\"{text}\"> separates "
                "numbers with commas (urdfdom refuses it): read as spaces", el.sourceline,
                "inertial"))
        return tuple(v for v in values if v is not None)

    def floats(self, el: etree._Element, attr: str, n: int, default: str | None = None,
               ) -> tuple[float, ...]:
        text = el.get(attr, default)
        if text is None:
            raise self.error(f"<{el.tag}> is missing attribute '{attr}'", el,
                             Rule.MISSING_ATTRIBUTE)
        known = _VALID_NUMBERS.get((text, n))
        if known is not None:
            return known
        shown = text if len(text) <= 80 else text[:77] + "..."
        if "$(" in text:
            raise self.error(f"<{el.tag} {attr}=\"{shown}\"> holds an unexpanded "
                             "substitution $(...): run xacro first", el,
                             Rule.UNEXPANDED_SUBSTITUTION)
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
            self.problems.append(Finding(
                Rule.VECTOR_COMMAS, self.link, f"<{el.tag} {attr}=\"{shown}\"> separates "
                "numbers with commas (urdfdom refuses it): read as spaces", el.sourceline))
            return values
        if len(_VALID_NUMBERS) >= _MAX_VALID_NUMBERS:
            _VALID_NUMBERS.clear()
        _VALID_NUMBERS[text, n] = values
        return values

    def positive(self, el: etree._Element, attr: str, n: int = 1) -> tuple[float, ...]:
        values = self.floats(el, attr, n)
        if not all(v > 0 for v in values):
            raise self.error(f"<{el.tag} {attr}=\"{el.get(attr)}\"> must be positive", el,
                             Rule.ZERO_SIZE_PRIMITIVE)
        return values


def _float_or_none(text: str) -> float | None:
    try:
        return float(text)
    except ValueError:
        return None


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
                        Rule.UNSUPPORTED_GEOMETRY)
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
                            Rule.ZERO_SIZE_PRIMITIVE)
        return Capsule(radius, length)
    if el.tag == "mesh":
        filename = el.get("filename")
        if not filename:
            raise ctx.error("<mesh> is missing attribute 'filename'", el,
                            Rule.MISSING_ATTRIBUTE)
        if "$(" in filename:
            raise ctx.error(f"<mesh filename=\"{filename}\"> holds an unexpanded "
                            "substitution $(...): run xacro first", el,
                            Rule.UNEXPANDED_SUBSTITUTION)
        scale = ctx.floats(el, "scale", 3, "1 1 1")
        if any(s == 0 for s in scale):
            raise ctx.error(f"<mesh scale=\"{el.get('scale')}\"> has a zero component", el,
                            Rule.ZERO_SIZE_PRIMITIVE)
        return Mesh(filename, scale)  # type: ignore[arg-type]
    raise ctx.error(f"unsupported geometry <{el.tag}>", el, Rule.UNSUPPORTED_GEOMETRY)


def _geometry_refs(link_el: etree._Element, role: str, ctx: _Ctx) -> tuple[GeometryRef, ...]:
    """The link's readable elements of `role`; each unreadable one is dropped with a
    problem (its index stays its position in the file, so labels match the document)."""
    refs = []
    for index, el in enumerate(_children(link_el, role)):
        name = el.get("name")
        try:
            geo = _children(el, "geometry")
            if not geo:
                raise ctx.error(f"<{role}> has no <geometry>", el, Rule.UNSUPPORTED_GEOMETRY)
            refs.append(GeometryRef(role, index, name, _origin(el, ctx),
                                    _shape(geo[0], ctx), el.sourceline))
        except UrdfError as exc:
            label = f"{role}[{index}]" + (f" '{name}'" if name else "")
            ctx.note(exc, label)
    return tuple(refs)


def _inertial(link_el: etree._Element, ctx: _Ctx) -> Inertial | None:
    """The first ``<inertial>`` exactly as written (:meth:`_Ctx.raw`); a missing ``<mass>``
    is a NaN mass with a finding (the tensor and CoM are still read)."""
    found = _children(link_el, "inertial")
    if not found:
        return None
    el = found[0]
    mass_el = _children(el, "mass")
    inertia_el = _children(el, "inertia")
    if mass_el:
        mass = ctx.raw(mass_el[0], "value", 1, "nan")[0]
    else:
        ctx.problems.append(Finding(Rule.MISSING_ATTRIBUTE, ctx.link, "<inertial> has no "
                                    "<mass>: the mass is unknown", el.sourceline, "inertial"))
        mass = math.nan
    if inertia_el:
        values = [ctx.raw(inertia_el[0], k, 1, "0")[0]
                  for k in ("ixx", "ixy", "ixz", "iyy", "iyz", "izz")]
    else:
        values = [0.0] * 6
    origin_el = _children(el, "origin")
    if origin_el:
        origin = Origin(ctx.raw(origin_el[0], "xyz", 3, "0 0 0"),  # type: ignore[arg-type]
                        ctx.raw(origin_el[0], "rpy", 3, "0 0 0"))  # type: ignore[arg-type]
    else:
        origin = Origin()
    ixx, ixy, ixz, iyy, iyz, izz = values
    return Inertial(origin, mass, ixx, ixy, ixz, iyy, iyz, izz, line=el.sourceline)


def _link(el: etree._Element, path: Path, problems: list[Finding]) -> Link:
    name = el.get("name")
    if not name:
        raise UrdfError("<link> without a name", file=path, line=el.sourceline)
    ctx = _Ctx(path, name, problems)
    inertial = _inertial(el, ctx)
    return Link(
        name=name,
        collisions=_geometry_refs(el, "collision", ctx),
        visuals=_geometry_refs(el, "visual", ctx),
        inertial=inertial,
        line=el.sourceline,
    )


def _joint(el: etree._Element, path: Path, problems: list[Finding]) -> Joint:
    ctx = _Ctx(path, None, problems)
    parent = _children(el, "parent")
    child = _children(el, "child")
    name = el.get("name", "")
    try:
        origin = _origin(el, ctx)
    except UrdfError as exc:  # not needed for inertials: a note, never a refusal
        ctx.note(exc, f"joint '{name}' origin", Rule.VALUE_UNREADABLE)
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
