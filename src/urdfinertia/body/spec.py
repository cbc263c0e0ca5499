"""Decomposition specs: the paper's elements and parts, written down in TOML.

A link is divided into elements, each with its own frame in the link frame (xyz + rpy:
the paper's gamma, alpha, delta, eqs. 14-17), and each element into parts with their own
frame in the element frame (section 2). A part is a primitive, a mesh file or a reference
to one of the link's `<collision>`/`<visual>` elements, and carries a known mass, a
density or a material name, or nothing (it then shares the link's pinned or default mass
by volume). See `docs/spec.md` for the format.

Errors name the spec file and the TOML key path, e.g.
`links.link1.elements.k.parts.body.density`.
"""

from __future__ import annotations

import difflib
import math
import re
import tomllib
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from urdfinertia.body.mass import MassShareError, MassSource, link_mass_source, share_mass
from urdfinertia.body.materials import MATERIALS, material_density, material_key
from urdfinertia.body.parts import (
    BodySolid,
    MeshSource,
    Part,
    Walls,
    shape_solids,
    shell_solids,
)
from urdfinertia.descriptions.model import (
    Box,
    Capsule,
    Cylinder,
    GeometryRef,
    Link,
    Mesh,
    Origin,
    Robot,
    Shape,
    Sphere,
)
from urdfinertia.errors import MeshError, SpecError
from urdfinertia.inertia.massprops import MassProperties

if TYPE_CHECKING:
    from urdfinertia.body.options import FixOptions

PRIMITIVES = ("box", "cylinder", "sphere", "capsule", "mesh")
REFERENCES = ("collision", "visual")
POINT = "point"  # a point mass: a motor or battery whose size does not matter
_POINT_KEYS = ("xyz", "mass")
_TOP_KEYS = ("links", "materials", "total_mass", "subtree")
_SUBTREE_KEYS = ("mass",)
_LINK_KEYS = ("mass", "elements")
_ELEMENT_KEYS = ("xyz", "rpy", "density", "material", "parts")
SHELL, INFILL = "shell", "infill"  # a 3-D printed part: walls and a partly filled interior
_SHELL_KEYS = ("thickness",)
_INFILL_KEYS = ("fraction", "density", "material")
_PART_KEYS = (*PRIMITIVES, *REFERENCES, POINT, "xyz", "rpy", "density", "material", "mass",
              "cavity", SHELL, INFILL)
_SHAPE_KEYS = {"box": ("size",), "cylinder": ("radius", "length"), "sphere": ("radius",),
               "capsule": ("radius", "length"), "mesh": ("filename", "scale")}


@dataclass(frozen=True)
class GeometrySelector:
    """A part that is one of the link's own ``<collision>``/``<visual>`` elements."""

    role: str  # "collision" | "visual"
    which: int | str  # index among the link's elements of that role, or name

    def find(self, link: Link, key: str, file: Path) -> GeometryRef:
        refs = link.collisions if self.role == "collision" else link.visuals
        if isinstance(self.which, int):
            if not 0 <= self.which < len(refs):
                raise SpecError(f"{key}: link '{link.name}' has {len(refs)} <{self.role}> "
                                f"element(s), index {self.which} is out of range", file=file)
            return refs[self.which]
        found = [r for r in refs if r.name == self.which]
        if len(found) != 1:
            names = [r.name for r in refs if r.name]
            what = "no" if not found else f"{len(found)}"
            raise SpecError(f"{key}: link '{link.name}' has {what} <{self.role}> named "
                            f"{self.which!r} (named ones: {names})", file=file)
        return found[0]


@dataclass(frozen=True)
class PointMass:
    """A part that is a point mass (``point = { xyz = [...], mass = ... }``): its position
    is the part's origin in the element frame, its mass the part's."""


@dataclass(frozen=True, eq=False)
class PointPart(Part):
    """A point mass in a link: no volume, no tensor of its own about its CoM; in the link
    frame it contributes the parallel-axis term ``m (|r|^2 E - r r^T)`` (eq. 43)."""

    def in_link(self, mass: float) -> MassProperties:
        return MassProperties(mass, self.pose[:3, 3], np.zeros((3, 3)))


