"""Break a link's geometry into parts: homogeneous pieces, each in its own frame.

This is where a part's tensor is computed: primitives by closed form
(:mod:`urdfinertia.inertia.primitives`), meshes by exact polyhedral integrals of each body
(:mod:`urdfinertia.mesh.solids`). Every part is computed at unit density (1 kg/m^3) in its own
frame, with its pose in the link frame; :mod:`urdfinertia.link.assemble` gives it mass and
moves it to the link's centre of mass.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, NamedTuple, Protocol

import numpy as np

from urdfinertia.descriptions.model import (
    Box,
    Capsule,
    Cone,
    Cylinder,
    Ellipsoid,
    GeometryRef,
    Mesh,
    Shape,
    Sphere,
)
from urdfinertia.errors import MeshError, UrdfInertiaError
from urdfinertia.inertia import primitives
from urdfinertia.inertia.massprops import MassProperties

if TYPE_CHECKING:
    from urdfinertia.mesh.solids import MeshSolids


class MeshSource(Protocol):
    """How parts reach meshes: a URI to a file, a file to its solids (each once per run).

    :class:`urdfinertia.cache.library.MeshLibrary` is the implementation; the parts
    step needs nothing more of it (no cache, no batch state).
    """

    def resolve(self, uri: str, urdf_dir: Path) -> Path: ...

    def solids(self, path: Path) -> MeshSolids: ...


@dataclass(frozen=True, eq=False)
class Part:
    """A homogeneous piece of a link.

    Attributes
    ----------
    name : str
        Human label, e.g. ``"collision[0] body 2"``.
    element : str
        The element (group of parts) it belongs to.
    unit : MassProperties
        Mass properties at 1 kg/m^3 in the part's own frame (so ``unit.mass`` is the
        volume in m^3).
    pose : (4, 4) float
        The part frame in the link frame.
    method : str
        How the tensor was obtained ("closed form box", "exact (closed mesh)", ...).
    density, mass : float or None
        kg/m^3 or kg when the user knows them; otherwise the link's policy decides.
    cavity : bool
        Removed material: contributes negative mass.
    provenance : str
        How a mesh body's surface was closed ("closed as given", "welded", "stitched",
        holes capped ...); "closed form" for primitives.
    uncertainty : float or None
        Stated relative error of the volume (0 for exact methods).
    relative : bool
        ``density``/``mass`` are weights: a pinned link mass scales them (see assemble).
    """

    name: str
    element: str
    unit: MassProperties
    pose: np.ndarray
    method: str
    density: float | None = None
    mass: float | None = None
    cavity: bool = False
    notes: tuple[str, ...] = field(default=())
    provenance: str = ""
    uncertainty: float | None = None
    relative: bool = False

    @property
    def volume(self) -> float:
        return self.unit.mass

    def in_link(self, mass: float) -> MassProperties:
        """This part with ``mass`` kg (negative for a cavity) expressed in the link frame."""
        return self.unit.with_mass(mass).transformed(self.pose)


class BodySolid(NamedTuple):
    """One body of a shape at unit density, and how it was obtained (see :class:`Part`)."""

    unit: MassProperties
    method: str
    notes: tuple[str, ...] = ()
    provenance: str = "closed form"
    uncertainty: float | None = 0.0


def shape_solids(shape: Shape, meshes: MeshSource, urdf_dir: Path) -> list[BodySolid]:
    """Unit-density mass properties of a shape in its geometry frame, one per body."""
    if isinstance(shape, Box):
        return [BodySolid(primitives.box(shape.size, 1.0), "closed form box")]
    if isinstance(shape, Cylinder):
        return [BodySolid(primitives.cylinder(shape.radius, shape.length, 1.0),
                          "closed form cylinder")]
    if isinstance(shape, Sphere):
        return [BodySolid(primitives.sphere(shape.radius, 1.0), "closed form sphere")]
    if isinstance(shape, Capsule):
        return [BodySolid(primitives.capsule(shape.radius, shape.length, 1.0),
                          "closed form capsule")]
    if isinstance(shape, Cone):
        return [BodySolid(primitives.cone(shape.radius, shape.length, 1.0), "closed form cone")]
    if isinstance(shape, Ellipsoid):
        return [BodySolid(primitives.ellipsoid(shape.radii, 1.0), "closed form ellipsoid")]
    if isinstance(shape, Mesh):
        path = meshes.resolve(shape.filename, urdf_dir)
        found = meshes.solids(path).scaled(shape.scale)
        out = []
        mirrored = math.prod(shape.scale) < 0  # the sign of np.prod's product, exactly
        for solid in found.solids:
            notes = solid.notes + found.notes + (("mirrored by scale",) if mirrored else ())
            try:
                unit = solid.mass_properties(1.0)
            except ValueError as exc:
                raise MeshError(f"mesh {shape.filename!r} gives no valid solid ({solid.method}): "
                                f"{exc}", code="no-volume") from None
            out.append(BodySolid(unit, solid.method, notes, solid.provenance,
                                 solid.error_estimate))
        return out
    raise TypeError(f"unknown shape {shape!r}")


def geometry_parts(ref: GeometryRef, meshes: MeshSource, urdf_dir: Path) -> list[Part]:
    """The parts of one ``<collision>``/``<visual>``: one per primitive or mesh body."""
    try:
        bodies = shape_solids(ref.shape, meshes, urdf_dir)
    except UrdfInertiaError as exc:
        raise exc.with_context(line=ref.line) from None
    pose = ref.origin.matrix()
    parts = []
    for i, body in enumerate(bodies):
        name = ref.label if len(bodies) == 1 else f"{ref.label} body {i + 1}"
        parts.append(Part(name=name, element=ref.label, unit=body.unit, pose=pose,
                          method=body.method, density=ref.density,
                          mass=_share(ref.mass, body.unit, bodies), notes=body.notes,
                          provenance=body.provenance, uncertainty=body.uncertainty,
                          relative=ref.relative))
    return parts


def _share(mass: float | None, unit: MassProperties, bodies: list[BodySolid]) -> float | None:
    """An element's stated mass split over its bodies by volume (None: not stated)."""
    if mass is None:
        return None
    total = sum(b.unit.mass for b in bodies)
    return mass * unit.mass / total if total > 0 else None
