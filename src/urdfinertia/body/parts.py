"""Break a link's geometry into parts: homogeneous pieces, each in its own frame.

This is where a part's tensor is computed: primitives by closed form
(:mod:`urdfinertia.inertia.primitives`), meshes by exact polyhedral integrals of each body
(:mod:`urdfinertia.mesh.solids`), printed shells with infill by
:mod:`urdfinertia.inertia.shell`. Every part is computed at unit density (1 kg/m^3) in its
own frame, with its pose in the link frame; :mod:`urdfinertia.body.assemble` gives it mass
and moves it to the link's centre of mass. A shell's "unit" body is its wall plus its
interior weighted by the infill, so its ``volume`` is that of solid wall material.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, NamedTuple, Protocol

import numpy as np

from urdfinertia.body.shell_voxels import voxel_shell
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
from urdfinertia.inertia import primitives, shell
from urdfinertia.inertia.massprops import MassProperties
from urdfinertia.inertia.polyhedron import mass_properties_from_integrals, solid_integrals
from urdfinertia.mesh.limits import DEFAULT_MAX_FACES
from urdfinertia.mesh.read.load import TriangleMesh, load_mesh
from urdfinertia.mesh.repair.pipeline import RepairedMesh, repair_mesh
from urdfinertia.rules import Rule

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
                                f"{exc}", rule=Rule.MESH_NO_VOLUME) from None
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


@dataclass(frozen=True)
class Walls:
    """A part printed as a shell: ``thickness`` m of wall around an interior filled at
    ``infill`` times the wall's density (0: hollow)."""

    thickness: float
    infill: float = 0.0

    def label(self) -> str:
        if self.infill == 0:
            return f"{self.thickness * 1e3:.4g} mm wall, hollow"
        return (f"{self.thickness * 1e3:.4g} mm wall, interior at {self.infill:.4g} x the "
                "wall's density")


def shell_solids(shape: Shape, walls: Walls, meshes: MeshSource, base_dir: Path,
                 ) -> list[BodySolid]:
    """Like :func:`shape_solids`, for the shape printed as ``walls``: each body's wall
    plus its interior weighted by ``walls.infill``, at unit wall density.

    A mesh body whose exact offset is refused (thinner than two walls somewhere) is
    estimated on voxels (:mod:`urdfinertia.body.shell_voxels`). A body with no interior
    at all (a primitive thinner than two walls, an ellipsoid more curved than the wall
    is thick, a mesh with nothing ``t`` deep) is kept solid, and its provenance says so:
    a slicer fills such a part solid too.
    """
    if isinstance(shape, Mesh):
        return _mesh_shells(shape, walls, meshes, base_dir)
    solid = shape_solids(shape, meshes, base_dir)[0]
    notes = solid.notes
    try:
        found = _primitive_shell(shape, walls.thickness)
    except shell.ShellError as exc:
        if not isinstance(shape, Ellipsoid):
            return [_kept_solid(solid, walls, str(exc))]
        try:
            found = _ellipsoid_on_voxels(shape, walls.thickness, solid.unit)
        except shell.ShellError as again:
            return [_kept_solid(solid, walls, str(again))]
        notes = (*notes, f"tube integral refused: {exc}")
    return [_shelled(found, walls, solid.provenance, solid.uncertainty, notes)]


