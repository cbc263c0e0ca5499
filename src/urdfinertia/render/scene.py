"""What the report's 3-D view shows: the robot at its zero configuration, and boxes.

Three things, all in the world frame of the robot's root link(s):

* link poses at the zero configuration (every joint at 0, so a link's pose is the product
  of the joint origins from the root);
* the links' display geometry as triangle meshes, decimated to a face budget so that
  the HTML stays small;
* per link and per source (existing / recomputed inertial) the *equivalent-inertia box*:
  the uniform box with the same mass and principal moments, oriented along the principal
  axes and centred at the CoM, as Gazebo's and RViz's "view inertia" draw it.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from urdfinertia.cache.library import MeshLibrary
from urdfinertia.descriptions.kinematics import zero_configuration_poses
from urdfinertia.descriptions.model import (
    Box,
    Capsule,
    Cone,
    Cylinder,
    Ellipsoid,
    GeometryRef,
    Inertial,
    Link,
    Mesh,
    Robot,
    Shape,
    Sphere,
)
from urdfinertia.errors import UrdfInertiaError
from urdfinertia.inertia.massprops import MassProperties

#: Default face budget of the whole 3-D view (about 24 bytes per face in the HTML: 16 for
#: the base64 indices, 16 per vertex, about half a vertex per face once unused ones go).
DEFAULT_VIEW_FACES = 100_000
#: No displayed mesh is decimated below this many faces, whatever the budget.
MIN_FACES_PER_MESH = 200
VIEW_MODES = ("visual", "collision")


# --- equivalent-inertia boxes -----------------------------------------------------------
def box_lengths(moments: np.ndarray, mass: float) -> tuple[np.ndarray, bool]:
    """Full side lengths (m) of the uniform box with principal ``moments`` and ``mass``.

    A box with sides a, b, c has ``I1 = m (b^2 + c^2) / 12`` etc., so
    ``a = sqrt(6 (I2 + I3 - I1) / m)``. A tensor that breaks the triangle inequality
    (``I2 + I3 < I1``) has no such box: the negative radicand is clipped to 0 and the
    second value returned is True.
    """
    i = np.asarray(moments, dtype=np.float64)
    if i.shape != (3,):
        raise ValueError(f"moments must have shape (3,), got {i.shape}")
    if not mass > 0:
        raise ValueError("mass must be positive")
    radicand = 6.0 * (i.sum() - 2.0 * i) / mass
    # Round-off on flat bodies makes an exact 0 slightly negative: not a broken tensor.
    slack = 1e-9 * max(float(np.abs(radicand).max()), np.finfo(float).tiny)
    clipped = bool(np.any(radicand < -slack))
    return np.sqrt(np.clip(radicand, 0.0, None)), clipped


@dataclass(frozen=True, eq=False)
class InertiaBox:
    """An equivalent-inertia box in the world frame.

    center : (3,) float, m. axes : (3, 3) float, columns are the box's edge directions
    (principal axes). lengths : (3,) float, full side lengths along those axes, m.
    clipped : the tensor breaks the triangle inequality (a side was clipped to 0).
    """

    link: str
    source: str  # "existing" | "recomputed"
    mass: float
    center: np.ndarray
    axes: np.ndarray
    lengths: np.ndarray
    clipped: bool

    def triangles(self) -> tuple[np.ndarray, np.ndarray]:
        """(8, 3) corner positions and (12, 3) triangle indices."""
        signs = np.array([[x, y, z] for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)],
                         dtype=np.float64)
        corners = self.center + (signs * (0.5 * self.lengths)) @ self.axes.T
        return corners, _BOX_FACES

    def edge_polyline(self) -> np.ndarray:
        """(36, 3) the 12 edges as point pairs, each followed by a NaN row (a line break)."""
        corners, _ = self.triangles()
        out = np.full((len(_BOX_EDGES), 3, 3), np.nan)
        out[:, 0], out[:, 1] = corners[_BOX_EDGES[:, 0]], corners[_BOX_EDGES[:, 1]]
        return out.reshape(-1, 3)


# Corner k has signs (x, y, z) = bits (4, 2, 1) of k; two triangles per side.
_BOX_FACES = np.array([
    [0, 1, 3], [0, 3, 2], [4, 6, 7], [4, 7, 5],  # x = -1, x = +1
    [0, 4, 5], [0, 5, 1], [2, 3, 7], [2, 7, 6],  # y = -1, y = +1
    [0, 2, 6], [0, 6, 4], [1, 5, 7], [1, 7, 3],  # z = -1, z = +1
], dtype=np.int32)
# Two corners share an edge when their signs differ in exactly one bit.
_BOX_EDGES = np.array([(k, k | bit) for k in range(8) for bit in (4, 2, 1) if not k & bit])


def equivalent_box(mp: MassProperties, link_pose: np.ndarray, link: str, source: str,
                   ) -> InertiaBox:
    """The equivalent-inertia box of ``mp`` (given in the link frame) in the world frame."""
    moments, axes = mp.principal()
    lengths, clipped = box_lengths(moments, mp.mass)
    rot = np.asarray(link_pose)[:3, :3]
    center = rot @ mp.com + np.asarray(link_pose)[:3, 3]
    return InertiaBox(link, source, mp.mass, center, rot @ axes, lengths, clipped)


def existing_mass_properties(inertial: Inertial | None) -> tuple[MassProperties | None, str]:
    """The inertial as written, in the link frame, or None and why it is not usable."""
    if inertial is None:
        return None, "no <inertial>"
    values = (inertial.mass, inertial.ixx, inertial.ixy, inertial.ixz, inertial.iyy,
              inertial.iyz, inertial.izz)
    if not all(np.isfinite(v) for v in values):
        return None, "invalid: non-finite values"
    if not inertial.mass > 0:
        return None, f"invalid: mass {inertial.mass:g} kg is not positive"
    try:
        mp = MassProperties(inertial.mass, np.array(inertial.origin.xyz),
                            inertial.tensor_in_link())
    except ValueError as exc:
        return None, f"invalid: {exc}"
    return mp, ""


# --- display geometry -------------------------------------------------------------------
@dataclass(frozen=True, eq=False)
class ViewMesh:
    """One displayed ``<visual>``/``<collision>`` in the world frame, decimated.

    vertices : (n, 3) float32, m. faces : (m, 3) int32. source_faces : faces before
    decimation. method : how it was reduced ("as is", "quadric decimation", ...).
    """

    link: str
    label: str
    vertices: np.ndarray
    faces: np.ndarray
    source_faces: int
    method: str


@dataclass(frozen=True, eq=False)
class Scene:
    poses: dict[str, np.ndarray]
    meshes: tuple[ViewMesh, ...]
    notes: tuple[str, ...]

    @property
    def face_count(self) -> int:
        return sum(len(m.faces) for m in self.meshes)


def decimate(vertices: np.ndarray, faces: np.ndarray, max_faces: int,
             ) -> tuple[np.ndarray, np.ndarray, str]:
    """Reduce a triangle mesh to at most about ``max_faces`` faces, for display only.

    Quadric decimation (trimesh + fast-simplification) when it works; otherwise an evenly
    spaced subset of the faces (holes, but the shape stays recognisable).
    """
    if len(faces) <= max_faces:
        return (*used_only(vertices, faces), "as is")
    import trimesh

    try:
        mesh = trimesh.Trimesh(vertices, faces, process=True)  # merges duplicate vertices
        small = mesh.simplify_quadric_decimation(face_count=max_faces)
        if 0 < len(small.faces) <= 1.5 * max_faces:
            return (*used_only(np.asarray(small.vertices), np.asarray(small.faces)),
                    "quadric decimation")
    except Exception:  # missing fast-simplification or a mesh it cannot handle
        pass
    keep = np.linspace(0, len(faces) - 1, max_faces).astype(np.int64)
    return (*used_only(vertices, faces[keep]), "face subset (decimation unavailable)")


def used_only(vertices: np.ndarray, faces: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The distinct vertices ``faces`` use and the faces renumbered into them, for display.

    A mesh file's other vertices (other objects, points, a decimation's leftovers) and
    repeated copies of one position (a triangle soup such as STL) would only make the page
    bigger: positions equal in float32, the precision drawn, are one vertex.
    """
    faces = np.asarray(faces, dtype=np.int64)
    points = np.ascontiguousarray(np.asarray(vertices, dtype=np.float32)[faces.reshape(-1)])
    rows = points.view(np.dtype((np.void, points.dtype.itemsize * 3))).reshape(-1)
    _, first, inverse = np.unique(rows, return_index=True, return_inverse=True)
    return np.asarray(vertices)[faces.reshape(-1)[first]], inverse.reshape(faces.shape)


