"""Can a link's written inertial come from mass inside the link's own geometry?

The triangle inequality only says that some nonnegative density exists somewhere. This
check says whether one exists inside the minimum-volume ellipsoid that holds every
``<collision>`` and ``<visual>`` of the link (the test of
:mod:`urdfinertia.inertia.realizable`: exact, no solver). Since the geometry lies inside
that ellipsoid, a written inertial that fails the test cannot belong to the geometry,
however its mass is spread; the finding says by how much the ellipsoid would have to grow
(its scale about its centre) to hold it.

With ``method="hull"`` the region is the geometry's convex hull instead, a tighter one
(:mod:`urdfinertia.body.hull`: an LP with HiGHS, a proof either way, slower); the
finding then reports the scale of the hull about its centroid.

Also here: for links without geometry, the radius of gyration their tensor implies
(``sqrt(trace / 2m)``, the RMS distance of the mass from the CoM), which no robot link
has beyond :data:`GYRATION_LIMIT`.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from urdfinertia.body.bounds import BoundsCache
from urdfinertia.body.hull import HullScale, convex_hull, hull_scale
from urdfinertia.cache.library import MeshLibrary
from urdfinertia.descriptions.inertial import RawInertial
from urdfinertia.descriptions.model import (
    Box,
    Capsule,
    Cone,
    Cylinder,
    Ellipsoid,
    GeometryRef,
    Link,
    Mesh,
    Shape,
    Sphere,
)
from urdfinertia.errors import UrdfInertiaError
from urdfinertia.findings import Finding
from urdfinertia.inertia.realizable import Ellipsoid as Region
from urdfinertia.inertia.realizable import bounding_ellipsoid, ellipsoid_scale
from urdfinertia.inertia.validity import is_placeholder
from urdfinertia.rules import Rule

#: A needed scale above this is a warning: no density inside the geometry gives the
#: written values (the ellipsoid holds the geometry, so the geometry cannot either).
#: Above 1 the proof is already there; the 5 % leave room for a description's geometry
#: being a little smaller than the part its CAD inertial came from (Panda's fingers need
#: 1.01, its third link 1.02).
SCALE_WARN = 1.05
#: Above this the mass would have to lie several of the part's own sizes away from it (a
#: tensor or CoM for another part, or a unit slip): the message says so. Still a warning,
#: like the other checks against the geometry (the geometry may be a stand-in: a marker,
#: a simplified hull); ``check --strict`` fails on it.
SCALE_ERROR = 3.0
#: A radius of gyration (sqrt(trace / 2m), m) above this on a link without geometry is
#: implausible: no robot link spreads its mass RMS a metre from its CoM.
GYRATION_LIMIT = 1.0

#: The regions a link's inertial can be tested in: the geometry's bounding ellipsoid (exact,
#: no solver: the default), or its convex hull (an LP; slower).
METHODS = ("ellipsoid", "hull")

#: Polygon sides of the circumscribed prisms standing in for round primitives.
_SIDES = 24


@dataclass(frozen=True, eq=False)
class Realizability:
    """The test of one link's written inertial against its geometry.

    scale : the scale of ``ellipsoid`` (about its centre) that would just hold the
        written body; <= 1: realizable in it; inf: by no nonnegative density at all.
    ellipsoid : the minimum-volume ellipsoid of the link's geometry, link frame.
    hull : with ``method="hull"``, the scale of the geometry's convex hull about its
        centroid that would just hold the body, bracketed (None: not asked for, or the
        body is realizable nowhere).
    """

    link: str
    scale: float
    ellipsoid: Region
    hull: HullScale | None = None

    @property
    def method(self) -> str:
        return "ellipsoid" if self.hull is None else "hull"

    @property
    def realizable(self) -> bool:
        """No finding: within :data:`SCALE_WARN` of the region (for the hull: not proved
        to need more)."""
        if self.hull is not None:
            return self.hull.low <= SCALE_WARN
        return self.scale <= SCALE_WARN

    @property
    def needed(self) -> float:
        """The scale the finding reports: the ellipsoid's, or the hull's bracket's upper
        end (its proved lower end when no upper one was found)."""
        return self.scale if self.hull is None else self.hull.scale


def _ring(radius: float, z: float) -> np.ndarray:
    """A regular polygon circumscribing the circle of ``radius`` at height ``z``."""
    a = np.linspace(0.0, 2 * np.pi, _SIDES, endpoint=False)
    r = radius / np.cos(np.pi / _SIDES)
    return np.column_stack([r * np.cos(a), r * np.sin(a), np.full(_SIDES, z)])


def _ball(radius: float, centre_z: float = 0.0, cap: int = 0) -> np.ndarray:
    """Points whose hull holds the ball (``cap`` +1/-1: only that hemisphere)."""
    # rings at latitudes of a circumscribed polyhedron: each ring polygon circumscribes its
    # circle of the ball grown by 1/cos of half the latitude step
    steps = 12
    lat = np.linspace(-np.pi / 2, np.pi / 2, steps + 1)
    grow = 1.0 / np.cos(np.pi / (2 * steps))
    rows = []
    for phi in lat:
        if cap and np.sign(phi) == -cap and phi != 0:
            continue
        rr = radius * grow * np.cos(phi)
        z = radius * grow * np.sin(phi)
        rows.append(_ring(rr, centre_z + z) if rr > 1e-12 * radius
                    else np.array([[0.0, 0.0, centre_z + z]]))
    return np.vstack(rows)


def primitive_points(shape: Shape) -> np.ndarray:
    """(n, 3) points whose convex hull holds the primitive (slightly larger: round shapes
    become circumscribed polyhedra, within 1 % of their size), geometry frame."""
    if isinstance(shape, Box):
        h = np.asarray(shape.size, dtype=np.float64) / 2
        return np.array([[x, y, z] for x in (-h[0], h[0]) for y in (-h[1], h[1])
                         for z in (-h[2], h[2])])
    if isinstance(shape, Cylinder):
        return np.vstack([_ring(shape.radius, -shape.length / 2),
                          _ring(shape.radius, shape.length / 2)])
    if isinstance(shape, Cone):
        return np.vstack([_ring(shape.radius, -shape.length / 2),
                          [[0.0, 0.0, shape.length / 2]]])
    if isinstance(shape, Sphere):
        return _ball(shape.radius)
    if isinstance(shape, Capsule):
        return np.vstack([_ball(shape.radius, -shape.length / 2, cap=-1),
                          _ball(shape.radius, shape.length / 2, cap=1)])
    if isinstance(shape, Ellipsoid):
        return _ball(1.0) * np.asarray(shape.radii, dtype=np.float64)
    raise TypeError(f"not a primitive: {shape!r}")


def geometry_points(refs: tuple[GeometryRef, ...], cache: BoundsCache,
                    urdf_dir: Path) -> np.ndarray:
    """(n, 3) points in the link frame whose convex hull holds every element of ``refs``."""
    out = []
    for ref in refs:
        shape = ref.shape
        if isinstance(shape, Mesh):
            pts = cache.vertices(shape.filename, urdf_dir) * np.asarray(shape.scale)
        else:
            pts = primitive_points(shape)
        pose = ref.origin.matrix()
        out.append(pts @ pose[:3, :3].T + pose[:3, 3])
    return np.vstack(out) if out else np.zeros((0, 3))


def link_realizability(link: Link, cache: BoundsCache, urdf_dir: Path,
                       method: str = "ellipsoid") -> Realizability | None:
    """The test for ``link`` (None: no geometry, or a written inertial that is not a body
    with positive finite mass, or a placeholder tensor: the value checks report those).
    ``method``: one of :data:`METHODS`.

    Raises UrdfInertiaError when a mesh cannot be read.
    """
    refs = link.collisions + link.visuals
    if link.inertial is None or not refs:
        return None
    raw = RawInertial.from_inertial(link.inertial)
    if not (raw.mass_ok and raw.com_ok and np.all(np.isfinite(raw.inertia))):
        return None
    if not np.any(raw.inertia) or is_placeholder(raw.inertia):
        return None  # a point mass or a placeholder: the value checks report it
    if method not in METHODS:
        raise ValueError(f"method must be one of {METHODS}, got {method!r}")
    points = geometry_points(refs, cache, urdf_dir)
    region = bounding_ellipsoid(points)
    scale = ellipsoid_scale(raw.mass, raw.com, raw.inertia, region)
    hull = None
    if method == "hull" and np.isfinite(scale):
        hull = hull_scale(raw.mass, raw.com, raw.inertia, convex_hull(points))
    return Realizability(link.name, scale, region, hull)


def realizability_findings(link: Link, cache: BoundsCache, urdf_dir: Path,
                           method: str = "ellipsoid") -> list[Finding]:
    """UI210 when the written inertial needs mass outside the link's geometry (its bounding
    ellipsoid, or with ``method="hull"`` its convex hull); UI211 when a link without
    geometry has an implausible radius of gyration."""
    if not (link.collisions or link.visuals):
        return gyration_findings(link)
    try:
        found = link_realizability(link, cache, urdf_dir, method)
    except (UrdfInertiaError, ValueError):
        return []  # unreadable geometry: the geometry checks report it
    if found is None or found.realizable:
        return []
    line = link.inertial.line if link.inertial is not None else None
    axes = ", ".join(f"{2 * a:.3g}" for a in found.ellipsoid.semi_axes)
    if not np.isfinite(found.scale):
        return []  # no density anywhere: the triangle inequality finding says so
    far = (": the mass would lie outside the part by several of its sizes"
           if found.needed > SCALE_ERROR else "")
    if found.hull is None:
        return [Finding(Rule.NOT_REALIZABLE, link.name,
                        f"no mass inside the geometry gives this inertial: its bounding "
                        f"ellipsoid (axes {axes} m) would have to be {found.scale:.3g}x as "
                        f"large to hold a body with the written CoM and tensor{far}", line)]
    h = found.hull
    bracket = (f"between {h.low:.4g}x and {h.high:.4g}x" if np.isfinite(h.high)
               else f"more than {h.low:.4g}x")
    return [Finding(Rule.NOT_REALIZABLE, link.name,
                    f"no mass inside the geometry's convex hull gives this inertial (method: "
                    f"convex hull, an LP certificate, HiGHS): the hull would have to be "
                    f"{bracket} as large about its centroid to hold a body with the written "
                    f"CoM and tensor{far}", line)]


def gyration_findings(link: Link) -> list[Finding]:
    """A link without geometry whose tensor spreads its mass implausibly far (UI211)."""
    if link.inertial is None:
        return []
    raw = RawInertial.from_inertial(link.inertial)
    if not (raw.mass_ok and np.all(np.isfinite(raw.inertia))):
        return []
    radius = float(np.sqrt(max(np.trace(raw.inertia), 0.0) / (2 * raw.mass)))
    if radius <= GYRATION_LIMIT:
        return []
    return [Finding(Rule.GYRATION_IMPLAUSIBLE, link.name,
                    f"{raw.mass:.4g} kg with trace {np.trace(raw.inertia):.4g} kg m^2: its mass "
                    f"would lie {radius:.3g} m (RMS) from its CoM, beyond any robot link's "
                    f"{GYRATION_LIMIT:g} m (the link has no geometry to check against)",
                    link.inertial.line)]


def robot_realizability(links: tuple[Link, ...], meshes: MeshLibrary,
                        urdf_dir: Path, method: str = "ellipsoid") -> list[Finding]:
    """:func:`realizability_findings` of every link, in link order."""
    cache = BoundsCache(meshes)
    out: list[Finding] = []
    for link in links:
        out.extend(realizability_findings(link, cache, urdf_dir, method))
    return out