def _ellipsoid_on_voxels(shape: Ellipsoid, t: float, unit: MassProperties) -> shell.Shell:
    """An ellipsoid more curved than its wall is thick (its inner body has edges): the
    interior estimated on voxels of a 96 x 192 latitude-longitude mesh of it, the wall
    the exact ellipsoid minus that interior."""
    theta = np.linspace(0.0, np.pi, 97)[1:-1]
    phi = np.linspace(0.0, 2 * np.pi, 192, endpoint=False)
    th, ph = np.meshgrid(theta, phi, indexing="ij")
    ring = np.stack([np.sin(th) * np.cos(ph), np.sin(th) * np.sin(ph), np.cos(th)], axis=-1)
    vertices = np.vstack([[0, 0, 1], ring.reshape(-1, 3), [0, 0, -1]]) * np.asarray(shape.radii)
    n, last = len(phi), len(vertices) - 1
    j = np.arange(n)
    faces = [np.column_stack([np.zeros(n, dtype=np.int64), 1 + j, 1 + (j + 1) % n])]
    for i in range(len(theta) - 1):
        a, b = 1 + i * n + j, 1 + i * n + (j + 1) % n
        faces += [np.column_stack([a, a + n, b + n]), np.column_stack([a, b + n, b])]
    k = 1 + (len(theta) - 1) * n
    faces.append(np.column_stack([np.full(n, last), k + (j + 1) % n, k + j]))
    f = np.vstack(faces)
    if solid_integrals(vertices, f)[0] < 0:
        f = f[:, ::-1]
    found = voxel_shell(vertices, f, t)
    v, first, second = shell.moments_of(unit)
    inner = found.interior
    return shell.Shell((v - inner[0], first - inner[1], second - inner[2]), inner,
                       found.error, found.method.replace("mesh", "ellipsoid", 1))


def _primitive_shell(shape: Shape, t: float) -> shell.Shell:
    if isinstance(shape, Box):
        return shell.box_shell(shape.size, t)
    if isinstance(shape, Cylinder):
        return shell.cylinder_shell(shape.radius, shape.length, t)
    if isinstance(shape, Sphere):
        return shell.sphere_shell(shape.radius, t)
    if isinstance(shape, Capsule):
        return shell.capsule_shell(shape.radius, shape.length, t)
    if isinstance(shape, Cone):
        return shell.cone_shell(shape.radius, shape.length, t)
    if isinstance(shape, Ellipsoid):
        return shell.ellipsoid_shell(shape.radii, t)
    raise TypeError(f"unknown shape {shape!r}")


def _shelled(found: shell.Shell, walls: Walls, provenance: str, uncertainty: float | None,
             notes: tuple[str, ...]) -> BodySolid:
    unit = found.filled(walls.infill)
    wall, interior = found.wall[0], found.interior[0]
    # the wall's stated error, relative to the weighted volume, on top of the body's own
    error = found.error * wall / unit.mass + (uncertainty or 0.0)
    # what was asked for goes in the provenance; notes are for what went wrong
    where = f"{provenance}; " if provenance and provenance != "closed form" else ""
    stated = None if uncertainty is None and not found.error else error
    return BodySolid(unit, found.method, notes,
                     f"{where}shell, {walls.label()} (wall {wall * 1e6:.4g} cm^3, "
                     f"interior {interior * 1e6:.4g} cm^3)", stated)


def _kept_solid(solid: BodySolid, walls: Walls, why: str) -> BodySolid:
    where = f"{solid.provenance}; " if solid.provenance else ""
    return BodySolid(solid.unit, solid.method,
                     (*solid.notes, f"shell not built, part kept solid: {why}"),
                     f"{where}solid: no {walls.thickness * 1e3:.4g} mm shell fits ({why})",
                     solid.uncertainty)


def _cross_check(found: shell.Shell, vertices: np.ndarray, faces: np.ndarray,
                 t: float) -> None:
    """A mesh too large for the offset's depth check to test every vertex
    (:data:`urdfinertia.inertia.shell.CHECKED_FACES`) is checked against a coarse voxel
    estimate: a wall outside the estimate's stated error is refused (an overlap the
    sampled check missed), never taken."""
    if len(faces) <= shell.CHECKED_FACES:
        return
    coarse = voxel_shell(vertices, faces, t, max_voxels=1_000_000)
    if abs(found.wall[0] - coarse.wall[0]) > coarse.error * coarse.wall[0]:
        raise shell.ShellError(f"the offset's wall ({found.wall[0] * 1e6:.4g} cm^3) is "
                               f"outside a voxel estimate's ({coarse.wall[0] * 1e6:.4g} "
                               f"cm^3 +- {coarse.error:.0%})")


#: Numbers per body of a cached mesh shell: mass, CoM (3), tensor (9), uncertainty.
_SHELL_NUMBERS = 14


