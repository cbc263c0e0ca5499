"""Turn a mesh file's triangles into closed, outward-oriented bodies, saying what it took.

The stages, in order (each vectorised; see `meshgraph`, `holes`, `winding`):

1. weld: merge exactly repeated vertices (STL triangle soup) and vertices closer than
   `WELD_RTOL` of the mesh size (cracks between patches); drop degenerate triangles;
   keep repeated triangles once, and cancel pairs of opposite ones (a shared inner wall);
2. orient: make neighbouring faces agree across every two-sided edge (a patch is a set of
   faces linked that way);
3. close: cap each patch's boundary loops (`holes.close_holes`: triangulations,
   fans or winding-number level caps), so every patch becomes a closed shell with a
   well-defined signed volume, each cap stating its uncertainty;
4. turn outward: a shell nested in no other is turned to positive volume; a nested
   shell keeps its orientation relative to its container, so an opposite one is a
   cavity and a same-oriented one is a solid inside a solid (removed by the union);
5. union: bodies whose bounding boxes overlap are united with manifold3d, so shared
   volume counts once;
6. group: each outward shell with the cavities directly inside it is one body.

Shells that enclose no volume (flat sheets, stray triangles) are dropped with a note.
"""

from __future__ import annotations

import weakref
from dataclasses import dataclass

import numpy as np

from urdfinertia.errors import MeshError
from urdfinertia.inertia.polyhedron import cross_rows, face_volumes, used_vertices
from urdfinertia.mesh.limits import OVER_BUDGET_NOTE, mesh_seconds
from urdfinertia.mesh.read.load import TriangleMesh
from urdfinertia.mesh.repair.graph import (
    EdgeTable,
    cancel_duplicate_faces,
    consistent_orientation,
    drop_degenerate,
    edge_table,
    face_components,
    is_closed_oriented,
    sort_order,
    split_vertices,
    weld_vertices,
)
from urdfinertia.mesh.repair.holes import HoleCaps, cap_with_fans, close_holes
from urdfinertia.mesh.repair.nesting import nest_signs, probe_point
from urdfinertia.mesh.repair.stitch import stitch_seams
from urdfinertia.mesh.repair.winding import closed_winding_numbers
from urdfinertia.rules import Rule
from urdfinertia.timing import Deadline, OverBudget, StageTimes

WELD_RTOL = 1e-6
"""Vertices closer than this fraction of the bounding-box diagonal are merged."""
FLAT_RTOL = 1e-7
"""A shell whose volume is below this fraction of (its area)^1.5 encloses nothing."""
OVERLAP_RTOL = 1e-9
"""Union results within this relative volume of the plain sum mean no overlap."""


@dataclass(frozen=True, eq=False)
class RepairedBody:
    """One closed body: an outward shell and any inward cavity shells inside it.

    Attributes
    ----------
    vertices : (n, 3) float
    faces : (m, 3) int
        A closed surface (every edge used equally often in both directions), oriented
        so that its signed volume integrals are those of the solid.
    method : str
        How the surface was obtained.
    error_estimate : float or None
        Estimated relative error of the volume, where the method has one.
    notes : tuple of str
        What was repaired on this body.
    provenance : str
        How its surface was closed, in one phrase: "closed as given", "welded",
        "stitched", each followed by "; capped N holes (volume within ~x%)" where holes
        were capped, naming how many were closed by winding-number level surfaces.
    dependence : float
        m^3, how much the volume depends on the choice of caps (`HoleCaps.dependence`)
        plus what a stitch may have changed: the figure by which a stitched and an
        unstitched repair of the same mesh are compared.
    """

    vertices: np.ndarray
    faces: np.ndarray
    method: str
    error_estimate: float | None = None
    notes: tuple[str, ...] = ()
    provenance: str = ""
    dependence: float = 0.0


@dataclass(frozen=True, eq=False)
class RepairedMesh:
    """All bodies of one mesh file, and notes on what was repaired for the whole file."""

    bodies: tuple[RepairedBody, ...]
    notes: tuple[str, ...] = ()


_Measures = tuple[np.ndarray, np.ndarray]
"""Signed volume and area of each labelled shell: `(volume, area)`."""