@dataclass(frozen=True)
class PartSpec:
    """One part as written in the spec; ``origin`` is its frame in the element frame."""

    name: str
    key: str
    source: Shape | GeometrySelector | PointMass
    origin: Origin
    density: float | None  # kg/m^3, from ``density`` or ``material``
    mass: float | None  # kg
    cavity: bool
    walls: Walls | None = None  # ``shell`` and ``infill``: the part is printed hollow

    @property
    def known(self) -> bool:
        return self.density is not None or self.mass is not None


@dataclass(frozen=True)
class ElementSpec:
    """An element: a frame in the link frame and the parts placed in it."""

    name: str
    key: str
    origin: Origin
    parts: tuple[PartSpec, ...]


@dataclass(frozen=True)
class LinkSpec:
    """A link's decomposition; ``mass`` pins the link's total (kg) when given."""

    name: str
    key: str
    mass: float | None
    elements: tuple[ElementSpec, ...]
    path: Path  # the spec file: meshes resolve relative to its folder

    def uses_default_mass(self) -> bool:
        """True when nothing in the spec says how heavy the link is."""
        return self.mass is None and not any(p.known for e in self.elements for p in e.parts)

    def check_references(self, link: Link) -> None:
        for element in self.elements:
            for p in element.parts:
                if isinstance(p.source, GeometrySelector):
                    p.source.find(link, f"{p.key}.{p.source.role}", self.path)

    def parts(self, link: Link, meshes: MeshSource, urdf_dir: Path,
              ) -> tuple[list[Part], float | None]:
        """The link's parts (unit density, own frame, pose in the link frame) and pinned mass.

        A part's pose is ``element pose @ part pose`` (eq. 23 applied twice); a referenced
        ``<collision>``/``<visual>`` keeps the pose its ``<origin>`` gives it in the link.
        """
        out: list[Part] = []
        for element in self.elements:
            element_pose = element.origin.matrix()
            for p in element.parts:
                out.extend(self._part(p, element, element_pose, link, meshes, urdf_dir))
        self._check_masses(out)
        return out, self.mass

    def _part(self, p: PartSpec, element: ElementSpec, element_pose: np.ndarray, link: Link,
              meshes: MeshSource, urdf_dir: Path) -> list[Part]:
        label = f"{element.name}/{p.name}"
        if isinstance(p.source, PointMass):
            return [PointPart(name=label, element=element.name, unit=MassProperties.zero(),
                              pose=element_pose @ p.origin.matrix(), method="point mass",
                              mass=p.mass, provenance="point mass")]
        if isinstance(p.source, GeometrySelector):
            ref = p.source.find(link, f"{p.key}.{p.source.role}", self.path)
            bodies = _solids(ref.shape, p.walls, meshes, urdf_dir)
            pose, where = ref.origin.matrix(), f" of {ref.label}"
        else:
            try:
                bodies = _solids(p.source, p.walls, meshes, self.path.parent)
            except MeshError as exc:
                if exc.file is not None:
                    raise
                raise SpecError(f"{p.key}.mesh: {exc.cause}", file=self.path) from None
            pose, where = element_pose @ p.origin.matrix(), ""
        volume = sum(body.unit.mass for body in bodies)
        if not volume > 0:
            raise SpecError(f"{p.key}: part has no volume", file=self.path)
        parts = []
        for i, body in enumerate(bodies):
            name = label if len(bodies) == 1 else f"{label} body {i + 1}"
            mass = None if p.mass is None else p.mass * body.unit.mass / volume
            parts.append(Part(name=name, element=element.name, unit=body.unit, pose=pose,
                              method=body.method + where, density=p.density, mass=mass,
                              cavity=p.cavity, notes=body.notes,
                              provenance=body.provenance, uncertainty=body.uncertainty))
        return parts

    def mass_source(self, link: Link, options: FixOptions, *, trust_mass: bool = True,
                    ) -> MassSource:
        """The link's mass policy (:func:`link_mass_source`) with what this spec says."""
        return link_mass_source(link, options, self.mass, not self.uses_default_mass(),
                                trust_mass=trust_mass)

    def mass_key(self, source: MassSource) -> str:
        """The TOML key a mass problem is reported at."""
        return f"{self.key}.mass" if source.kind == "pinned" else self.key

    def _check_masses(self, parts: list[Part]) -> None:
        """Known masses against the pinned total, named by spec key (the one sharing rule)."""
        if self.mass is None:
            return
        source = MassSource("pinned", self.mass)
        try:
            share_mass(parts, source)
        except MassShareError as exc:
            raise SpecError(f"{self.mass_key(source)}: {exc.cause}", file=self.path) from None


