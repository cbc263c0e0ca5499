"""From a mesh file's triangles to solid bodies with exact volume integrals.

Each solid carries its volume integrals about the mesh frame's origin at unit density, so a
`<mesh scale>` (including mirroring, det < 0) is applied afterwards exactly:
volume scales by `|det S|`, the first moment by `|det S| S` and the second by
`|det S| S (.) S^T`. Every result names the method that produced it.

Two stages, timed and cached separately: `urdfinertia.mesh.repair.pipeline.repair_mesh` turns
the triangles into closed bodies (welding, orientation, hole caps, cavities, unions) and
`integrate_repaired` integrates them. Both results are plain arrays, floats and
strings, so they pickle.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from urdfinertia.errors import MeshError
from urdfinertia.inertia.massprops import MassProperties
from urdfinertia.inertia.polyhedron import mass_properties_from_integrals, solid_integrals
from urdfinertia.inertia.validity import diagnose_tensor
from urdfinertia.mesh.read.load import TriangleMesh
from urdfinertia.mesh.repair.pipeline import RepairedMesh, repair_mesh
from urdfinertia.rules import Rule


@dataclass(frozen=True, eq=False)
class Solid:
    """One body of a mesh: volume integrals about the mesh frame's origin.

    Attributes
    ----------
    volume : float
        m^3, positive.
    first : (3,) float
        `integral(x dV)`.
    second : (3, 3) float
        `integral(x x^T dV)`.
    method : str
        How the solid was obtained, e.g. `"exact (closed mesh)"`.
    error_estimate : float or None
        Estimated relative error of the volume where the method has one (0 for exact).
    notes : tuple of str
        What was repaired on this body.
    provenance : str
        How the surface was closed: "closed as given", "welded" or "stitched", then
        any holes capped and their estimate (see `RepairedBody.provenance`).
    """

    volume: float
    first: np.ndarray
    second: np.ndarray
    method: str
    error_estimate: float | None = None
    notes: tuple[str, ...] = ()
    provenance: str = ""

    def scaled(self, scale: ArrayLike) -> Solid:
        """The solid under `<mesh scale="sx sy sz">`; mirroring keeps volume positive."""
        s = np.asarray(scale, dtype=np.float64)
        det = abs(float(np.prod(s)))
        return Solid(
            self.volume * det,
            det * s * self.first,
            det * np.outer(s, s) * self.second,
            self.method,
            self.error_estimate,
            self.notes,
            self.provenance,
        )

    def mass_properties(self, density: float) -> MassProperties:
        """The solid's mass properties at `density`.

        Parameters
        ----------
        density : float
            kg/m^3.

        Returns
        -------
        MassProperties
            In the mesh's frame.
        """
        return mass_properties_from_integrals(self.volume, self.first, self.second, density)


@dataclass(frozen=True, eq=False)
class MeshSolids:
    """All bodies found in one mesh file, with notes on what was repaired."""

    solids: tuple[Solid, ...]
    notes: tuple[str, ...] = ()

    def scaled(self, scale: ArrayLike) -> MeshSolids:
        """Every solid scaled by `scale` (a `<mesh scale>`).

        Parameters
        ----------
        scale : (3,) float
            The scale along x, y, z.

        Returns
        -------
        MeshSolids
            The scaled solids, the same notes.
        """
        return MeshSolids(tuple(s.scaled(scale) for s in self.solids), self.notes)


SLIVER_FRACTION = 0.01
"""Bodies with an invalid tensor smaller than this fraction of a mesh's volume are dropped."""


def integrate_repaired(repaired: RepairedMesh) -> MeshSolids:
    """Exact volume integrals of each repaired body (cavities subtract).

    A body whose net volume is not positive (a sliver left by a boolean union, a shell
    cancelled by its cavity) is dropped with a note; none left is a `MeshError`.
    """
    candidates = []
    for body in repaired.bodies:
        volume, first, second = solid_integrals(body.vertices, body.faces)
        if np.isfinite(volume) and volume > 0:
            candidates.append(Solid(volume, first, second, body.method, body.error_estimate,
                                    body.notes, body.provenance))
    if not candidates:
        raise MeshError("mesh encloses no volume", rule=Rule.MESH_NO_VOLUME)
    notes = repaired.notes
    if len(candidates) < len(repaired.bodies):
        notes += (f"dropped {len(repaired.bodies) - len(candidates)} bodies with no net "
                  "volume",)
    # A body whose integrals give no valid tensor (not positive definite, or breaking the
    # triangle inequality) is not a closed solid: a self-crossing sliver left by a union
    # or a cap, or triangles of a soup capped into a surface that crosses itself (a
    # random soup gave principal moments breaking A + B >= C by 24 %). Tiny ones are
    # dropped with a note; a large one is an error, never a silent wrong answer.
    total = sum(s.volume for s in candidates)
    solids, slivers = [], 0.0
    for solid in candidates:
        why = _invalid_tensor(solid)
        if why:
            if solid.volume > SLIVER_FRACTION * total:
                raise MeshError(f"a repaired body ({solid.method}) holding "
                                f"{solid.volume / total:.1%} of the volume has no valid "
                                f"inertia tensor: {why}",
                                of_bytes=True)
            slivers += solid.volume
            continue
        solids.append(solid)
    if slivers:
        notes += (f"dropped {len(candidates) - len(solids)} sliver bodies without a valid "
                  f"tensor ({slivers / total:.2%} of the volume)",)
    return MeshSolids(tuple(solids), notes)


def _invalid_tensor(solid: Solid) -> str:
    """Why a solid's own tensor (unit density, about its centroid) is not a rigid body's;
    "" when it is one (:func:`~urdfinertia.inertia.validity.diagnose_tensor`)."""
    try:
        props = solid.mass_properties(1.0)
    except ValueError as exc:
        return str(exc)
    d = diagnose_tensor(props.inertia)
    if not d.positive_definite:
        return f"principal moments {d.moments.tolist()} are not all positive"
    if not d.triangle_ok:
        return (f"principal moments {d.moments.tolist()} break A + B >= C by "
                f"{d.triangle_excess:.3g} of C (the surface crosses itself)")
    return ""


def mesh_solids(mesh: TriangleMesh) -> MeshSolids:
    """Repair a mesh into closed bodies and integrate each one (see `repair`)."""
    return integrate_repaired(repair_mesh(mesh))
