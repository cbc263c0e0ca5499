"""Target masses: what the whole robot, or a subtree of it, is known to weigh.

A datasheet gives a robot's total mass ("17.8 kg"), sometimes a part's ("the hand weighs
0.73 kg"). ``fix --total-mass KG`` and the spec's ``total_mass`` / ``[subtree.NAME] mass``
keys scale the masses ``fix`` derives (not those it keeps) so that the robot, or the links
at and below link NAME, weigh that much. With ``scale_kept`` every mass scales. A link's
tensor scales with its mass (the same density scaled: same CoM, same shape).

Targets nest: the innermost subtree is settled first, and its links then count as fixed
mass for the targets around it. A target that the fixed masses alone reach or exceed, or
one with nothing to scale, is refused (:class:`MassTargetError`): nothing is written.

``check`` holds the written masses against the same targets (:func:`target_findings`,
UI703 ``total-mass-mismatch``).
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

from urdfinertia.errors import UrdfInertiaError
from urdfinertia.findings import Finding
from urdfinertia.plan.results import LinkResult, Status
from urdfinertia.rules import Rule

if TYPE_CHECKING:
    from urdfinertia.body.options import FixOptions
    from urdfinertia.descriptions.model import Robot


_VALUES = ("mass", "com", "tensor")  # the order verdicts name them in
#: A target met within this relative difference is left alone: the written masses of a
#: fixed file sum to the target only up to the round-off of their shortest decimal forms.
MET_RTOL = 1e-9


class MassTargetError(UrdfInertiaError):
    """A target mass that cannot be met by scaling what may be scaled."""


@dataclass(frozen=True)
class MassTarget:
    """A target: the links ``links`` (a subtree, or the whole robot) weigh ``mass`` kg.

    ``name`` is the subtree's root link, None for the whole robot.
    """

    name: str | None
    links: frozenset[str]
    mass: float


@dataclass(frozen=True)
class TargetOutcome:
    """One target met: the links' mass before (as written), as ``fix`` would derive it
    without the target (``unscaled``), the target, after, and the factor applied to the
    scaled links (kg; ``scaled`` names them)."""

    name: str | None
    before: float
    unscaled: float
    target: float
    after: float
    factor: float
    scaled: tuple[str, ...]

    def __str__(self) -> str:
        what = "total mass" if self.name is None else f"subtree '{self.name}' mass"
        if not self.scaled:
            return f"{what} target {self.target:.6g} kg: met already ({self.after:.6g} kg)"
        return (f"{what} target {self.target:.6g} kg: before {self.before:.6g} kg, "
                f"after {self.after:.6g} kg ({len(self.scaled)} link(s) scaled "
                f"x{self.factor:.6g})")

    def as_dict(self) -> dict[str, object]:
        return {"subtree": self.name, "before": self.before, "unscaled": self.unscaled,
                "target": self.target, "after": self.after, "factor": self.factor,
                "scaled": list(self.scaled)}


def subtree_links(robot: Robot, root: str) -> frozenset[str]:
    """Link ``root`` and every link below it in the kinematic tree."""
    children: dict[str, list[str]] = {}
    for joint in robot.joints:
        children.setdefault(joint.parent, []).append(joint.child)
    seen, stack = set(), [root]
    while stack:
        name = stack.pop()
        if name not in seen:
            seen.add(name)
            stack.extend(children.get(name, ()))
    return frozenset(seen)


def mass_targets(robot: Robot, options: FixOptions) -> tuple[MassTarget, ...]:
    """The targets asked for: the spec's subtrees, then the whole robot's (the option's
    ``total_mass``, else the spec's); innermost first."""
    subtrees: Mapping[str, float] = {}
    total = options.total_mass
    if options.spec is not None:
        subtrees = options.spec.subtree_masses
        if total is None:
            total = options.spec.total_mass
    targets = [MassTarget(name, subtree_links(robot, name), kg) for name, kg in subtrees.items()]
    targets.sort(key=lambda t: len(t.links))
    if total is not None:
        targets.append(MassTarget(None, frozenset(link.name for link in robot.links), total))
    return tuple(targets)


def _written(r: LinkResult) -> float:
    if r.previous is not None:
        return _usable(r.previous.mass)
    return _usable(r.stated_mass) if r.stated_mass is not None else 0.0


def _output(r: LinkResult) -> float:
    return _usable(r.assembly.total.mass) if r.changed and r.assembly is not None \
        else _written(r)


def _usable(mass: float) -> float:
    return mass if math.isfinite(mass) and mass > 0 else 0.0


def _scalable(r: LinkResult, scale_kept: bool) -> bool:
    """A mass derived from geometry scales; with ``scale_kept`` any mass the output carries
    does, except the smallest body a repair gives a massless link (a placeholder)."""
    if r.changed:
        if "mass" in r.derived:
            return r.status == Status.RECOMPUTED and _output(r) > 0
        return scale_kept and _output(r) > 0
    return scale_kept and _output(r) > 0 and r.before is not None


def meet_targets(robot: Robot, results: Sequence[LinkResult], options: FixOptions,
                 ) -> tuple[tuple[LinkResult, ...], tuple[TargetOutcome, ...]]:
    """The verdicts with masses scaled to meet every target, and each target's outcome.

    Raises :class:`MassTargetError` when a target cannot be met.
    """
    targets = mass_targets(robot, options)
    if not targets:
        return tuple(results), ()
    by_name = {r.name: r for r in results}
    mass = {r.name: _output(r) for r in results}
    factor = dict.fromkeys(by_name, 1.0)
    settled: set[str] = set()
    outcomes = []
    for t in targets:
        members = [n for n in by_name if n in t.links]
        scaled = [n for n in members if n not in settled
                  and _scalable(by_name[n], options.scale_kept)]
        free = sum(mass[n] for n in scaled)
        fixed = sum(mass[n] for n in members if n not in scaled)
        unscaled = free + fixed
        where = "the robot" if t.name is None else f"subtree '{t.name}'"
        if abs(unscaled - t.mass) <= MET_RTOL * t.mass:  # met already (a fixed file again)
            settled.update(members)
            outcomes.append(TargetOutcome(t.name, sum(_written(by_name[n]) for n in members),
                                          unscaled, t.mass, unscaled, 1.0, ()))
            continue
        if not free > 0:
            hint = "" if options.scale_kept else " (--scale-kept scales kept masses too)"
            raise MassTargetError(f"target mass {t.mass:.6g} kg for {where}: no derived "
                                  f"mass to scale{hint}", file=robot.path)
        if fixed >= t.mass:
            kind = "fixed" if options.scale_kept else "kept"
            raise MassTargetError(
                f"target mass {t.mass:.6g} kg for {where}: the {kind} masses alone weigh "
                f"{fixed:.6g} kg, at or above the target (nothing written)", file=robot.path)
        k = (t.mass - fixed) / free
        for n in scaled:
            mass[n] *= k
            factor[n] *= k
        settled.update(members)
        outcomes.append(TargetOutcome(t.name, sum(_written(by_name[n]) for n in members),
                                      unscaled, t.mass, sum(mass[n] for n in members), k,
                                      tuple(scaled)))
    out = tuple(_scaled(r, factor[r.name]) if factor[r.name] != 1.0 else r for r in results)
    return out, tuple(outcomes)


def _scaled(r: LinkResult, k: float) -> LinkResult:
    """Link ``r`` with its mass and tensor times ``k`` (CoM unchanged)."""
    from urdfinertia.body.assemble import Assembly
    from urdfinertia.body.mass import MassSource

    note = Finding(Rule.MASS_TARGET_MET, r.name, f"mass scaled x{k:.6g} to meet a target mass")
    if r.changed and r.assembly is not None:
        a = r.assembly
        parts = tuple(dataclasses.replace(p, mass_properties=p.mass_properties.with_mass(
            p.mass_properties.mass * k), density=p.density * k) if p.mass_properties.mass
            else p for p in a.parts)
        total = a.total.with_mass(a.total.mass * k)
        kind, value = a.mass_source.kind, a.mass_source.value
        # what the mass now comes from: the scaled total, or the scaled density
        source = a.mass_source if value is None else MassSource(
            kind, total.mass if a.mass_source.total is not None else value * k)
        derived = {*r.derived, "mass", "tensor"}
        # a target mass wins over the prior: its band no longer describes the mass
        bar = None if r.error_bar is None else dataclasses.replace(r.error_bar, mass=None)
        return dataclasses.replace(r, assembly=Assembly(total, parts, source), error_bar=bar,
                                   kept=tuple(v for v in r.kept if v not in derived),
                                   derived=tuple(v for v in _VALUES if v in derived),
                                   findings=r.findings + (note,))
    before = r.before
    assert before is not None  # only links with a usable written mass are scaled
    kept = tuple(v for v in r.kept if v not in ("mass", "tensor")) or ("com",)
    return dataclasses.replace(
        r, status=Status.RECOMPUTED,
        assembly=Assembly(before.with_mass(before.mass * k), (),
                          MassSource("kept", before.mass * k)),
        kept=kept, derived=("mass", "tensor"), findings=r.findings + (note,),
        grounds=r.grounds + (Rule.MASS_TARGET_MET,))


# --- check: the written masses against the targets ------------------------------------

#: A written mass within this fraction of its target is no finding (``check
#: --mass-tolerance``): a datasheet's total is rarely given to better than a percent.
DEFAULT_MASS_TOLERANCE = 0.01


def untargeted(options: FixOptions) -> FixOptions:
    """``options`` without any target mass (the verdicts ``fix`` would reach without them)."""
    spec = options.spec
    if spec is not None and spec.has_targets:
        spec = dataclasses.replace(spec, total_mass=None, subtree_masses={})
    return dataclasses.replace(options, total_mass=None, spec=spec)


def written_masses(robot: Robot) -> dict[str, float]:
    """Each link's written mass where it is a usable one (positive, finite), kg."""
    from urdfinertia.descriptions.inertial import RawInertial

    out = {}
    for link in robot.links:
        if link.inertial is not None:
            raw = RawInertial.from_inertial(link.inertial)
            if raw.mass_ok and _usable(raw.mass) > 0:
                out[link.name] = raw.mass
    return out


def _names(names: Sequence[str], most: int = 4) -> str:
    shown = ", ".join(names[:most])
    return shown + (f", ... ({len(names)} in all)" if len(names) > most else "")


def target_findings(robot: Robot, results: Sequence[LinkResult], options: FixOptions,
                    tolerance: float = DEFAULT_MASS_TOLERANCE) -> list[Finding]:
    """UI703 ``total-mass-mismatch`` for each target the written masses miss by more than
    ``tolerance`` (a fraction of the target): written, target, difference, which links
    ``fix`` derives and which it keeps, and what ``fix`` with the target would do.

    ``results`` are the verdicts without the targets (:func:`untargeted`); empty when the
    geometry was not read (then only the written figures are given).
    """
    targets = mass_targets(robot, options)
    if not targets:
        return []
    written = written_masses(robot)
    outcomes: tuple[TargetOutcome, ...] = ()
    refusal = None
    if results:
        try:
            outcomes = meet_targets(robot, results, options)[1]
        except MassTargetError as exc:
            refusal = exc.cause
    by_name = {r.name: r for r in results}
    out = []
    for i, t in enumerate(targets):
        members = [link.name for link in robot.links if link.name in t.links]
        total = sum(written.get(n, 0.0) for n in members)
        diff = total - t.mass
        if abs(diff) <= tolerance * t.mass:
            continue
        where = "the robot's links" if t.name is None else f"subtree '{t.name}'"
        source = ("--total-mass" if t.name is None and options.total_mass is not None
                  else "the spec")
        side = "over" if diff > 0 else "under"
        text = (f"{where} weigh {total:.6g} kg as written, {abs(diff):.4g} kg "
                f"({abs(diff) / t.mass:.2%}) {side} the target {t.mass:.6g} kg ({source}; "
                f"tolerance {tolerance:.2%})")
        if results:
            derived = [n for n in members if n in by_name and "mass" in by_name[n].derived
                       and _output(by_name[n]) > 0]
            kept = [n for n in members if n in written and n not in derived]
            text += (f"; fix derives the mass of {len(derived)} link(s)"
                     f"{' (' + _names(derived) + ')' if derived else ''} and keeps "
                     f"{len(kept)}")
            unscaled = sum(_output(by_name[n]) for n in members if n in by_name)
            if abs(unscaled - total) > MET_RTOL * t.mass:
                text += f"; without the target fix would write {unscaled:.6g} kg"
            if refusal is not None:
                text += f"; fix with the target refuses: {refusal}"
            elif i < len(outcomes) and outcomes[i].scaled:
                o = outcomes[i]
                text += (f"; fix with the target scales {len(o.scaled)} link(s) "
                         f"x{o.factor:.6g}")
        out.append(Finding(Rule.TOTAL_MASS_MISMATCH, t.name, text))
    return out


# --- the robot's total mass before and after fix --------------------------------------

#: A change of the robot's total mass beyond this fraction is warned about.
MASS_CHANGE_WARN = 0.01


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


def mass_change(links: Sequence[LinkResult]) -> MassChange:
    """The robot's total mass as written and as ``fix`` writes it (a mass a description
    states without a tensor, a USD MassAPI's, counts as written)."""
    before = after = 0.0
    for r in links:
        old = _written(r)
        before += old
        after += _output(r)
    return MassChange(before, after)


def mass_change_finding(links: Sequence[LinkResult]) -> Finding | None:
    """UI705 when ``fix`` changes the robot's total mass by more than
    :data:`MASS_CHANGE_WARN`."""
    change = mass_change(links)
    if not change.warn:
        return None
    return Finding(Rule.TOTAL_MASS_CHANGED, None, f"{change.text()} ({100 * change.relative:+.1f} "
                   f"%: more than {100 * MASS_CHANGE_WARN:g} %, check the links given mass)")