#: Segments around the axis of a drawn round primitive, and rings from pole to pole of a
#: sphere (a capsule's ends share them): coarse, the shape only has to be recognisable.
ROUND_SECTIONS = 24
SPHERE_RINGS = 12


def primitive_triangles(shape: Shape) -> tuple[np.ndarray, np.ndarray]:
    """Coarse triangles of a primitive in its geometry frame, outward-facing: (n, 3) float
    vertices (m) and (k, 3) int faces. Made here with numpy (no mesh library to import:
    a warm report draws its primitives without one)."""
    if isinstance(shape, Box):
        signs = np.array([[x, y, z] for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)],
                         dtype=np.float64)
        return signs * (0.5 * np.asarray(shape.size, dtype=np.float64)), _BOX_FACES.copy()
    if isinstance(shape, Cylinder):
        r, h = shape.radius, shape.length / 2
        return revolved(np.array([[0.0, -h], [r, -h], [r, h], [0.0, h]]))
    if isinstance(shape, Cone):  # centred, apex at +length/2 (the model's convention)
        r, h = shape.radius, shape.length / 2
        return revolved(np.array([[0.0, -h], [r, -h], [0.0, h]]))
    if isinstance(shape, Sphere):
        return revolved(_half_circle(shape.radius, SPHERE_RINGS))
    if isinstance(shape, Ellipsoid):
        v, f = revolved(_half_circle(1.0, SPHERE_RINGS))
        return v * np.asarray(shape.radii, dtype=np.float64), f
    if isinstance(shape, Capsule):
        arc = _half_circle(shape.radius, SPHERE_RINGS)
        half = SPHERE_RINGS // 2  # the equator is the last point of the lower end
        lower = arc[:half + 1] - [0.0, shape.length / 2]
        upper = arc[half:] + [0.0, shape.length / 2]
        return revolved(np.vstack([lower, upper]))
    raise TypeError(f"not a primitive: {shape!r}")


