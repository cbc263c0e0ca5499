"""The rules on the written values alone: missing, not finite, not positive, not a body's
tensor, absurd magnitudes, placeholders.

Pure over the evidence (:mod:`urdfinertia.body.evidence`): no geometry is read here. Every
number is judged as written, NaN and 1e308 included, without an exception escaping: a
value that breaks the arithmetic is itself the finding.
"""

from __future__ import annotations

import math

import numpy as np

from urdfinertia.body.evidence import LinkEvidence
from urdfinertia.descriptions.inertial import RawInertial
from urdfinertia.findings import Finding
from urdfinertia.inertia.validity import TensorDiagnosis, diagnose_tensor, is_placeholder
from urdfinertia.rules import Rule

#: A link heavier than this (kg) is a unit slip (mm^3 taken as m^3 gives 1e9 times).
ABSURD_MASS = 1e6
#: Inertia components beyond this (kg m^2) describe no robot link.
ABSURD_MOMENT = 1e6
#: A typed tensor (no products; equal or one-digit moments) whose radius of gyration
#: exceeds this many times the radius of a water sphere of the same mass is no compact
#: body's: a placeholder (PR2's 10 g frames at 0.32 m, 1 g IMUs at 1e-4 kg m^2). A solid sphere's
#: gyration is 0.63 of its radius; even a thin hollow sphere of a light plastic (200 kg/m^3
#: spread over the whole ball) stays within 3 times.
ISOTROPIC_REACH = 10.0


def diagnosis(raw: RawInertial) -> TensorDiagnosis:
    """The tensor's diagnosis, with every floating-point warning silenced (1e308 squares
    to infinity: the diagnosis then says "not finite")."""
    with np.errstate(all="ignore"):
        return diagnose_tensor(raw.inertia)


def value_findings(ev: LinkEvidence) -> list[Finding]:
    """Checks on the written numbers alone (module doc)."""
    name, link = ev.name, ev.link
    line = link.inertial.line if link.inertial is not None else link.line
    others = ev.merged_mass
    if link.inertial is None:
        if not ev.moves or link.implicit is not None:
            return []  # a frame, or a body the format's simulator computes
        if others > 0:
            return [Finding(Rule.MISSING_INERTIAL_MERGED, name, "moving link has no "
                            f"<inertial>; links fixed to it give it {others:.4g} kg only in "
                            "simulators that merge fixed joints", link.line)]
        return [Finding(Rule.MISSING_INERTIAL, name, "moving link (child of a non-fixed "
                        "joint) has no <inertial>", link.line)]
    raw = ev.raw
    assert raw is not None
    out: list[Finding] = []
    # A massless link that does not move, or whose fixed neighbours carry the mass, is a
    # frame, not a body. A moving body with nothing to merge is an error.
    severe = ev.moves and others == 0
    mass = raw.mass
    if not math.isfinite(mass):
        out.append(Finding(Rule.MASS_NOT_FINITE, name, f"mass is {mass}", line, "inertial"))
    elif mass < 0:
        out.append(Finding(Rule.MASS_NOT_POSITIVE, name, f"mass is {mass:.6g} kg", line,
                           "inertial"))
    elif mass == 0:
        if ev.moves:
            out.append(Finding(Rule.MASS_NOT_POSITIVE if severe else Rule.MASS_ZERO_MERGED,
                               name, "moving link has zero mass", line, "inertial"))
        else:
            out.append(Finding(Rule.MASSLESS_FRAME, name, "zero mass on a link that does "
                               "not move: a frame, not a body", line, "inertial"))
    elif mass > ABSURD_MASS:
        out.append(Finding(Rule.MASS_ABSURD, name, f"mass {mass:.4g} kg is beyond any robot "
                           f"link (above {ABSURD_MASS:g} kg): a unit slip, e.g. mm^3 taken "
                           "as m^3?", line, "inertial"))
    with np.errstate(all="ignore"):
        finite = raw.inertia[np.isfinite(raw.inertia)]
        largest = float(np.abs(finite).max()) if finite.size else 0.0
    if largest > ABSURD_MOMENT:
        out.append(Finding(Rule.INERTIA_ABSURD, name, f"inertia component {largest:.4g} kg "
                           f"m^2 is above {ABSURD_MOMENT:g}: a unit slip?", line, "inertial"))
    if not raw.com_ok:
        out.append(Finding(Rule.COM_NOT_FINITE, name, f"CoM is {raw.com.tolist()} (origin "
                           "xyz/rpy not finite)", line, "inertial"))
    d = diagnosis(raw)
    if not d.finite:
        out.append(Finding(Rule.INERTIA_NOT_FINITE, name, "inertia tensor has NaN/inf",
                           line, "inertial"))
        return out
    if d.zero:
        if mass > 0:
            out.append(Finding(Rule.INERTIA_ZERO if severe else Rule.INERTIA_ZERO_MERGED,
                               name, f"{mass:.4g} kg with a zero inertia tensor (a point "
                               "mass: MuJoCo refuses it on a moving body)", line, "inertial"))
    elif not d.symmetric:
        out.append(Finding(Rule.INERTIA_NOT_SYMMETRIC, name, f"tensor asymmetry "
                           f"{d.asymmetry:.3g}", line, "inertial"))
    elif not d.positive_definite:
        m = d.moments
        out.append(Finding(Rule.INERTIA_NOT_POSITIVE_DEFINITE, name, f"principal moments "
                           f"{moments_text(m)} kg m^2: the smallest is "
                           f"{m[0] / max(abs(m[2]), 1e-300):.3g} of the largest", line,
                           "inertial"))
    elif not d.triangle_ok:
        m = d.moments
        out.append(Finding(Rule.TRIANGLE_INEQUALITY, name, f"principal moments A+B<C by "
                           f"{d.triangle_excess:.3g} of C ({moments_text(m)} kg m^2); MuJoCo "
                           "refuses it", line, "inertial"))
    placeholder = placeholder_cause(raw)
    if placeholder is not None:
        out.append(Finding(Rule.PLACEHOLDER_INERTIA, name, placeholder, line, "inertial"))
    return out


