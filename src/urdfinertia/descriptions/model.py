"""The parts of a URDF this tool reads: one frozen dataclass per XML element.

Only what matters for inertia is kept. Every object remembers its source line so that
errors and reports can point at it.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from urdfinertia.findings import Finding
from urdfinertia.inertia.rotation import pose_matrix


@dataclass(frozen=True)
class Origin:
    """`<origin xyz rpy>`: a child frame's pose in its parent frame."""

    xyz: tuple[float, float, float] = (0.0, 0.0, 0.0)
    rpy: tuple[float, float, float] = (0.0, 0.0, 0.0)

    def matrix(self) -> np.ndarray:
        """(4, 4) homogeneous transform, rotation `Rz Ry Rx` (paper eq. 15)."""
        return pose_matrix(self.xyz, self.rpy)


@dataclass(frozen=True)
class Box:
    size: tuple[float, float, float]  # full side lengths, m


@dataclass(frozen=True)
class Cylinder:
    radius: float
    length: float  # full length along z, m


@dataclass(frozen=True)
class Sphere:
    radius: float


@dataclass(frozen=True)
class Capsule:
    radius: float
    length: float  # cylindrical section along z, m


@dataclass(frozen=True)
class Cone:
    radius: float  # of the base disc, m
    length: float  # full height along z, centred: base at -length/2, apex at +length/2


@dataclass(frozen=True)
class Ellipsoid:
    radii: tuple[float, float, float]  # semi-axes along x, y, z, m


@dataclass(frozen=True)
class Mesh:
    filename: str  # the URI as written
    scale: tuple[float, float, float] = (1.0, 1.0, 1.0)


Shape = Box | Cylinder | Sphere | Capsule | Cone | Ellipsoid | Mesh


@dataclass(frozen=True)
class GeometryRef:
    """One `<collision>` or `<visual>` of a link."""

    role: str  # "collision" | "visual"
    index: int  # position among the link's elements of that role
    name: str | None
    origin: Origin
    shape: Shape
    line: int | None = None
    density: float | None = None
    """What the description itself states about the element's material (MJCF geom
    `density`/`mass`, SDF `<density>`): kg/m^3 and kg, None when it says nothing.
    """
    mass: float | None = None
    relative: bool = False
    """`density`/`mass` only weigh the elements against each other: a link mass that is kept
    scales them all (MJCF: MuJoCo ignores geom materials of a body that has an `<inertial>`;
    their proportions still say where the mass is)
    """

    @property
    def label(self) -> str:
        """How reports name the element: `collision[0] 'name'`."""
        tag = f"{self.role}[{self.index}]"
        return f"{tag} '{self.name}'" if self.name else tag


@dataclass(frozen=True)
class Inertial:
    """`<inertial>` as written: inertia about `origin` along the origin's axes."""

    origin: Origin
    mass: float
    ixx: float
    ixy: float
    ixz: float
    iyy: float
    iyz: float
    izz: float
    line: int | None = None

    def tensor(self) -> np.ndarray:
        """(3, 3) tensor along the inertial origin's axes, URDF sign convention."""
        return np.array([
            [self.ixx, self.ixy, self.ixz],
            [self.ixy, self.iyy, self.iyz],
            [self.ixz, self.iyz, self.izz],
        ])

    def tensor_in_link(self) -> np.ndarray:
        """(3, 3) tensor about the CoM along the link frame's axes."""
        r = self.origin.matrix()[:3, :3]
        return r @ self.tensor() @ r.T


IMPLICIT_SOURCES = ("geoms", "colliders")
"""Where a simulator takes the mass properties of a link without a complete inertial."""


@dataclass(frozen=True)
class Implicit:
    """What the format's simulator computes for a link whose description gives no complete
    inertial: MuJoCo from the body's geoms (`inertiafromgeom`), a USD engine from the
    colliders (a MassAPI without mass or inertia).

    Attributes
    ----------
    source : {"geoms", "colliders"}
        What the simulator computes from.
    mass : float or None
        The mass the description states (a USD MassAPI's `physics:mass` without an
        inertia), kg; None when the simulator computes it too.
    density : float or None
        The density it states (kg/m^3), None when it states none.
    """

    source: str
    mass: float | None = None
    density: float | None = None


@dataclass(frozen=True)
class Link:
    name: str
    collisions: tuple[GeometryRef, ...] = ()
    visuals: tuple[GeometryRef, ...] = ()
    inertial: Inertial | None = None
    line: int | None = None
    inertia_geometry: tuple[GeometryRef, ...] | None = None
    """The elements the format itself counts for inertia, when it has such a rule (MJCF: geoms whose
    group is in `inertiagrouprange`); `--geometry auto` then uses them.
    """
    auto_inertial: bool = False
    """The format asks its simulator to compute this inertial at load time (SDFormat
    `<inertial auto="true">`): `fix --keep-auto` leaves it so.
    """
    read_only: str | None = None
    """Why this document cannot carry a new inertial for the link (MJCF: the body is defined in an
    included file, which `fix` does not write); None when it can.
    """
    implicit: Implicit | None = None
    """What the simulator computes where `inertial` is None (or, for MJCF
    `inertiafromgeom="true"`, instead of it); None when it computes nothing."""


@dataclass(frozen=True)
class Joint:
    name: str
    type: str
    parent: str
    child: str
    origin: Origin = field(default_factory=Origin)
    line: int | None = None
    axis: tuple[float, float, float] = (1.0, 0.0, 0.0)
    """The motion's axis in the joint frame (URDF's default x), for whole-robot statics."""
    axis_point: tuple[float, float, float] = (0.0, 0.0, 0.0)
    """A point the axis passes through, in the child link frame: URDF's is the frame's origin; an
    MJCF joint `pos` or an SDFormat joint `<pose>` may put it elsewhere.
    """
    lower: float | None = None
    """`<limit lower upper effort>`: m or rad, and N or N m; None when not stated."""
    upper: float | None = None
    effort: float | None = None
    mimic: tuple[str, float, float] | None = None
    """`<mimic joint multiplier offset>`: (joint, multiplier, offset), None when it has none."""


@dataclass(frozen=True)
class Robot:
    name: str
    links: tuple[Link, ...]
    joints: tuple[Joint, ...]
    path: Path | None = None
    format: str = "urdf"
    """The registered description format that read it ("urdf", ...): it also writes it."""
    findings: tuple[Finding, ...] = ()
    """What the reader has to say, in document order: elements dropped, values it could
    not read, how it read what other loaders refuse (each a finding with its rule)."""

    def findings_of(self, link: str | None) -> tuple[Finding, ...]:
        """The reader's findings about `link` (None: about the document)."""
        return tuple(f for f in self.findings if f.link == link)

    def link(self, name: str) -> Link:
        """The link called `name`.

        Parameters
        ----------
        name : str
            A link name.

        Returns
        -------
        Link
            The link.

        Raises
        ------
        KeyError
            When the robot has no such link.
        """
        for link in self.links:
            if link.name == name:
                return link
        raise KeyError(name)