@dataclass(frozen=True, eq=False)
class _Shell:
    """A closed, edge-connected surface of the repaired mesh."""

    vertices: np.ndarray
    faces: np.ndarray
    volume: float  # signed: negative for a cavity
    caps: HoleCaps


def repair_mesh(mesh: TriangleMesh, timer: StageTimes | None = None,
                seconds: float | None = -1.0) -> RepairedMesh:
    """Weld, orient, close, turn outward and unite the bodies of `mesh`.

    `timer`, when given, gets the time spent in boolean unions as stage `"union"`.
    `seconds` is the time the refined hole caps may take (default
    `mesh_seconds`, None for no limit); past it the holes
    are capped with fans, the stated error widened and a note says so.

    Raises
    ------
    MeshError
        Non-finite or out-of-range input, or nothing that encloses a volume.
    """
    # the budget covers every stage: weld, stitch, caps and unions
    deadline = Deadline(mesh_seconds() if seconds is not None and seconds < 0 else seconds)
    vertices, faces = _checked(mesh)
    notes: list[str] = []
    used = vertices[used_vertices(len(vertices), faces)]
    size = float(np.linalg.norm(used.max(axis=0) - used.min(axis=0)))
    if not size > 0:
        raise MeshError("mesh is a single point: it encloses no volume", rule=Rule.MESH_NO_VOLUME)
    n_in = len(used)
    del used  # a copy of every used vertex: not kept through the repair (memory)
    vertices, faces = weld_vertices(vertices, faces, WELD_RTOL * size)
    if len(vertices) < n_in:
        notes.append(f"merged {n_in - len(vertices)} duplicate vertices")
    n_faces = len(faces)
    faces = drop_degenerate(vertices, faces, (1e-12 * size) ** 2)
    if len(faces) < n_faces:
        notes.append(f"dropped {n_faces - len(faces)} degenerate triangles")
    faces, repeats, cancelled = cancel_duplicate_faces(faces)
    if repeats:
        notes.append(f"dropped {repeats} repeated triangles")
    if cancelled:
        notes.append(f"removed {cancelled} pairs of coincident opposite triangles")
    if len(faces) == 0:
        raise MeshError("mesh has no non-degenerate triangles: it encloses no volume",
                        rule=Rule.MESH_NO_VOLUME)
    timer = timer if timer is not None else StageTimes()
    welded = "welded" if notes else "closed as given"
    # one edge table for the stitch and, when nothing was stitched, the repair
    table: EdgeTable | None = edge_table(faces)
    try:
        stitch = stitch_seams(vertices, faces, size, table, deadline)
    except OverBudget:  # the repair goes on without the stitch, and says so
        stitch = None
        notes.append(f"{OVER_BUDGET_NOTE} ({deadline.seconds:g} s): seams not stitched "
                     "(--mesh-seconds raises it)")
    if stitch is None:
        return _finish(_close_up(vertices, faces, notes, deadline, welded, table=table),
                       timer, deadline)
    table = None  # not kept through the stitched repair (memory): built again if needed
    stitched_faces = drop_degenerate(stitch.vertices, stitch.faces, (1e-12 * size) ** 2)
    stitched_faces, _, _ = cancel_duplicate_faces(stitched_faces)
    # nothing dropped: the same faces in the same order, so the stitch's table holds
    stitched_table = stitch.table if len(stitched_faces) == len(stitch.faces) else None

    def plain() -> RepairedMesh:
        return _finish(_close_up(vertices, faces, notes, deadline, welded), timer, deadline)

    try:
        stitched = _close_up(stitch.vertices, stitched_faces, notes + [stitch.note()],
                             deadline, stitch.provenance(), stitch.uncertainty,
                             stitched_table)
    except MeshError:
        return plain()
    # the stitch's arrays and tables are not needed past here: freed before the unions,
    # the memory peak of a large mesh
    ambiguous = stitch.ambiguous
    del stitch, stitched_faces, stitched_table
    if not ambiguous:
        try:
            return _finish(stitched, timer, deadline)
        except OverBudgetError:
            raise
        except MeshError:
            return plain()
    # some rims stayed open or an edge now has three faces: the stitch may have joined
    # what it should not have; keep whichever repair states the smaller uncertainty. The
    # unions (the costly part) are run for the repair kept only, where the figures
    # before the unions settle the comparison (:meth:`_Closed.stated_error_bounds`).
    try:
        unstitched = _close_up(vertices, faces, notes, deadline, welded)
    except MeshError:
        try:
            return _finish(stitched, timer, deadline)
        except OverBudgetError:
            raise
        except MeshError:
            return plain()  # raises as the unstitched repair did
    p_lo, p_hi = unstitched.stated_error_bounds()
    s_lo, s_hi = stitched.stated_error_bounds()
    # one repair states less whatever the unions do: unite only that one (checked
    # against its own bound afterwards, which rests on a union leaving no more bodies
    # than it was given)
    for first, hi, other_lo, second in ((unstitched, p_hi, s_lo, stitched),
                                        (stitched, s_hi, p_lo, unstitched)):
        if hi < other_lo:
            try:
                kept = _finish(first, timer, deadline)
            except OverBudgetError:
                raise
            except MeshError:
                return _finish(second, timer, deadline)
            if _stated_error(kept) <= hi:
                return kept
    try:
        stitched_mesh = _finish(stitched, timer, deadline)
    except OverBudgetError:
        raise
    except MeshError:
        return _finish(unstitched, timer, deadline)
    try:
        plain_mesh = _finish(unstitched, timer, deadline)
    except OverBudgetError:
        raise
    except MeshError:
        return stitched_mesh
    return plain_mesh if _stated_error(plain_mesh) < _stated_error(stitched_mesh) \
        else stitched_mesh


