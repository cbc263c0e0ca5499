"""Carry out one link's :class:`~urdfinertia.plan.policy.Decision`, and the robot's mass change.

A recomputed link keeps the values the policy trusts: the mass (through the mass policy,
:func:`urdfinertia.body.mass.link_mass_source`) and the CoM. With a kept CoM the tensor is
the homogeneous solid's tensor about its own centroid, written at the kept CoM: measured
on real robots, adding the parallel-axis term to move it there makes the error
against CAD worse in the tail (p90 76 % -> 104 %). Every derived tensor gets an error bar
(:mod:`urdfinertia.body.errorbar`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from urdfinertia.body.assemble import Assembly
from urdfinertia.body.errorbar import tensor_error_bar
from urdfinertia.body.mass import MassSource
from urdfinertia.body.options import FixOptions
from urdfinertia.body.parts import MeshSource
from urdfinertia.descriptions.inertial import RawInertial
from urdfinertia.descriptions.model import Link, Problem
from urdfinertia.inertia.massprops import MassProperties
from urdfinertia.plan.compute import compute_link
from urdfinertia.plan.policy import Decision
from urdfinertia.plan.repair_only import repair_link
from urdfinertia.plan.results import Action, FixResult, LinkResult, Status

VALUES = ("mass", "com", "tensor")
#: Below this radius of gyration (m) a written tensor holds no information to keep.
MIN_GYRATION = 1e-4
#: The body given to a moving link with no mass and nothing to compute from, kg and m:
#: light enough not to change a robot's mass, heavy enough for MuJoCo (1e-15 floor).
MIN_BODY_MASS = 1e-5
MIN_BODY_RADIUS = 0.01
#: A change of the robot's total mass beyond this fraction is warned about.
MASS_CHANGE_WARN = 0.01


def apply_decision(link: Link, decision: Decision, options: FixOptions, meshes: MeshSource,
                   urdf_dir: Path, problems: tuple[Problem, ...] = ()) -> LinkResult:
    """The link's verdict under ``decision``; ``problems``: what the reader read past in it.

    The verdict carries the decision's action, reason and findings, and what could not be
    verified: the decision's unreadable geometry and every element dropped computing it.
    """
    r = _apply(link, decision, options, meshes, urdf_dir, problems)
    if r.status == Status.LEFT and decision.plausible_only and _invalid(link):
        # no other geometry is the body either: an invalid inertial still gets the
        # minimal repair (nothing fix leaves or writes is invalid)
        decision = replace(decision, action=Action.REPAIR, plausible_only=False)
        r = _apply(link, decision, options, meshes, urdf_dir, problems)
    if link.read_only is not None and r.changed:
        # the new values cannot be written where the inertial lives: say so, change nothing
        r = LinkResult(link.name, Status.LEFT, r.geometry, None, link.inertial,
                       problems=problems, reason=link.read_only,
                       decision=f"left as it was: {link.read_only}",
                       kept=VALUES if link.inertial is not None else ())
    dropped = tuple(f"{p.element}: {p.cause}" if p.element else p.cause
                    for p in r.problems if p.kind == "dropped" and p.link == link.name)
    unverified = tuple(dict.fromkeys(decision.unverified + dropped))
    return replace(r, action=decision.action, why=decision.why, findings=decision.findings,
                   unverified=unverified)


def _invalid(link: Link) -> bool:
    """The written inertial is one a simulator refuses (see :mod:`inertia.validity`)."""
    if link.inertial is None:
        return False
    return not RawInertial.from_inertial(link.inertial).diagnosis().valid


def _apply(link: Link, decision: Decision, options: FixOptions, meshes: MeshSource,
           urdf_dir: Path, problems: tuple[Problem, ...]) -> LinkResult:
    written = VALUES if link.inertial is not None else ()
    if decision.action == "keep":
        return LinkResult(link.name, Status.KEPT, "as written", None, link.inertial,
                          problems=problems, decision=decision.describe(), kept=written)
    if decision.action == "leave":
        # a placeholder that cannot be derived is left, never silently (exit 1)
        status = Status.LEFT if decision.unresolved else Status.UNTOUCHED
        return LinkResult(link.name, status, "none", None, link.inertial,
                          problems=problems, decision=decision.describe(), kept=written,
                          reason=decision.why if decision.unresolved else None)
    if decision.action == "repair":
        return replace(_repair(link, decision, options), problems=problems)
    if decision.action == "correct" and decision.slip is not None:
        # the slip undone: only the values the edit changed are written
        changed = decision.slip.changed
        return LinkResult(link.name, Status.REPAIRED, "as written", Assembly(
            decision.slip.after, (), MassSource("kept", decision.slip.after.mass)),
            link.inertial, problems=problems, decision=decision.describe(),
            kept=tuple(v for v in VALUES if v not in changed),
            derived=tuple(v for v in VALUES if v in changed), slip=decision.slip)
    r = compute_link(link, options, meshes, urdf_dir, problems, trust_mass=decision.keep_mass,
                     plausible_only=decision.plausible_only)
    if r.status == Status.LEFT:
        return replace(r, decision=f"left as it was: {r.reason}", kept=written)
    if r.assembly is None:  # no geometry (--all or --links): as before the policy
        return replace(r, decision=r.warnings[0] if r.warnings else "", kept=written)
    assembly = r.assembly
    kept: tuple[str, ...] = ("mass",) if assembly.mass_source.kind == "kept" else ()
    offset = None
    if decision.keep_com and kept and link.inertial is not None:
        com = RawInertial.from_inertial(link.inertial).com
        total = assembly.total
        offset = float(np.linalg.norm(total.com - com))
        assembly = Assembly(MassProperties(total.mass, com, total.inertia), assembly.parts,
                            assembly.mass_source)
        kept += ("com",)
    diagonal = r.choice.diagonal if r.choice is not None else None
    if diagonal is None and decision.bounds is not None:
        diagonal = float(np.linalg.norm(decision.bounds[1] - decision.bounds[0]))
    error_bar = None if r.geometry == "spec" else tensor_error_bar(
        offset, diagonal, *((r.choice.kind, r.choice.role, r.choice.density)
                            if r.choice is not None else ()))
    return replace(r, assembly=assembly, decision=decision.describe(), kept=kept,
                   derived=tuple(v for v in VALUES if v not in kept), error_bar=error_bar)


def _repair(link: Link, decision: Decision, options: FixOptions) -> LinkResult:
    """The minimal repair of a link with nothing to recompute from.

    An invalid tensor is lifted (``--repair-only``). Two cases the lift cannot make usable
    get the smallest body a simulator accepts instead, reported as such: a tensor with no
    information left (radius of gyration below :data:`MIN_GYRATION`, e.g. iCub's ankles at
    1e-20 kg m^2 for 0.27 kg, below MuJoCo's 1e-15 floor even once lifted) becomes a solid
    sphere of the written mass at ``options.density``; a moving link with no mass at all
    (a "virtual" link between the joints of a hip) gets :data:`MIN_BODY_MASS`.
    """
    raw = RawInertial.from_inertial(link.inertial) if link.inertial is not None else None
    if raw is None or not raw.mass_ok or (raw.mass == 0 and not raw.inertia.any()):
        # no usable mass (none, zero, negative or not finite) and nothing to compute from
        radius = MIN_BODY_RADIUS
        com = raw.com if raw is not None and raw.com_ok else np.zeros(3)
        body = MassProperties(MIN_BODY_MASS, com, _sphere(MIN_BODY_MASS, radius))
        kept_com = ("com",) if raw is not None and raw.com_ok else ()
        return LinkResult(link.name, Status.REPAIRED, "none", Assembly(body, (), MassSource(
            "kept", MIN_BODY_MASS)), link.inertial, decision=decision.describe() + (
            f"; a moving body needs mass: given {MIN_BODY_MASS:g} kg, a {100 * radius:g} cm "
            "sphere"), kept=kept_com, derived=tuple(v for v in VALUES if v not in kept_com))
    r = repair_link(link)
    if r.status == Status.REPAIRED and r.assembly is not None:
        total = r.assembly.total
        moments, _ = total.principal()
        # nothing fix writes is invalid: a lift that leaves the tensor invalid (a rank-one
        # tensor, two moments at zero: anymal-kinova's base) gets the sphere below
        valid = RawInertial.from_mass_properties(total).diagnosis().valid
        if valid and math.sqrt(moments[-1] / total.mass) >= MIN_GYRATION:
            return replace(r, decision=decision.describe(), kept=("mass", "com"),
                           derived=("tensor",))
    com = raw.com if raw.com_ok else np.zeros(3)
    kept = ("mass", "com") if raw.com_ok else ("mass",)
    radius = (3 * raw.mass / (4 * math.pi * options.density)) ** (1 / 3)
    body = MassProperties(raw.mass, com, _sphere(raw.mass, radius))
    return LinkResult(link.name, Status.REPAIRED, "none", Assembly(body, (), MassSource(
        "kept", raw.mass)), link.inertial, decision=decision.describe() + (
        f"; the tensor holds nothing to keep: a solid sphere of the mass at "
        f"{options.density:g} kg/m^3"), kept=kept,
        derived=tuple(v for v in VALUES if v not in kept))


def _sphere(mass: float, radius: float) -> np.ndarray:
    return np.eye(3) * (0.4 * mass * radius**2)


@dataclass(frozen=True)
class MassChange:
    """The robot's total mass (sum of the usable link masses) before and after, kg."""

    before: float
    after: float

    @property
    def relative(self) -> float:
        if self.before > 0:
            return (self.after - self.before) / self.before
        return 0.0 if self.after == 0 else math.inf

    @property
    def warn(self) -> bool:
        return abs(self.relative) > MASS_CHANGE_WARN

    def text(self) -> str:
        """Before and after, without the warning."""
        return f"total mass {self.before:.6g} kg -> {self.after:.6g} kg"

    def __str__(self) -> str:
        text = self.text()
        if self.warn:
            text += (f" ({100 * self.relative:+.1f} %: more than "
                     f"{100 * MASS_CHANGE_WARN:g} %, check the links given mass)")
        return text


def _usable(mass: float) -> float:
    return mass if math.isfinite(mass) and mass > 0 else 0.0


def mass_change(result: FixResult) -> MassChange:
    before = after = 0.0
    for r in result.links:
        old = _usable(r.previous.mass) if r.previous is not None else 0.0
        before += old
        after += _usable(r.assembly.total.mass) if r.assembly is not None else old
    return MassChange(before, after)