def _half_circle(radius: float, rings: int) -> np.ndarray:
    """(rings + 1, 2) (r, z) from the south pole to the north pole."""
    theta = np.linspace(0.0, np.pi, rings + 1)
    return radius * np.column_stack([np.sin(theta), -np.cos(theta)])


def revolved(profile: np.ndarray, sections: int = ROUND_SECTIONS,
             ) -> tuple[np.ndarray, np.ndarray]:
    """The closed surface swept by turning ``profile`` about z.

    profile : (m, 2) float, (r, z) points from the bottom of the axis to its top; its first
    and last points have r = 0 (poles, one vertex each), the others r > 0 (a ring of
    ``sections`` vertices each). Faces are wound outward (counter-clockwise seen from
    outside).
    """
    profile = np.asarray(profile, dtype=np.float64)
    if profile.ndim != 2 or profile.shape[1] != 2 or len(profile) < 3:
        raise ValueError(f"profile must have shape (m >= 3, 2), got {profile.shape}")
    phi = np.linspace(0.0, 2 * np.pi, sections, endpoint=False)
    ring = np.column_stack([np.cos(phi), np.sin(phi)])
    inner = profile[1:-1]
    rings = np.concatenate([
        np.column_stack([r * ring, np.full(sections, z)]) for r, z in inner])
    bottom, top = len(rings), len(rings) + 1
    vertices = np.vstack([rings, [[0.0, 0.0, profile[0, 1]], [0.0, 0.0, profile[-1, 1]]]])
    k = np.arange(sections)
    nxt = (k + 1) % sections
    faces = [np.column_stack([np.full(sections, bottom), nxt, k])]  # bottom fan
    for i in range(len(inner) - 1):
        a, b = i * sections, (i + 1) * sections
        faces.append(np.column_stack([a + k, a + nxt, b + nxt]))
        faces.append(np.column_stack([a + k, b + nxt, b + k]))
    last = (len(inner) - 1) * sections
    faces.append(np.column_stack([np.full(sections, top), last + k, last + nxt]))  # top fan
    return vertices, np.concatenate(faces).astype(np.int64)