def _stated_error(repaired: RepairedMesh) -> float:
    """How much a repair's volume depends on its choices (m^3): what a stitched and an
    unstitched repair are compared by. Not the stated error bound (the tent of
    `holes` bounds what a cap may miss, the same for both repairs' big holes)."""
    return sum(b.dependence for b in repaired.bodies)


BOUNDS_RTOL = 1e-9
"""Relative round-off allowed between a repair's dependence summed before and after its unions (the
union shares its bodies' dependence out and sums it again).
"""


@dataclass(frozen=True, eq=False)
class _Closed:
    """A repair up to its unions (stages 2-4 and 6): its bodies before any union, and
    what `_finish` needs to unite them and state their provenance."""

    bodies: list[RepairedBody]
    notes: list[str]
    origin: str
    stitch_uncertainty: float

    def stated_error_bounds(self) -> tuple[float, float]:
        """Bounds on `_stated_error` of `_finish`'s result, without the unions.

        A union gives the bodies it unites their summed dependence, shared out among as
        many bodies as it leaves, each also carrying `stitch_uncertainty`: at least one
        per group of bodies whose boxes overlap, at most one per body given (the upper
        bound is checked on the union's result by the caller). Bodies whose boxes overlap
        no other's keep theirs. The lower bound assumes a union leaves no body enclosing
        no volume (`drop_empty`; a degenerate union, not seen on the corpus). Exact
        when no box overlaps another.
        """
        u = self.stitch_uncertainty
        dep = np.array([b.dependence for b in self.bodies])
        kept = np.array([_body_volume(b) != 0 for b in self.bodies])
        touch = _touching(self.bodies)
        if not touch.any():
            exact = sum(b.dependence + u for b, k in zip(self.bodies, kept, strict=True) if k)
            return exact, exact
        from scipy.sparse.csgraph import connected_components

        alone = ~touch.any(axis=1)
        rest = float(np.sum((dep + u)[alone & kept]))
        unchanged = float(np.sum((dep + u)[kept]))  # the union failed or removed nothing
        shared = float(np.sum(dep[~alone]))
        groups = connected_components(touch[~alone][:, ~alone], directed=False)[0]
        lo = min(unchanged, rest + shared + u * groups)
        hi = max(unchanged, rest + shared + u * int(np.count_nonzero(~alone)))
        return lo * (1 - BOUNDS_RTOL), hi * (1 + BOUNDS_RTOL)