@dataclass(frozen=True)
class Spec:
    """A whole spec file: link name -> `LinkSpec`.

    Attributes
    ----------
    path : Path
        The spec file.
    links : tuple of LinkSpec
        One entry per link the spec names.
    total_mass : float or None
        `total_mass`: what the whole robot weighs, kg (`urdfinertia.plan.total_mass`).
    subtree_masses : mapping of str to float
        `[subtree.NAME] mass`: link NAME and the links below it weigh this much, kg.
    """

    path: Path
    links: tuple[LinkSpec, ...]
    total_mass: float | None = None
    subtree_masses: Mapping[str, float] = field(default_factory=dict)

    @property
    def has_targets(self) -> bool:
        """The spec says what the robot or a subtree of it weighs."""
        return self.total_mass is not None or bool(self.subtree_masses)

    def link(self, name: str) -> LinkSpec | None:
        for link in self.links:
            if link.name == name:
                return link
        return None

    def check_links(self, robot: Robot) -> None:
        """Raise [`SpecError`][urdfinertia.errors.SpecError] for spec links the URDF lacks or bad
        references."""
        names = [link.name for link in robot.links]
        for ls in self.links:
            if ls.name not in names:
                close = difflib.get_close_matches(ls.name, names, n=3)
                hint = f" (did you mean {', '.join(close)}?)" if close else ""
                raise SpecError(f"{ls.key}: the URDF '{robot.name}' has no link "
                                f"'{ls.name}'{hint}", file=self.path)
            ls.check_references(robot.link(ls.name))
        for name in self.subtree_masses:
            if name not in names:
                close = difflib.get_close_matches(name, names, n=3)
                hint = f" (did you mean {', '.join(close)}?)" if close else ""
                raise SpecError(f"subtree.{_q(name)}: the URDF '{robot.name}' has no link "
                                f"'{name}'{hint}", file=self.path)


def _solids(shape: Shape, walls: Walls | None, meshes: MeshSource, base_dir: Path,
            ) -> list[BodySolid]:
    return (shape_solids(shape, meshes, base_dir) if walls is None
            else shell_solids(shape, walls, meshes, base_dir))


# --- reading --------------------------------------------------------------------------

def load_spec(path: str | Path) -> Spec:
    """Read and validate a spec file (TOML)."""
    path = Path(path)
    try:
        text = path.read_bytes().decode("utf-8")
    except OSError as exc:
        raise SpecError(f"cannot read spec: {exc.strerror or exc}", file=path) from None
    except UnicodeDecodeError:
        raise SpecError("spec is not UTF-8 text", file=path) from None
    return parse_spec(text, path)


def parse_spec(text: str, path: Path) -> Spec:
    """Validate spec ``text``; ``path`` names it in errors and anchors relative meshes."""
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        found = re.search(r"at line (\d+)", str(exc))  # Python < 3.14 has no exc.lineno
        line = getattr(exc, "lineno", None) or (int(found.group(1)) if found else None)
        raise SpecError(f"invalid TOML: {exc}", file=path, line=line) from None
    return _Reader(path).spec(data)


