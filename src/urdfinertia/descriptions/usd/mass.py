"""A body's `PhysicsMassAPI` (and Newton's `NewtonMassAPI`) as the model's inertial,
and SimReady's rules on the authored values.

UsdPhysics: `physics:mass` (0 = not given), `physics:density` (0 = not given),
`physics:centerOfMass` in the body's local frame (-inf = not given),
`physics:diagonalInertia` (0, 0, 0 = not given) along `physics:principalAxes`, a
quaternion (w, x, y, z) in the body's local frame (0, 0, 0, 0 = identity). The tensor in
the body frame is `R diag(d) R^T` with R the rotation of the quaternion. Newton's
`newton:inertia` is the full tensor `[Ixx, Iyy, Izz, Ixy, Ixz, Iyz]` in the body frame
and overrides the two. Values are in stage units: kg / kilogramsPerUnit, m /
metersPerUnit.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from urdfinertia.descriptions.model import Inertial, Origin
from urdfinertia.descriptions.usd.frames import matrix_rpy, quat_matrix, vec3
from urdfinertia.rules import Rule

QUAT_NORM_TOL = 1e-4
"""|q| - 1 beyond which `principalAxes` is not a unit quaternion (float32 round-off of a
normalised quaternion is ~1e-7)
"""
NEWTON_RTOL = 1e-5
"""Relative disagreement of `newton:inertia` with MassAPI's tensor tolerated (float32)"""


@dataclass(frozen=True)
class Authored:
    """What a prim's MassAPI authors, SI units; None where it gives nothing."""

    mass: float | None
    density: float | None
    com: np.ndarray | None
    diagonal: np.ndarray | None
    axes: tuple[float, float, float, float] | None
    newton: np.ndarray | None  # (3, 3) tensor, or None
    newton_applied: bool

    @property
    def complete(self) -> bool:
        """Mass and inertia both given: the engine computes nothing."""
        return self.mass is not None and self.mass != 0 and (
            self.diagonal is not None or self.newton is not None)


def _get(prim: Any, name: str) -> Any:
    """An authored value; float32 values as the decimal they were written as (3.7, not
    3.700000047683716), so that comparisons see the author's number."""
    attr = prim.GetAttribute(name)
    if not attr or not attr.HasAuthoredValue():
        return None
    value = attr.Get()
    type_name = str(attr.GetTypeName())
    if value is None or not ("float" in type_name or type_name.endswith("f")):
        return value
    if type_name.startswith("quat"):
        return (_decimal(value.GetReal()), *map(_decimal, value.GetImaginary()))
    if isinstance(value, float):
        return _decimal(value)
    return tuple(_decimal(v) for v in value)


def _decimal(v: float) -> float:
    return float(str(np.float32(v)))


def applied(prim: Any) -> tuple[str, ...]:
    """The API schemas applied to a prim, as authored (known to this pxr or not)."""
    return tuple(str(s) for s in prim.GetPrimTypeInfo().GetAppliedAPISchemas())


def authored(prim: Any, mpu: float, kpu: float) -> Authored:
    """What a prim's MassAPI (and Newton's attributes) author, in SI units.

    Parameters
    ----------
    prim : Usd.Prim
        A rigid body or collider prim.
    mpu : float
        The stage's metres per unit.
    kpu : float
        The stage's kilograms per unit.

    Returns
    -------
    Authored
        The authored mass, density, CoM, diagonal inertia and principal axes.
    """
    schemas = applied(prim)
    mass = _get(prim, "physics:mass")
    density = _get(prim, "physics:density")
    com = _get(prim, "physics:centerOfMass")
    diag = _get(prim, "physics:diagonalInertia")
    axes = _get(prim, "physics:principalAxes")
    newton = _get(prim, "newton:inertia")
    com_a = np.asarray(com, dtype=np.float64) * mpu if com is not None else None
    if com_a is not None and np.all(np.isneginf(com_a)):
        com_a = None  # the schema's "compute it" sentinel
    diag_a = np.asarray(diag, dtype=np.float64) * kpu * mpu * mpu if diag is not None else None
    if diag_a is not None and not np.any(diag_a):
        diag_a = None
    quat = None
    if axes is not None:
        w, (x, y, z) = (axes[0], axes[1:]) if isinstance(axes, tuple) else \
            (axes.GetReal(), axes.GetImaginary())
        quat = (float(w), float(x), float(y), float(z))
    tensor = None
    if newton is not None and len(newton) == 6:
        xx, yy, zz, xy, xz, yz = (float(v) * kpu * mpu * mpu for v in newton)
        tensor = np.array([[xx, xy, xz], [xy, yy, yz], [xz, yz, zz]])
        if not np.any(tensor):
            tensor = None  # zeros: no opinion, as the empty array
    return Authored(
        mass=float(mass) * kpu if mass is not None else None,
        density=float(density) * kpu / mpu**3 if density is not None else None,
        com=com_a, diagonal=diag_a, axes=quat, newton=tensor,
        newton_applied="NewtonMassAPI" in schemas)