def _touching(bodies: list[RepairedBody]) -> np.ndarray:
    """(k, k) bool: the bodies whose bounding boxes overlap (a body not with itself)."""
    lo = np.array([b.vertices.min(axis=0) for b in bodies]).reshape(-1, 3)
    hi = np.array([b.vertices.max(axis=0) for b in bodies]).reshape(-1, 3)
    touch = np.all((lo[:, None] < hi[None]) & (lo[None] < hi[:, None]), axis=2)
    np.fill_diagonal(touch, False)
    return touch


def _close_up(vertices: np.ndarray, faces: np.ndarray, notes: list[str],
              deadline: Deadline, origin: str, stitch_uncertainty: float = 0.0,
              table: EdgeTable | None = None) -> _Closed:
    """Orient, cap, turn outward and group welded faces (stages 2-4 and 6); the union
    (stage 5) is `_finish`'s.

    Past `deadline` the holes are capped with fans (`HoleCaps.widened`).

    `origin` says how the surface was obtained before capping ("closed as given",
    "welded", "stitched"); `stitch_uncertainty` (m^3) is what stitching may have
    changed, added to every body's stated error. `table` is `edge_table(faces)` when
    the caller has it already.
    """
    notes = list(notes)
    table = table if table is not None else edge_table(faces)
    # closed and oriented already (most CAD exports): no flips, no caps, and the edge
    # components are both the orientation patches and the shells
    known = face_components(faces, table) if is_closed_oriented(table) else None
    oriented, reversed_faces, non_orientable, measures = _orient(vertices, faces, table, known)
    flipped = int(np.count_nonzero(reversed_faces))
    if flipped:
        notes.append(f"reoriented {flipped} of {len(faces)} faces outward")
    if non_orientable:
        notes.append(f"{non_orientable} faces lie on a non-orientable surface: "
                     "volume is approximate")
    if known is not None:  # nothing to cap; turning whole shells keeps the components
        shells, flat = _split(vertices, oriented, HoleCaps.none(), known, measures)
    else:
        # the oriented faces' edges are the input's, each reversed face's run backwards:
        # the half-edges of the table with their directions turned serve
        oriented_table = table._replace(forward=table.forward ^ np.repeat(reversed_faces, 3))
        try:
            closed_v, closed_f, caps = close_holes(vertices, oriented, deadline=deadline,
                                                   table=oriented_table)
        except OverBudget:
            closed_v, closed_f, caps = close_holes(vertices, oriented, triangulate=False,
                                                   table=oriented_table)
            caps = caps.widened()
            notes.append(f"{OVER_BUDGET_NOTE} ({deadline.seconds:g} s): holes capped with "
                         "fans only, stated error widened (--mesh-seconds raises it)")
            origin = f"{origin}; fans only, over the {deadline.seconds:g} s repair budget"
        shells, flat = _split(closed_v, closed_f, caps)
    if flat:
        notes.append(f"ignored {flat} pieces enclosing no volume (flat or stray triangles)")
    if not shells:
        raise MeshError("mesh encloses no volume (flat sheet, single triangle or "
                        "degenerate surface)", rule=Rule.MESH_NO_VOLUME)
    groups, loose = _group(shells)
    if loose:
        notes.append(f"turned {loose} inverted shells that lie in no other body outward")
    bodies = [_body(shells, o, c) for o, c in groups]
    return _Closed(bodies, notes, origin, stitch_uncertainty)


def _finish(closed: _Closed, timer: StageTimes, deadline: Deadline | None = None,
            ) -> RepairedMesh:
    """Unite the overlapping bodies of `closed` (stage 5) and state their provenance."""
    notes = list(closed.notes)
    bodies, union_note = _unite(closed.bodies, timer, deadline)
    if union_note:
        notes.append(union_note)
    bodies = drop_empty(bodies, notes)
    if len(bodies) > 1:
        notes.append(f"{len(bodies)} bodies")
    bodies = [_with_origin(b, closed.origin, closed.stitch_uncertainty) for b in bodies]
    return RepairedMesh(tuple(bodies), tuple(notes))


def drop_empty(bodies: list[RepairedBody], notes: list[str]) -> list[RepairedBody]:
    """`bodies` without those enclosing no volume (a union can leave one: pybullet's
    samurai monastery), noted; `MeshError` when none is left."""
    kept = [b for b in bodies if _body_volume(b) != 0]
    if len(kept) < len(bodies):
        notes.append(f"ignored {len(bodies) - len(kept)} bodies enclosing no volume after "
                     "the union")
        if not kept:
            raise MeshError("mesh encloses no volume once its shells are united",
                            rule=Rule.MESH_NO_VOLUME)
    return kept