class _Reader:
    def __init__(self, path: Path) -> None:
        self.path = path
        self.materials: dict[str, float] = {}

    def fail(self, key: str, problem: str) -> SpecError:
        return SpecError(f"{key}: {problem}", file=self.path)

    def table(self, value: Any, key: str, allowed: tuple[str, ...] | None) -> dict[str, Any]:
        if not isinstance(value, dict):
            raise self.fail(key, f"expected a table, got {type(value).__name__}")
        if allowed is not None:
            for k in value:
                if k not in allowed:
                    close = difflib.get_close_matches(k, allowed, n=1)
                    hint = f"did you mean '{close[0]}'? " if close else ""
                    raise self.fail(f"{key}.{k}" if key else k,
                                    f"unknown key ({hint}allowed: {', '.join(allowed)})")
        return value

    def number(self, value: Any, key: str, unit: str, *, zero_ok: bool = False) -> float:
        ok = isinstance(value, (int, float)) and not isinstance(value, bool)
        if ok and math.isfinite(value) and (value > 0 or (zero_ok and value == 0)):
            return float(value)
        need = "a non-negative" if zero_ok else "a positive"
        raise self.fail(key, f"must be {need} number ({unit}), got {value!r}")

    def vector(self, value: Any, key: str, *, positive: bool = False) -> tuple[float, ...]:
        if not (isinstance(value, list) and len(value) == 3 and all(
                isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v)
                for v in value)):
            raise self.fail(key, f"must be a list of 3 numbers, got {value!r}")
        if positive and not all(v > 0 for v in value):
            raise self.fail(key, f"must be 3 positive numbers (m), got {value!r}")
        return tuple(float(v) for v in value)

    def origin(self, table: dict[str, Any], key: str) -> Origin:
        xyz = self.vector(table.get("xyz", [0, 0, 0]), f"{key}.xyz")
        rpy = self.vector(table.get("rpy", [0, 0, 0]), f"{key}.rpy")
        return Origin(xyz, rpy)  # type: ignore[arg-type]

    def density(self, table: dict[str, Any], key: str) -> float | None:
        if "density" in table and "material" in table:
            raise self.fail(f"{key}.material", "give either density or material, not both")
        if "density" in table:
            return self.number(table["density"], f"{key}.density", "kg/m^3")
        if "material" in table:
            name = table["material"]
            found = material_density(name, self.materials) if isinstance(name, str) else None
            if found is None:
                known = sorted({*MATERIALS, *self.materials})
                raise self.fail(f"{key}.material", f"unknown material {name!r} (known: "
                                f"{', '.join(known)}; add it under [materials])")
            return found
        return None

    def spec(self, data: dict[str, Any]) -> Spec:
        self.table(data, "", _TOP_KEYS)
        for name, value in self.table(data.get("materials", {}), "materials", None).items():
            self.materials[material_key(name)] = self.number(value, f"materials.{name}",
                                                             "kg/m^3")
        links = self.table(data.get("links", {}), "links", None)
        total = self.number(data["total_mass"], "total_mass", "kg") \
            if "total_mass" in data else None
        subtrees = {name: self.subtree(value, f"subtree.{_q(name)}") for name, value
                    in self.table(data.get("subtree", {}), "subtree", None).items()}
        if not links and total is None and not subtrees:
            raise self.fail("links", "the spec names no links and no target mass "
                            "(total_mass, [subtree.NAME] mass)")
        return Spec(self.path, tuple(self.link(n, v, f"links.{_q(n)}")
                                     for n, v in links.items()), total, subtrees)

    def subtree(self, value: Any, key: str) -> float:
        table = self.table(value, key, _SUBTREE_KEYS)
        if "mass" not in table:
            raise self.fail(f"{key}.mass", "missing (a subtree target needs its mass, kg)")
        return self.number(table["mass"], f"{key}.mass", "kg")

    def link(self, name: str, value: Any, key: str) -> LinkSpec:
        table = self.table(value, key, _LINK_KEYS)
        mass = self.number(table["mass"], f"{key}.mass", "kg") if "mass" in table else None
        elements = self.table(table.get("elements", {}), f"{key}.elements", None)
        if not elements:
            raise self.fail(f"{key}.elements", "a link in the spec needs at least one element")
        return LinkSpec(name, key, mass, tuple(
            self.element(n, v, f"{key}.elements.{_q(n)}") for n, v in elements.items()),
            self.path)

    def element(self, name: str, value: Any, key: str) -> ElementSpec:
        table = self.table(value, key, _ELEMENT_KEYS)
        default_density = self.density(table, key)
        parts = self.table(table.get("parts", {}), f"{key}.parts", None)
        if not parts:
            raise self.fail(f"{key}.parts", "an element needs at least one part")
        return ElementSpec(name, key, self.origin(table, key), tuple(
            self.part(n, v, f"{key}.parts.{_q(n)}", default_density) for n, v in parts.items()))

    def part(self, name: str, value: Any, key: str, default_density: float | None) -> PartSpec:
        table = self.table(value, key, _PART_KEYS)
        if POINT in table:
            return self.point(name, table, key)
        given = [k for k in (*PRIMITIVES, *REFERENCES) if k in table]
        if len(given) != 1:
            if not given and "mass" in table:
                raise self.fail(f"{key}.mass", "a known mass needs a volume: give the part a "
                                f"shape ({', '.join(PRIMITIVES + REFERENCES)}), or make it "
                                "a point = { xyz = [...], mass = KG }")
            raise self.fail(key, f"give exactly one of {', '.join(PRIMITIVES + REFERENCES)}"
                            f" or {POINT} (got {', '.join(given) or 'none'})")
        kind = given[0]
        source = self.source(kind, table[kind], f"{key}.{kind}")
        if kind in REFERENCES and ("xyz" in table or "rpy" in table):
            raise self.fail(f"{key}.{'xyz' if 'xyz' in table else 'rpy'}", "a referenced "
                            f"<{kind}> is placed by its own <origin> in the URDF")
        density = self.density(table, key)
        mass = self.number(table["mass"], f"{key}.mass", "kg") if "mass" in table else None
        if mass is not None and density is not None:
            raise self.fail(f"{key}.mass", "give a mass or a density/material, not both")
        if mass is None and density is None:
            density = default_density
        cavity = table.get("cavity", False)
        if not isinstance(cavity, bool):
            raise self.fail(f"{key}.cavity", f"must be true or false, got {cavity!r}")
        walls = self.walls(table, key, density, mass is not None, cavity)
        return PartSpec(name, key, source, self.origin(table, key), density, mass, cavity,
                        walls)

    def walls(self, table: dict[str, Any], key: str, density: float | None, has_mass: bool,
              cavity: bool) -> Walls | None:
        """``shell = { thickness = T }`` and ``infill = F`` or ``{ fraction, density |
        material }``: the interior's density as a multiple of the wall's."""
        if SHELL not in table:
            if INFILL in table:
                raise self.fail(f"{key}.{INFILL}", "infill fills the inside of a shell: give "
                                "the part a shell = { thickness = M } too (a wall thickness "
                                "left to a guess would decide most of the mass)")
            return None
        if cavity:
            raise self.fail(f"{key}.{SHELL}", "a cavity is removed material: it has no wall")
        shell = self.table(table[SHELL], f"{key}.{SHELL}", _SHELL_KEYS)
        if "thickness" not in shell:
            raise self.fail(f"{key}.{SHELL}.thickness", "missing (the wall thickness, m)")
        thickness = self.number(shell["thickness"], f"{key}.{SHELL}.thickness", "m")
        value = table.get(INFILL, 0.0)
        if not isinstance(value, dict):
            return Walls(thickness, self.fraction(value, f"{key}.{INFILL}"))
        infill = self.table(value, f"{key}.{INFILL}", _INFILL_KEYS)
        stated = self.density(infill, f"{key}.{INFILL}")
        if stated is None:
            if "fraction" not in infill:
                raise self.fail(f"{key}.{INFILL}", "give fraction (0..1), a density or a "
                                "material")
            return Walls(thickness, self.fraction(infill["fraction"],
                                                  f"{key}.{INFILL}.fraction"))
        # a fraction of its own material: needs the wall's density to weigh it against
        fraction = self.fraction(infill.get("fraction", 1.0), f"{key}.{INFILL}.fraction")
        if density is None:
            why = "the part's mass is" if has_mass else "no density is"
            raise self.fail(f"{key}.{INFILL}.{'density' if 'density' in infill else 'material'}",
                            f"{why} given for the wall, so the infill's own density cannot be "
                            "weighed against it: give the part a density or material, or the "
                            "infill as a fraction of the wall's")
        return Walls(thickness, fraction * stated / density)

    def fraction(self, value: Any, key: str) -> float:
        ok = isinstance(value, (int, float)) and not isinstance(value, bool)
        if ok and math.isfinite(value) and 0 <= value <= 1:
            return float(value)
        raise self.fail(key, f"must be a fraction from 0 (hollow) to 1 (solid), got {value!r}")

    def point(self, name: str, table: dict[str, Any], key: str) -> PartSpec:
        others = [k for k in table if k != POINT]
        if others:
            raise self.fail(f"{key}.{others[0]}", "a point part is given by its point table "
                            "alone: point = { xyz = [x, y, z], mass = KG }")
        point = self.table(table[POINT], f"{key}.{POINT}", _POINT_KEYS)
        if "mass" not in point:
            raise self.fail(f"{key}.{POINT}.mass", "missing (a point needs its mass, kg)")
        mass = self.number(point["mass"], f"{key}.{POINT}.mass", "kg")
        xyz = self.vector(point.get("xyz", [0, 0, 0]), f"{key}.{POINT}.xyz")
        return PartSpec(name, key, PointMass(), Origin(xyz, (0.0, 0.0, 0.0)),  # type: ignore
                        None, mass, False)

    def source(self, kind: str, value: Any, key: str) -> Shape | GeometrySelector:
        if kind in REFERENCES:
            ok = isinstance(value, str) or (isinstance(value, int)
                                            and not isinstance(value, bool) and value >= 0)
            if not ok:
                raise self.fail(key, f"must be an index (0, 1, ...) or a name, got {value!r}")
            return GeometrySelector(kind, value)
        t = self.table(value, key, _SHAPE_KEYS[kind])
        for k in _SHAPE_KEYS[kind]:
            if k not in t and k != "scale":
                raise self.fail(f"{key}.{k}", f"missing (a {kind} needs "
                                f"{', '.join(_SHAPE_KEYS[kind])})")
        if kind == "box":
            return Box(self.vector(t["size"], f"{key}.size", positive=True))  # type: ignore
        if kind == "sphere":
            return Sphere(self.number(t["radius"], f"{key}.radius", "m"))
        if kind in ("cylinder", "capsule"):
            r = self.number(t["radius"], f"{key}.radius", "m")
            length = self.number(t["length"], f"{key}.length", "m", zero_ok=kind == "capsule")
            return Cylinder(r, length) if kind == "cylinder" else Capsule(r, length)
        return self.mesh(t, key)

    def mesh(self, t: dict[str, Any], key: str) -> Mesh:
        filename = t["filename"]
        if not isinstance(filename, str) or not filename:
            raise self.fail(f"{key}.filename", f"must be a file name, got {filename!r}")
        scale: Any = t.get("scale", 1.0)
        if isinstance(scale, (int, float)) and not isinstance(scale, bool):
            scale = [scale] * 3
        scale3 = self.vector(scale, f"{key}.scale")
        if any(s == 0 for s in scale3):
            raise self.fail(f"{key}.scale", "must not be zero")
        if "://" not in filename:
            file = Path(filename) if Path(filename).is_absolute() else self.path.parent / filename
            if not file.is_file():
                raise self.fail(f"{key}.filename", f"mesh file not found: {filename!r} "
                                f"(looked at {file})")
        return Mesh(filename, scale3)  # type: ignore[arg-type]


def _q(name: str) -> str:
    """A TOML key as it would be written in a dotted path."""
    bare = name and all(c.isalnum() or c in "-_" for c in name)
    return name if bare else f'"{name}"'