def principal_rotation(axes: tuple[float, float, float, float] | None) -> np.ndarray:
    """Rotation of `principalAxes`; the zero quaternion (the default) is the identity."""
    if axes is None or not any(axes):
        return np.eye(3)
    return quat_matrix(axes)


def inertial(a: Authored) -> Inertial | None:
    """The model's inertial of a complete MassAPI (None when the engine computes any of
    mass or inertia). MassAPI's diagonal and axes win over `newton:inertia` (every
    UsdPhysics engine reads them; Newton's own must agree, `rule_problems`)."""
    if not a.complete or a.mass is None:
        return None
    com = a.com if a.com is not None else np.zeros(3)
    if a.diagonal is not None:
        try:
            rot = principal_rotation(a.axes)
        except ValueError:
            rot = np.eye(3)
        d = a.diagonal
        return Inertial(origin=Origin(xyz=vec3(com), rpy=matrix_rpy(rot)),
                        mass=a.mass, ixx=float(d[0]), ixy=0.0, ixz=0.0, iyy=float(d[1]),
                        iyz=0.0, izz=float(d[2]))
    t = a.newton
    assert t is not None
    return Inertial(origin=Origin(xyz=vec3(com)), mass=a.mass,
                    ixx=float(t[0, 0]), ixy=float(t[0, 1]), ixz=float(t[0, 2]),
                    iyy=float(t[1, 1]), iyz=float(t[1, 2]), izz=float(t[2, 2]))


def rule_problems(a: Authored) -> list[tuple[Rule, str]]:
    """SimReady's mass rules on what is authored: (rule, cause) pairs."""
    out = []
    if a.mass is not None and a.mass < 0:
        out.append((Rule.USD_NEGATIVE_MASS, f"physics:mass is {a.mass:.6g} kg"))
    if a.density is not None and a.density < 0:
        out.append((Rule.USD_NEGATIVE_DENSITY, f"physics:density is {a.density:.6g} kg/m^3"))
    if a.density is not None and a.density > 0 and not (a.mass is not None and a.mass > 0):
        out.append((Rule.USD_DENSITY_WITHOUT_MASS,
                    f"physics:density {a.density:.6g} kg/m^3 but no physics:mass: the engine "
                    "derives the mass from the collision shapes' volume"))
    if a.diagonal is not None:
        d = a.diagonal
        if np.any(d < 0) or not np.all(np.isfinite(d)):
            out.append((Rule.USD_DIAGONAL_INERTIA_INVALID,
                        f"physics:diagonalInertia {_fmt(d)} has a negative or non-finite "
                        "moment"))
        elif d[0] + d[1] < d[2] * (1 - 1e-6) or d[0] + d[2] < d[1] * (1 - 1e-6) \
                or d[1] + d[2] < d[0] * (1 - 1e-6):
            out.append((Rule.USD_DIAGONAL_INERTIA_INVALID,
                        f"physics:diagonalInertia {_fmt(d)} violates the triangle "
                        "inequality (A + B >= C)"))
    if a.axes is not None and any(a.axes):
        norm = float(np.linalg.norm(a.axes))
        if not np.isfinite(norm) or abs(norm - 1.0) > QUAT_NORM_TOL:
            out.append((Rule.USD_PRINCIPAL_AXES_NOT_UNIT,
                        f"physics:principalAxes {_fmt(np.array(a.axes))} has norm {norm:.6g}, "
                        "not 1"))
    if a.newton is not None and a.diagonal is not None:
        try:
            rot = principal_rotation(a.axes)
            mass_api = rot @ np.diag(a.diagonal) @ rot.T
        except ValueError:
            mass_api = None
        scale = max(float(np.abs(a.newton).max()), float(np.abs(a.diagonal).max()), 1e-300)
        if mass_api is not None and np.abs(mass_api - a.newton).max() > NEWTON_RTOL * scale:
            out.append((Rule.USD_NEWTON_MASS_DISAGREES,
                        "newton:inertia and physics:diagonalInertia/principalAxes give "
                        "different tensors (Newton uses newton:inertia, other engines the "
                        "MassAPI)"))
    return out


def _fmt(v: np.ndarray) -> str:
    return "(" + ", ".join(f"{float(x):.6g}" for x in v) + ")"