def _mesh_shells(shape: Mesh, walls: Walls, meshes: MeshSource, base_dir: Path,
                 ) -> list[BodySolid]:
    """Each repaired body of the mesh shelled in the scaled frame (the wall's thickness
    is in metres after ``<mesh scale>``), in the mesh cache when ``meshes`` keeps one
    (:meth:`MeshLibrary.derived`): a shell costs a repair and an offset or voxels."""
    path = meshes.resolve(shape.filename, base_dir)
    derived = getattr(meshes, "derived", None)
    if derived is None:
        max_faces = getattr(meshes, "max_faces", DEFAULT_MAX_FACES)
        return _shelled_bodies(repair_mesh(load_mesh(path, max_faces)), shape, walls)
    import hashlib

    what = repr((walls.thickness, walls.infill, tuple(float(v) for v in shape.scale)))
    kind = "shell-" + hashlib.blake2b(what.encode(), digest_size=10).hexdigest()

    def make(mesh: TriangleMesh) -> tuple[dict, np.ndarray]:
        bodies = _shelled_bodies(repair_mesh(mesh), shape, walls)
        header = {"walls": what, "bodies": [
            {"method": b.method, "notes": list(b.notes), "provenance": b.provenance,
             "uncertain": b.uncertainty is None} for b in bodies]}
        numbers = np.concatenate([np.concatenate((
            [b.unit.mass], b.unit.com, b.unit.inertia.ravel(),
            [0.0 if b.uncertainty is None else b.uncertainty])) for b in bodies])
        return header, numbers

    def valid(header: dict, numbers: np.ndarray) -> bool:
        bodies = header.get("bodies")
        return (header.get("walls") == what and isinstance(bodies, list) and bool(bodies)
                and len(numbers) == _SHELL_NUMBERS * len(bodies))

    header, numbers = derived(path, kind, make, valid)
    out = []
    for i, body in enumerate(header["bodies"]):
        row = numbers[_SHELL_NUMBERS * i:_SHELL_NUMBERS * (i + 1)]
        unit = MassProperties(float(row[0]), row[1:4].copy(), row[4:13].reshape(3, 3).copy())
        out.append(BodySolid(unit, str(body["method"]), tuple(body["notes"]),
                             str(body["provenance"]),
                             None if body["uncertain"] else float(row[13])))
    return out


def _shelled_bodies(repaired: RepairedMesh, shape: Mesh, walls: Walls) -> list[BodySolid]:
    """Each body of ``repaired`` scaled as ``shape`` says and shelled as ``walls`` say."""
    scale = np.asarray(shape.scale, dtype=np.float64)
    mirrored = math.prod(shape.scale) < 0
    out = []
    for body in repaired.bodies:
        vertices = body.vertices * scale
        faces = body.faces[:, ::-1] if mirrored else body.faces
        volume, first, second = solid_integrals(vertices, faces)
        if not volume > 0:
            continue
        try:
            unit = mass_properties_from_integrals(volume, first, second, 1.0)
        except ValueError:
            continue  # a sliver (as :func:`urdfinertia.mesh.solids.integrate_repaired`)
        notes = body.notes + repaired.notes
        solid = BodySolid(unit, body.method, notes, body.provenance, body.error_estimate)
        try:
            found = shell.mesh_shell(vertices, faces, walls.thickness)
            _cross_check(found, vertices, faces, walls.thickness)
        except shell.ShellError as exc:
            # thin features somewhere (as in most printed parts): estimated on voxels,
            # where such places are all wall, as a slicer fills them
            why = f"exact offset refused: {exc}"
            try:
                found = voxel_shell(vertices, faces, walls.thickness)
            except shell.ShellError as again:
                out.append(_kept_solid(solid, walls, str(again)))
                continue
            notes = (*notes, why)
        out.append(_shelled(found, walls, body.provenance, body.error_estimate, notes))
    if not out:
        raise MeshError(f"mesh {shape.filename!r} encloses no volume", rule=Rule.MESH_NO_VOLUME)
    return out