def _with_origin(body: RepairedBody, origin: str, stitch_uncertainty: float) -> RepairedBody:
    """`body` with its provenance, and the stitch's uncertainty added to its error."""
    capped = body.provenance  # set by _body: "" or the caps' summary
    error, method = body.error_estimate, body.method
    if origin.startswith("stitched"):
        method = f"stitched seams; {method}"
    if stitch_uncertainty > 0:
        error = (error or 0.0) + stitch_uncertainty / abs(_body_volume(body))
        if not capped:
            origin = f"{origin}, volume within ~{100 * error:.2g}%"
    provenance = f"{origin}; {capped}" if capped else origin
    return RepairedBody(body.vertices, body.faces, method, error, body.notes, provenance,
                        body.dependence + stitch_uncertainty)


def _checked(mesh: TriangleMesh) -> tuple[np.ndarray, np.ndarray]:
    vertices = np.asarray(mesh.vertices, dtype=np.float64)
    faces = np.asarray(mesh.faces)
    if vertices.ndim != 2 or vertices.shape[1] != 3:
        raise MeshError(f"mesh vertices must have shape (n, 3), got {vertices.shape}")
    if faces.ndim != 2 or faces.shape[1] != 3 or len(faces) == 0:
        raise MeshError(f"mesh faces must have shape (m, 3) with m > 0, got {faces.shape}")
    faces = faces.astype(np.int64)
    if faces.min() < 0 or faces.max() >= len(vertices):
        raise MeshError("mesh faces index vertices that do not exist")
    if not np.all(np.isfinite(vertices[used_vertices(len(vertices), faces)])):
        raise MeshError("mesh has non-finite (NaN or infinite) vertex coordinates")
    return vertices, faces


def _orient(vertices: np.ndarray, faces: np.ndarray, table: EdgeTable,
            closed: tuple[int, np.ndarray] | None,
            ) -> tuple[np.ndarray, np.ndarray, int, _Measures | None]:
    """Faces oriented consistently per patch and outward per closed patch.

    Each orientation patch is closed on its own (private vertices, so loops never cross
    patches) to get a signed volume. Patches in no other are turned to positive volume;
    a nested patch keeps its input orientation relative to its container (cavity or
    solid-in-solid). Patches enclosing no volume (stray triangles, sheets) keep the
    orientation most of their input faces had, inverted if the largest patch was.

    `table` is `edge_table(faces)`. `closed`, when every edge has two opposite
    faces (`is_closed_oriented`), is `face_components(faces)`: then no face
    flips, the patches are those components and each is closed already, so the private
    copies are skipped (they would hold the same coordinates, hence the same sums).

    Returns the oriented faces, which input faces were reversed, how many lie on
    non-orientable patches, and, when `closed` is given and no patch was turned, the
    patches' volumes and areas (which `_split` would compute again).
    """
    if closed is not None:
        flip = np.zeros(len(faces), dtype=bool)
        non_orientable = flip
        _, patch = closed
        propagated = faces
        own_v, own_f, face_patch = vertices, faces, patch
    else:
        flip, patch, non_orientable = consistent_orientation(faces, table)
        propagated = np.where(flip[:, None], faces[:, ::-1], faces)
        own_v, own_f, face_patch = _patch_copies(vertices, propagated, patch)
    n_patch = int(patch.max() + 1)
    centre = vertices[used_vertices(len(vertices), faces)].mean(axis=0)
    tri = np.take(vertices, faces, axis=0) - centre  # vertices[faces], a faster gather
    own_tri = tri if closed is not None else np.take(own_v, own_f, axis=0) - centre
    volume = np.bincount(face_patch, weights=face_volumes(own_tri), minlength=n_patch)
    area = np.bincount(patch, weights=_areas(tri), minlength=n_patch)
    # the corner copies are not needed past here: freed before the nesting test, the
    # memory peak of a large mesh
    del tri, own_tri
    flat = ~(np.abs(volume) > FLAT_RTOL * area ** 1.5)
    majority_flipped = 2 * np.bincount(patch, weights=flip, minlength=n_patch) > \
        np.bincount(patch, minlength=n_patch)
    given = np.where(majority_flipped, -1.0, 1.0) * np.sign(volume)
    final = nest_signs(own_v, own_f, face_patch, np.abs(volume), given, flat)
    turn = np.sign(volume) != final
    if np.any(~flat):
        big = int(np.argmax(np.where(flat, -1.0, np.abs(volume))))
        inverted = given[big] != final[big]
        turn[flat] = majority_flipped[flat] ^ inverted
    reverse = turn[patch]
    oriented = np.where(reverse[:, None], propagated[:, ::-1], propagated)
    measures = (volume, area) if closed is not None and not turn.any() else None
    return oriented, flip ^ reverse, int(np.count_nonzero(non_orientable)), measures