def placeholder_cause(raw: RawInertial) -> str | None:
    """Why the written tensor is a placeholder (None: it is not one): the literal
    placeholders (``1``, a power of ten up to 1e-6 on the diagonal, no products), or a
    typed tensor (:func:`typed`) whose radius of gyration no compact body of its mass
    reaches (:data:`ISOTROPIC_REACH`)."""
    t = raw.inertia
    if is_placeholder(t):
        return (f"ixx=iyy=izz={t[0, 0]:g}, no products: a placeholder, not a computed "
                "tensor")
    if not typed(t) or not raw.mass_ok or not raw.mass > 0:
        return None
    gyration, water = _reach(raw)
    if gyration > ISOTROPIC_REACH * water:
        what = (f"ixx=iyy=izz={t[0, 0]:g}" if isotropic(t) else
                f"ixx={t[0, 0]:g} iyy={t[1, 1]:g} izz={t[2, 2]:g}")
        return (f"{what}, no products, for {raw.mass:.4g} kg: a radius of "
                f"gyration of {gyration:.3g} m, which no compact body of that mass reaches "
                f"(a water sphere of it has radius {water:.3g} m): a placeholder")
    return None


def _reach(raw: RawInertial) -> tuple[float, float]:
    """The radius of gyration sqrt(trace / 2m) and the radius of a water sphere of the
    mass, m."""
    gyration = math.sqrt(max(float(np.trace(raw.inertia)), 0.0) / (2 * raw.mass))
    return gyration, (3 * raw.mass / (4 * math.pi * 1000.0)) ** (1 / 3)


def reaches_too_far(raw: RawInertial) -> bool:
    """The tensor spreads the mass beyond any compact body of it (:data:`ISOTROPIC_REACH`
    water-sphere radii), whatever its shape."""
    if not raw.mass_ok or not raw.mass > 0 or not np.all(np.isfinite(raw.inertia)):
        return False
    gyration, water = _reach(raw)
    return gyration > ISOTROPIC_REACH * water


def typed(t: np.ndarray) -> bool:
    """No products and round moments: equal ones, or each of one significant digit (PR2's
    laser at ixx=1e-4 iyy=1e-6 izz=1e-4), the shapes of typed placeholders."""
    off = t[~np.eye(3, dtype=bool)]
    if not np.all(off == 0) or not np.all(np.diag(t) > 0):
        return False
    return isotropic(t) or all(_one_digit(float(x)) for x in np.diag(t))


def _one_digit(x: float) -> bool:
    mantissa = f"{x:.15e}".split("e")[0].rstrip("0").rstrip(".")
    return len(mantissa.replace(".", "")) == 1


def isotropic(t: np.ndarray) -> bool:
    """Equal diagonal entries and no products (the shape of a typed placeholder)."""
    off = t[~np.eye(3, dtype=bool)]
    return bool(np.all(off == 0) and t[0, 0] == t[1, 1] == t[2, 2] and t[0, 0] > 0)


def moments_text(m: np.ndarray) -> str:
    return "(" + ", ".join(f"{x:.4g}" for x in m) + ")"
