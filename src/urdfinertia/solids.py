"""From a mesh file's triangles to solid bodies with exact volume integrals.

Each solid carries its volume integrals about the mesh frame's origin at unit density, so a
``<mesh scale>`` (including mirroring, det < 0) is applied afterwards exactly:
volume scales by ``|det S|``, the first moment by ``|det S| S`` and the second by
``|det S| S (.) S^T``. Every result names the method that produced it.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from .errors import MeshError
from .massprops import MassProperties
from .mesh_io import TriangleMesh
from .polyhedron import mass_properties_from_integrals, solid_integrals


@dataclass(frozen=True, eq=False)
class Solid:
    """One body of a mesh: volume integrals about the mesh frame's origin.

    Attributes
    ----------
    volume : float
        m^3, positive.
    first : (3,) float
        ``integral(x dV)``.
    second : (3, 3) float
        ``integral(x x^T dV)``.
    method : str
        How the solid was obtained, e.g. ``"exact (closed mesh)"``.
    error_estimate : float or None
        Relative error bound or estimate of the volume where the method has one.
    """

    volume: float
    first: np.ndarray
    second: np.ndarray
    method: str
    error_estimate: float | None = None
    notes: tuple[str, ...] = ()

    def scaled(self, scale: ArrayLike) -> Solid:
        """The solid under ``<mesh scale="sx sy sz">``; mirroring keeps volume positive."""
        s = np.asarray(scale, dtype=np.float64)
        det = abs(float(np.prod(s)))
        return Solid(
            self.volume * det,
            det * s * self.first,
            det * np.outer(s, s) * self.second,
            self.method,
            self.error_estimate,
            self.notes,
        )

    def mass_properties(self, density: float) -> MassProperties:
        return mass_properties_from_integrals(self.volume, self.first, self.second, density)


@dataclass(frozen=True, eq=False)
class MeshSolids:
    """All bodies found in one mesh file, with notes on what was repaired."""

    solids: tuple[Solid, ...]
    notes: tuple[str, ...] = ()

    def scaled(self, scale: ArrayLike) -> MeshSolids:
        return MeshSolids(tuple(s.scaled(scale) for s in self.solids), self.notes)


def mesh_solids(mesh: TriangleMesh) -> MeshSolids:
    """Split a mesh into bodies and integrate each one.

    Closed bodies are integrated exactly after merging duplicate vertices and orienting
    faces outward. Open bodies are closed where trimesh can fill the holes; otherwise
    their surface is integrated as it is, with a warning.
    """
    import trimesh

    tm = trimesh.Trimesh(mesh.vertices, mesh.faces, process=True, validate=False)
    tm.merge_vertices()
    tm.update_faces(tm.nondegenerate_faces())
    if len(tm.faces) == 0:
        raise MeshError("mesh has no non-degenerate triangles")
    bodies = tm.split(only_watertight=False)
    solids: list[Solid] = []
    notes: list[str] = []
    for body in bodies:
        solid = _body_solid(body)
        if solid is not None:
            solids.append(solid)
    if not solids:
        raise MeshError("mesh encloses no volume (flat or degenerate surface)")
    if len(bodies) > 1:
        notes.append(f"{len(bodies)} bodies")
    return MeshSolids(tuple(solids), tuple(notes))


def _body_solid(body) -> Solid | None:
    import trimesh

    notes: list[str] = []
    method = "exact (closed mesh)"
    if not body.is_watertight:
        trimesh.repair.fill_holes(body)
        if body.is_watertight:
            method = "exact after filling holes"
        else:
            method = "open surface integrated as is"
            notes.append("open mesh: volume is approximate")
    trimesh.repair.fix_winding(body)
    volume, first, second = solid_integrals(body.vertices, body.faces)
    if volume < 0:
        volume, first, second = -volume, -first, -second
        notes.append("inverted faces flipped")
    if volume <= 1e-15:
        return None
    return Solid(volume, first, second, method, None, tuple(notes))