def _patch_copies(vertices: np.ndarray, faces: np.ndarray, patch: np.ndarray,
                  ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Each patch on private vertices, capped with fans: vertices, faces, patch per face."""
    count = int(patch.max()) + 1
    uniq, local, bounds = split_vertices(len(vertices), faces, patch, count)
    own_v, own_f = cap_with_fans(vertices[uniq], local)
    vertex_patch = np.concatenate([np.repeat(np.arange(count), np.diff(bounds)),
                                   np.zeros(len(own_v) - len(uniq), np.int64)])
    return own_v, own_f, np.concatenate([patch, vertex_patch[own_f[len(local):, 0]]])


def _split(vertices: np.ndarray, faces: np.ndarray, caps: HoleCaps,
           known: tuple[int, np.ndarray] | None = None, measures: _Measures | None = None,
           ) -> tuple[list[_Shell], int]:
    """Edge-connected closed shells; those enclosing no volume are counted and dropped.

    `known` is `face_components(faces)` when the caller has it already, `measures`
    each component's signed volume and area.
    """
    count, label = known if known is not None else face_components(faces)
    vertex_label = np.zeros(len(vertices), dtype=np.int64)
    vertex_label[faces.reshape(-1)] = np.repeat(label, 3)
    if measures is None:
        centre = vertices[used_vertices(len(vertices), faces)].mean(axis=0)
        tri = np.take(vertices, faces, axis=0) - centre
        measures = (np.bincount(label, weights=face_volumes(tri), minlength=count),
                    np.bincount(label, weights=_areas(tri), minlength=count))
    volume, area = measures
    solid = np.abs(volume) > FLAT_RTOL * area ** 1.5
    order = sort_order(label)
    bounds = np.searchsorted(label[order], np.arange(count + 1))
    # each shell's sorted vertices and its faces re-indexed into them, for all shells at
    # once, shell by shell, vertices ascending within
    uniq, local, vbounds = split_vertices(len(vertices), faces[order], label[order], count)
    loop_label = vertex_label[caps.vertex]
    shells = []
    for c in np.flatnonzero(solid):  # one iteration per shell, slicing only
        used = uniq[vbounds[c]:vbounds[c + 1]]
        shells.append(_Shell(vertices[used], local[bounds[c]:bounds[c + 1]] - vbounds[c],
                             float(volume[c]), caps.subset(loop_label == c)))
    return shells, int(np.count_nonzero(~solid))


def _areas(tri: np.ndarray) -> np.ndarray:
    """(m,) area of each triangle of `tri` (m, 3 corners, 3)."""
    return 0.5 * np.linalg.norm(cross_rows(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0]),
                                axis=1)


def _group(shells: list[_Shell]) -> tuple[list[tuple[int, list[int]]], int]:
    """`[(outer shell, [its cavities])]` and how many stray inverted shells were turned.

    A negative shell inside a positive one is a cavity of the smallest such container;
    one inside none is a body the wrong way round, turned outward.
    """
    positive = [i for i, s in enumerate(shells) if s.volume > 0]
    negative = [i for i, s in enumerate(shells) if s.volume < 0]
    cavities: dict[int, list[int]] = {i: [] for i in positive}
    lo = np.array([s.vertices.min(axis=0) for s in shells]).reshape(-1, 3)
    hi = np.array([s.vertices.max(axis=0) for s in shells]).reshape(-1, 3)
    pos, neg = np.array(positive, dtype=np.int64), np.array(negative, dtype=np.int64)
    boxed = (np.all(lo[neg][:, None] >= lo[pos][None], axis=2)
             & np.all(hi[neg][:, None] <= hi[pos][None], axis=2))  # (cavity, container)
    inside = np.zeros_like(boxed)
    probes = {c: probe_point(shells[c].vertices[shells[c].faces])
              for c in neg[boxed.any(axis=1)].tolist()}
    for j in np.flatnonzero(boxed.any(axis=0)):  # one winding evaluation per container
        rows = np.flatnonzero(boxed[:, j])
        q = shells[pos[j]]
        w = closed_winding_numbers(np.array([probes[c] for c in neg[rows].tolist()]),
                                   q.vertices, q.faces)
        inside[rows, j] = np.abs(w) > 0.5
    loose = 0
    for row, c in enumerate(negative):
        home = pos[inside[row]].tolist()
        if home:
            cavities[min(home, key=lambda q: shells[q].volume)].append(c)
        else:
            s = shells[c]
            shells[c] = _Shell(s.vertices, s.faces[:, ::-1].copy(), -s.volume, s.caps)
            cavities[c] = []
            loose += 1
    return list(cavities.items()), loose


def _body(shells: list[_Shell], outer: int, cavities: list[int]) -> RepairedBody:
    members = [shells[outer]] + [shells[c] for c in cavities]
    offsets = np.cumsum([0] + [len(s.vertices) for s in members])
    vertices = np.concatenate([s.vertices for s in members])
    faces = np.concatenate([s.faces + o for s, o in zip(members, offsets[:-1], strict=True)])
    volume = sum(s.volume for s in members)
    loops = sum(s.caps.loops for s in members)
    planar = sum(int(s.caps.planar.sum()) for s in members)
    uncertainty = sum(float(s.caps.uncertainty.sum()) for s in members)
    notes: list[str] = []
    error = 0.0
    provenance = ""
    if loops == 0:
        method = "exact (closed mesh)"
    elif planar == loops:
        method = f"exact after closing {loops} planar holes"
        provenance = f"capped {loops} planar holes exactly"
    else:
        method = f"closed {loops} holes with caps (estimate)"
        error = uncertainty / volume
        area = _areas(vertices[faces]).sum()
        share = sum(float(s.caps.area.sum()) for s in members) / area
        level = sum(int(s.caps.level.sum()) for s in members)
        by = f", {level} by winding-number level surfaces" if level else ""
        notes.append(f"open mesh: closed {loops} holes ({100 * share:.2g}% of the surface"
                     f"{by}), volume estimated within ~{100 * error:.2g}%")
        provenance = f"capped {loops} holes{by} (volume within ~{100 * error:.2g}%)"
    if cavities:
        notes.append(f"{len(cavities)} cavities subtracted")
    dependence = sum(float(s.caps.dependence.sum()) for s in members)
    return RepairedBody(vertices, faces, method, error, tuple(notes), provenance, dependence)


class OverBudgetError(MeshError):
    """The repair ran out of its time budget at a stage with no cheaper fallback (the
    unions: skipping them would count shared volume twice). Not a property of the bytes
    alone: another run may have the time, so it is not cached."""

    def __init__(self, deadline: Deadline, what: str) -> None:
        super().__init__(f"{OVER_BUDGET_NOTE} ({deadline.seconds:g} s) before {what} "
                         "(--mesh-seconds raises it)", rule=Rule.MESH_REFUSED)


#: Bodies united by one boolean call: the time budget is checked between such calls. Above
#: the most a mesh of example-robot-data unites (178 bodies: borinot's base), so that every
#: real mesh seen is still united in one call, as before the budget covered the unions.
UNION_CHUNK = 256


def _unite(bodies: list[RepairedBody], timer: StageTimes, deadline: Deadline | None = None,
           ) -> tuple[list[RepairedBody], str]:
    """Bodies, with those whose bounding boxes overlap replaced by their boolean union.

    Up to :data:`UNION_CHUNK` bodies are united in one call; more in calls of that many,
    then their results, with ``deadline`` checked before each call
    (:class:`OverBudgetError`).
    """
    if len(bodies) < 2:
        return bodies, ""
    touch = _touching(bodies)
    involved = np.flatnonzero(touch.any(axis=1))
    if len(involved) == 0:
        return bodies, ""
    chosen = [bodies[i] for i in involved]
    with timer.stage("union"):
        united = _union_in_chunks(chosen, deadline)
    if united is None:
        return bodies, (f"{len(involved)} bodies may overlap but are not manifold: "
                        "shared volume may be counted twice")
    before = sum(_body_volume(b) for b in chosen)
    after = _volume(*united)
    if abs(before - after) <= OVERLAP_RTOL * before:
        return bodies, ""
    rest = [b for i, b in enumerate(bodies) if not touch[i].any()]
    shells_u, _ = _split(*united, HoleCaps.none())
    groups_u, _ = _group(shells_u)
    exact = all(b.method.startswith("exact") for b in chosen)
    base = "exact" if exact else "holes closed with caps (estimate)"
    # the stated volumes add up: each body's relative error weighted by its volume, over
    # the united volume (a small, badly capped body must not set the whole body's error)
    error = sum((b.error_estimate or 0.0) * abs(_body_volume(b))
                for b in chosen) / after
    notes = tuple(dict.fromkeys(n for b in chosen for n in b.notes))
    capped = "; ".join(dict.fromkeys(b.provenance for b in chosen if b.provenance))
    new = []
    for o, c in groups_u:
        body = _body(shells_u, o, c)
        new.append(RepairedBody(body.vertices, body.faces,
                                f"{base}; boolean union of overlapping bodies (manifold3d)",
                                error, notes + body.notes,
                                f"{capped}; united" if capped else "united",
                                sum(b.dependence for b in chosen) / len(groups_u)))
    note = (f"united {len(involved)} overlapping bodies into {len(new)}: removed "
            f"{100 * (before - after) / before:.3g}% double-counted volume")
    return rest + new, note


def _union_in_chunks(bodies: list[RepairedBody], deadline: Deadline | None,
                     ) -> tuple[np.ndarray, np.ndarray] | None:
    """`union_bodies` of `bodies`: in one call up to `UNION_CHUNK` of them (never
    interrupted, as one hole cap is not); more (a soup of overlapping shells: 3,000 boxes
    took 5 s) in calls of that many, then their results, `deadline` checked before each
    call."""
    from urdfinertia.mesh.repair.union import union_bodies

    if len(bodies) <= UNION_CHUNK:
        return union_bodies(bodies)
    parts: list[RepairedBody | _Piece] = list(bodies)
    while len(parts) > 1:
        merged: list[RepairedBody | _Piece] = []
        for i in range(0, len(parts), UNION_CHUNK):
            if deadline is not None and deadline.expired():
                raise OverBudgetError(deadline, f"uniting {len(bodies)} overlapping bodies")
            found = union_bodies(parts[i:i + UNION_CHUNK])
            if found is None:
                return None
            # writable copies: manifold3d refuses its own read-only result arrays as input
            merged.append(_Piece(np.array(found[0]), np.array(found[1])))
        parts = merged
    return parts[0].vertices, parts[0].faces


@dataclass(frozen=True, eq=False)
class _Piece:
    """A partial union: what `union_bodies` takes (vertices and faces)."""

    vertices: np.ndarray
    faces: np.ndarray


_BODY_VOLUMES: weakref.WeakKeyDictionary[RepairedBody, float] = weakref.WeakKeyDictionary()
"""`_volume` of each body asked about, while the body lives: the stated bounds, the union and
the provenance ask for the same bodies' volumes several times.
"""


def _body_volume(body: RepairedBody) -> float:
    """`_volume(body.vertices, body.faces)`, computed once per body (its arrays are not
    changed once it is made)."""
    volume = _BODY_VOLUMES.get(body)
    if volume is None:
        volume = _BODY_VOLUMES[body] = _volume(body.vertices, body.faces)
    return volume


def _volume(vertices: np.ndarray, faces: np.ndarray) -> float:
    centre = vertices.mean(axis=0)
    return float(face_volumes(np.take(vertices, faces, axis=0) - centre).sum())