def view_refs(link: Link, mode: str):
    """The elements drawn for a link: ``mode``'s, or the other role's when it has none."""
    first, second = (link.visuals, link.collisions) if mode == "visual" else (
        link.collisions, link.visuals)
    return first or second


def display_plan(robot: Robot, view: str = "visual",
                 face_budget: int = DEFAULT_VIEW_FACES,
                 ) -> tuple[list[tuple[Link, GeometryRef]], int]:
    """The elements drawn (link, element) and the face cap of each mesh: the budget is
    shared evenly by the mesh elements (primitives are small anyway)."""
    if view not in VIEW_MODES:
        raise ValueError(f"view must be one of {VIEW_MODES}")
    items = [(link, ref) for link in robot.links for ref in view_refs(link, view)]
    n_mesh = sum(isinstance(ref.shape, Mesh) for _, ref in items)
    return items, max(MIN_FACES_PER_MESH, face_budget // max(n_mesh, 1))


def display_paths(robot: Robot, meshes: MeshLibrary, view: str = "visual",
                  face_budget: int = DEFAULT_VIEW_FACES) -> tuple[list[Path], int]:
    """The distinct mesh files :func:`build_scene` draws (those that resolve) and their
    face cap: what can be prepared ahead, in other processes (:func:`display_task`)."""
    items, cap = display_plan(robot, view, face_budget)
    urdf_dir = (robot.path or Path("robot.urdf")).parent
    paths: dict[Path, None] = {}
    for _, ref in items:
        if isinstance(ref.shape, Mesh):
            try:
                paths[meshes.resolve(ref.shape.filename, urdf_dir).resolve()] = None
            except UrdfInertiaError:
                continue  # build_scene says why
    return list(paths), cap


def load_display_modules() -> None:
    """Import what reads and decimates display meshes (trimesh, fast-simplification), so
    that worker processes forked afterwards inherit it instead of each importing it."""
    try:
        import fast_simplification  # noqa: F401
        import trimesh  # noqa: F401
    except ImportError:  # decimate falls back; a reader says what is missing
        pass


def display_task(path: str, max_faces: int, cap: int) -> tuple[dict, np.ndarray] | None:
    """The display copy of one mesh file (:func:`~urdfinertia.cache.library.display_entry`
    of :func:`decimate`), made in a worker process; None when the file cannot be read
    (:func:`build_scene` then reads it again and says why, in context)."""
    from urdfinertia.cache.library import display_entry
    from urdfinertia.mesh.read.load import load_mesh

    try:
        return display_entry(load_mesh(Path(path), max_faces), cap, decimate)
    except UrdfInertiaError:
        return None


def build_scene(robot: Robot, meshes: MeshLibrary, *, view: str = "visual",
                face_budget: int = DEFAULT_VIEW_FACES) -> Scene:
    """Poses and decimated display meshes of every link at the zero configuration.

    The face budget is shared evenly by the mesh elements (:func:`display_plan`).
    A display mesh that cannot be read is left out with a note: the report still shows
    the inertials.
    """
    items, cap = display_plan(robot, view, face_budget)
    poses, kin_notes = zero_configuration_poses(robot)
    notes = list(kin_notes)
    urdf_dir = (robot.path or Path("robot.urdf")).parent
    memo: dict[Path, tuple[np.ndarray, np.ndarray, int, str]] = {}
    out: list[ViewMesh] = []
    for link, ref in items:
        shape = ref.shape
        if isinstance(shape, Mesh):
            try:
                path = meshes.resolve(shape.filename, urdf_dir).resolve()
                if path not in memo:
                    v, f, n_faces, method = meshes.display(path, cap, decimate)
                    memo[path] = (v, f, n_faces, method)
            except UrdfInertiaError as exc:
                notes.append(f"link '{link.name}' {ref.label}: not drawn ({exc.cause})")
                continue
            v, f, n_source, method = memo[path]
            scale = np.asarray(shape.scale, dtype=np.float64)
            v = v * scale
            if np.prod(scale) < 0:
                f = f[:, ::-1]
        else:
            v, f = primitive_triangles(shape)
            n_source, method = len(f), "primitive"
        world = poses[link.name] @ ref.origin.matrix()
        v = v @ world[:3, :3].T + world[:3, 3]
        out.append(ViewMesh(link.name, ref.label, v.astype(np.float32), f.astype(np.int32),
                            n_source, method))
    return Scene(poses, tuple(out), tuple(notes))

