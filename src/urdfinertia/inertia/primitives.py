"""Closed-form mass properties of URDF/SDF primitives, each in its own frame.

Pure numpy. Every body is centred at the origin of its own frame, which is the frame of
the URDF `<geometry>`: boxes take *full* side lengths, cylinders and capsules lie along
z with *full* length (for a capsule: the length of the cylindrical section between the
two cap centres, as in SDF and ROS 2 URDF). All take a density in kg/m^3.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from urdfinertia.inertia.massprops import MassProperties


def _positive(name: str, *values: float) -> None:
    for v in values:
        if not (np.isfinite(v) and v > 0):
            raise ValueError(f"{name} must be positive and finite, got {v!r}")


def box(size: ArrayLike, density: float) -> MassProperties:
    """A solid cuboid (paper eq. 39).

    Parameters
    ----------
    size : (3,) float
        The full side lengths `(a, b, c)` along x, y, z, m.
    density : float
        kg/m^3.

    Returns
    -------
    MassProperties
        The body in its own frame (CoM at the origin).
    """
    a, b, c = np.asarray(size, dtype=np.float64)
    _positive("box size", a, b, c)
    m = density * a * b * c
    diag = m / 12.0 * np.array([b * b + c * c, a * a + c * c, a * a + b * b])
    return MassProperties(m, np.zeros(3), np.diag(diag))


def cylinder(radius: float, length: float, density: float) -> MassProperties:
    """A solid cylinder along z.

    Parameters
    ----------
    radius : float
        m.
    length : float
        The full length, m.
    density : float
        kg/m^3.

    Returns
    -------
    MassProperties
        The body in its own frame (CoM at the origin).
    """
    _positive("cylinder radius/length", radius, length)
    m = density * np.pi * radius**2 * length
    ixx = m * (3.0 * radius**2 + length**2) / 12.0
    return MassProperties(m, np.zeros(3), np.diag([ixx, ixx, 0.5 * m * radius**2]))


def sphere(radius: float, density: float) -> MassProperties:
    """A solid sphere.

    Parameters
    ----------
    radius : float
        m.
    density : float
        kg/m^3.

    Returns
    -------
    MassProperties
        The body in its own frame (CoM at the origin).
    """
    _positive("sphere radius", radius)
    m = density * 4.0 / 3.0 * np.pi * radius**3
    return MassProperties(m, np.zeros(3), np.eye(3) * 0.4 * m * radius**2)


def ellipsoid(radii: ArrayLike, density: float) -> MassProperties:
    """A solid ellipsoid.

    Parameters
    ----------
    radii : (3,) float
        The semi-axes `(a, b, c)` along x, y, z, m.
    density : float
        kg/m^3.

    Returns
    -------
    MassProperties
        The body in its own frame (CoM at the origin).
    """
    a, b, c = np.asarray(radii, dtype=np.float64)
    _positive("ellipsoid radii", a, b, c)
    m = density * 4.0 / 3.0 * np.pi * a * b * c
    diag = m / 5.0 * np.array([b * b + c * c, a * a + c * c, a * a + b * b])
    return MassProperties(m, np.zeros(3), np.diag(diag))


def capsule(radius: float, length: float, density: float) -> MassProperties:
    """Capsule along z: a cylinder of `radius` and `length` plus two hemispherical caps.

    Each cap's centre of mass lies 3r/8 beyond the cylinder end, which gives the
    `3 L r / 8` cross term below.

    Parameters
    ----------
    radius : float
        m.
    length : float
        The length of the cylindrical section between the two cap centres, m (0: a sphere).
    density : float
        kg/m^3.

    Returns
    -------
    MassProperties
        The body in its own frame (CoM at the origin).
    """
    _positive("capsule radius", radius)
    if not (np.isfinite(length) and length >= 0):
        raise ValueError(f"capsule length must be >= 0 and finite, got {length!r}")
    r, h = radius, length
    m_cyl = density * np.pi * r * r * h
    m_caps = density * 4.0 / 3.0 * np.pi * r**3  # both hemispheres together
    izz = m_cyl * r * r / 2.0 + m_caps * 2.0 * r * r / 5.0
    ixx = m_cyl * (r * r / 4.0 + h * h / 12.0) + m_caps * (
        2.0 * r * r / 5.0 + h * h / 4.0 + 3.0 * h * r / 8.0
    )
    return MassProperties(m_cyl + m_caps, np.zeros(3), np.diag([ixx, ixx, izz]))


def cone(radius: float, height: float, density: float) -> MassProperties:
    """Solid right circular cone along z, centred as OpenUSD's `UsdGeom.Cone`: base disc
    of `radius` at z = -height/2, apex at z = +height/2.

    The centre of mass lies a quarter of the height above the base (z = -height/4);
    about it `Izz = 3/10 m r^2` and `Ixx = Iyy = m (3/20 r^2 + 3/80 h^2)`.

    Parameters
    ----------
    radius : float
        The base's radius, m.
    height : float
        m.
    density : float
        kg/m^3.

    Returns
    -------
    MassProperties
        The body in its own frame, its CoM at z = -height/4.
    """
    _positive("cone radius/height", radius, height)
    r, h = radius, height
    m = density * np.pi * r * r * h / 3.0
    ixx = m * (3.0 * r * r / 20.0 + 3.0 * h * h / 80.0)
    return MassProperties(m, np.array([0.0, 0.0, -h / 4.0]),
                          np.diag([ixx, ixx, 0.3 * m * r * r]))
