"""Which links ``fix`` changes, and which of their values it keeps: **where a link's verdict
is made**.

:func:`plan_robot` decides every link from the judgement (:mod:`urdfinertia.judge.robot`)
and the options, fallbacks included: the :class:`LinkPlan` says what ``fix`` does, why (the
rules it answers, or the rule that says why it keeps or leaves the link), and carries the
values it will write. Carrying a plan out (:mod:`.execute`) only assembles what the plan
holds; nothing decides again after this.

The default (``recompute="needed"``): a written value is kept unless the judgement shows
it wrong. Invalid values (NaN, non-positive mass, not positive definite, the triangle
inequality, a zero tensor with a mass) are always changed: by undoing a slip, else by
deriving from the geometry, else by the minimal repair. A placeholder, a missing inertial
on a moving link, or values the body's geometry contradicts are derived from the geometry
that best represents the body (:mod:`urdfinertia.body.geometry_choice`), keeping a
plausible mass and a CoM inside the geometry; a link with no usable mass gets the mass
prior's density for it (:mod:`urdfinertia.priors`, with its band) unless a density is
given. Geometry that is not the body (the
judgement's ``not_body``) gives no evidence: a valid value is kept, said so. Massless
frames stay massless. ``recompute="all"`` (``--all``) and ``"links"`` (``--links``) derive
every link (or those named) with geometry, and still give an invalid value the minimal
repair where they derive nothing. Links named in a spec are always recomputed.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import TYPE_CHECKING

import numpy as np

from urdfinertia.body.assemble import Assembly, assemble
from urdfinertia.body.evidence import LinkEvidence, RobotEvidence
from urdfinertia.body.geometry_choice import Candidate, GeometryChoice, choose
from urdfinertia.body.mass import MassSource, link_mass_source
from urdfinertia.body.options import PLAUSIBLE_DENSITY
from urdfinertia.errors import UrdfInertiaError
from urdfinertia.findings import Finding
from urdfinertia.judge.geometry import inside
from urdfinertia.judge.robot import Judgement, LinkJudgement
from urdfinertia.judge.slips import SLIP_TRIGGERS, SlipProposal
from urdfinertia.judge.values import reaches_too_far
from urdfinertia.plan.results import Action
from urdfinertia.priors.model import MassPrior
from urdfinertia.rules import Rule

if TYPE_CHECKING:
    from urdfinertia.inertia.massprops import MassProperties

#: Findings that make ``fix`` change a link by default.
RECOMPUTE = (
    Rule.MISSING_INERTIAL, Rule.MISSING_INERTIAL_MERGED, Rule.MASS_NOT_FINITE,
    Rule.MASS_NOT_POSITIVE, Rule.MASS_ZERO_MERGED, Rule.COM_NOT_FINITE,
    Rule.INERTIA_NOT_FINITE, Rule.INERTIA_ZERO, Rule.INERTIA_ZERO_MERGED,
    Rule.INERTIA_NOT_SYMMETRIC, Rule.INERTIA_NOT_POSITIVE_DEFINITE, Rule.TRIANGLE_INEQUALITY,
    Rule.PLACEHOLDER_INERTIA, Rule.MASS_ABSURD, Rule.INERTIA_ABSURD,
    Rule.COM_OUTSIDE_GEOMETRY, Rule.COM_FAR_OUTSIDE_GEOMETRY, Rule.IMPLAUSIBLE_DENSITY,
    Rule.INERTIA_VS_GEOMETRY, Rule.MASS_DISTRIBUTION, Rule.INERTIAL_COPIED,
    Rule.USD_MASS_WITHOUT_TENSOR,
)
#: Findings after which the written mass is not kept (and with it the CoM).
MASS_DISTRUST = frozenset({Rule.MISSING_INERTIAL, Rule.MISSING_INERTIAL_MERGED,
                           Rule.MASS_NOT_FINITE, Rule.MASS_NOT_POSITIVE,
                           Rule.MASS_ZERO_MERGED, Rule.MASS_ABSURD, Rule.INERTIAL_COPIED})
#: Findings that a unit slip of the geometry (a mesh in mm without scale) explains: the
#: geometry, not the inertial, is wrong, and recomputing from it would make things worse.
GEOMETRY_SLIP = frozenset({Rule.IMPLAUSIBLE_DENSITY, Rule.INERTIA_VS_GEOMETRY})
#: Findings after which the written CoM is not kept.
COM_DISTRUST = frozenset({Rule.COM_NOT_FINITE, Rule.COM_OUTSIDE_GEOMETRY,
                          Rule.COM_FAR_OUTSIDE_GEOMETRY})
#: Findings a simulator refuses: what the minimal repair is for when nothing is derived.
INVALID = frozenset({Rule.MASS_NOT_FINITE, Rule.MASS_NOT_POSITIVE, Rule.MASS_ZERO_MERGED,
                     Rule.COM_NOT_FINITE, Rule.INERTIA_NOT_FINITE, Rule.INERTIA_ZERO,
                     Rule.INERTIA_ZERO_MERGED, Rule.INERTIA_NOT_SYMMETRIC,
                     Rule.INERTIA_NOT_POSITIVE_DEFINITE, Rule.TRIANGLE_INEQUALITY,
                     Rule.MASS_ABSURD, Rule.INERTIA_ABSURD})
#: Findings that hold the inertial against the geometry: no evidence when the geometry is
#: not the body.
GEOMETRIC = frozenset({Rule.IMPLAUSIBLE_DENSITY, Rule.COM_OUTSIDE_GEOMETRY,
                       Rule.COM_FAR_OUTSIDE_GEOMETRY, Rule.INERTIA_VS_GEOMETRY})
#: A kept CoM lies in the geometry's box grown by this fraction of its diagonal on every
#: side: collision geometry is often a simplified, slightly smaller hull of the CAD part.
COM_KEEP_MARGIN = 0.02
#: A link lighter than this share of the robot's mass is a frame body (ANYmal C's 1 g hips,
#: Baxter's 0.1 g sensor frames): a placeholder tensor there changes nothing a simulator
#: does, so with nothing to derive it from it is left as it is without failing the run.
NEGLIGIBLE_SHARE = 1e-3


@dataclass(frozen=True, eq=False)
class LinkPlan:
    """What ``fix`` does with one link, and why; with the values it writes.

    Attributes
    ----------
    link : str
    action : Action
    grounds : tuple of Rule
        The findings the action answers.
    because : Rule or None
        Why the link is kept or left despite findings (or why it is left).
    keep : frozenset of str
        Which of "mass", "com" are written as they are (for "recompute").
    assembly : Assembly or None
        The values to write, for "recompute" (the CoM still to be placed at the kept one),
        "repair" and "correct".
    source : Candidate or None, choice : GeometryChoice or None
        The geometry a recomputed inertial integrates, and why.
    role : str
        "collision", "visual", "geom", "spec", "none" or "as written".
    unresolved : bool
        Left although it should have changed (``fix`` exits 1).
    slip : SlipProposal or None
        For "correct": the edit undone.
    prior : MassPrior or None
        For "recompute" of a link with no usable mass: the mass prior its mass came from,
        with the band.
    notes : tuple of Finding
        What planning found out carrying on (the minimal body given, elements dropped).
    """

    link: str
    action: Action
    grounds: tuple[Rule, ...] = ()
    because: Rule | None = None
    keep: frozenset[str] = frozenset()
    assembly: Assembly | None = None
    source: Candidate | None = None
    choice: GeometryChoice | None = None
    role: str = "as written"
    unresolved: bool = False
    slip: SlipProposal | None = None
    prior: MassPrior | None = None
    notes: tuple[Finding, ...] = ()


def plan_robot(judgement: Judgement) -> dict[str, LinkPlan]:
    """The plan of every link, by name (module doc)."""
    evidence = judgement.evidence
    return {name: plan_link(evidence.links[name], j, evidence)
            for name, j in judgement.links.items()}


def plan_link(ev: LinkEvidence, j: LinkJudgement, robot: RobotEvidence) -> LinkPlan:
    """One link's plan: the decision (:func:`_decide`), then the read-only rule."""
    plan = _decide(ev, j, robot)
    if ev.link.read_only is not None and plan.action in (Action.RECOMPUTE, Action.REPAIR,
                                                         Action.CORRECT):
        return LinkPlan(ev.name, Action.LEAVE, plan.grounds, Rule.READ_ONLY_BODY,
                        unresolved=True, notes=(Finding(
                            Rule.READ_ONLY_BODY, ev.name, ev.link.read_only, ev.link.line),))
    return plan


def _decide(ev: LinkEvidence, j: LinkJudgement, robot: RobotEvidence) -> LinkPlan:
    options = ev.options
    name, link = ev.name, ev.link
    rules = j.rules
    spec = options.spec.link(name) if options.spec is not None else None
    if spec is not None:
        return _from_spec(ev, spec, not rules & MASS_DISTRUST)
    if options.keep_auto and link.auto_inertial:
        return LinkPlan(name, Action.LEAVE, because=Rule.AUTO_INERTIAL_KEPT)
    if options.recompute == "all" or (options.recompute == "links" and name in options.links):
        asked = _recompute(ev, j, (), keep_mass=True, keep_com=False, because=Rule.ASKED)
        if asked.action == Action.RECOMPUTE or not rules & INVALID:
            return asked
        return _repair(ev, j, tuple(r for r in RECOMPUTE if r in rules))
    if options.recompute == "links":
        if rules & INVALID:
            return _repair(ev, j, tuple(r for r in RECOMPUTE if r in rules))
        return LinkPlan(name, Action.KEEP, because=Rule.NOT_ASKED)
    # an <inertial> the reader could not read is not an absent one: its bytes would stay
    unread = link.inertial is None and any(f.element == "inertial" for f in j.findings)
    massless = (link.inertial is None and not unread) or (
        link.inertial is not None and link.inertial.mass == 0)
    if massless and not ev.moves and not (link.inertial is not None and rules & INVALID
                                          - {Rule.MASS_NOT_POSITIVE, Rule.MASS_ZERO_MERGED}):
        if not ev.is_root:
            why = "massless, on a fixed joint: left as it is"
        else:
            what = "without <inertial>" if link.inertial is None else "with mass 0"
            why = (f"root link {what}: left as it is (a floating base is recomputed only "
                   "when named)")
        return LinkPlan(name, Action.LEAVE, because=Rule.MASSLESS_FRAME,
                        notes=(Finding(Rule.MASSLESS_FRAME, name, why, link.line),))
    if unread:
        # derived from the geometry as if absent, so that no unreadable value is left
        cause = next(f.rule for f in j.findings if f.element == "inertial")
        plan = _recompute(ev, j, (cause,), keep_mass=False, keep_com=False)
        if plan.action == Action.RECOMPUTE:
            return plan
        return LinkPlan(name, Action.LEAVE, (cause,), plan.because, unresolved=True,
                        notes=plan.notes)
    if link.inertial is None and link.implicit is not None:
        if link.implicit.mass is not None:  # a USD mass without a tensor: derive it
            return _recompute(ev, j, (Rule.USD_MASS_WITHOUT_TENSOR,), keep_mass=True,
                              keep_com=False, mass=MassSource("kept", link.implicit.mass))
        if Rule.INERTIAL_FROM_GEOMS in rules:
            return LinkPlan(name, Action.LEAVE, because=Rule.INERTIAL_FROM_GEOMS)
    triggers = {r for r in rules if r in RECOMPUTE}
    if triggers - {Rule.MESH_UNRESOLVED, Rule.GEOMETRY_UNREADABLE} == {Rule.INERTIA_ZERO_MERGED,
                                                                       } and not ev.moves \
            and not ev.is_root and not ev.has_geometry:
        # a frame with a token mass (so101's gripper_frame_link: 1e-9 kg, zero tensor):
        # simulators merge it into its parent; a made-up tensor of that size is one MuJoCo
        # refuses (eigenvalues below its 1e-15 floor), where it took the zero tensor
        return LinkPlan(name, Action.LEAVE, because=Rule.MASSLESS_FRAME, notes=(Finding(
            Rule.MASSLESS_FRAME, name, "frame on a fixed joint with a zero tensor and "
            "nothing to compute from: left as it is", link.line),))
    if j.closed_form is not None and j.closed_form != 1.0 and not rules & INVALID:
        return LinkPlan(name, Action.KEEP, because=Rule.CLOSED_FORM_SCALED)
    if j.vouched_by is not None:
        return LinkPlan(name, Action.KEEP, because=Rule.TWIN_VOUCHES)
    if j.slip is not None:
        return _correct(ev, j)
    if j.copy_of is not None and j.copy_density is not None and j.copy_density > 0:
        plan = _recompute(ev, j, (Rule.INERTIAL_COPIED,), keep_mass=False, keep_com=False,
                          mass=MassSource("density", j.copy_density))
        if plan.action == Action.RECOMPUTE:
            return plan
    return _default(ev, j, robot)


def _default(ev: LinkEvidence, j: LinkJudgement, robot: RobotEvidence) -> LinkPlan:
    """The default policy for a link that is not a frame, from its findings."""
    name, rules = ev.name, set(j.rules)
    g = j.geometry
    if g.geometry_slip is not None:
        rules -= GEOMETRY_SLIP
    not_body = g.not_body
    if not_body is not None:
        rules -= GEOMETRIC
    unread = ev.link.inertial is not None and bool(j.unverified)
    triggers = tuple(r for r in RECOMPUTE if r in rules)
    if not triggers:
        if not_body is not None:
            return LinkPlan(name, Action.KEEP, because=Rule.GEOMETRY_NOT_BODY)
        if g.geometry_slip is not None:
            return LinkPlan(name, Action.KEEP, because=Rule.GEOMETRY_UNIT_SLIP)
        if unread:
            return LinkPlan(name, Action.KEEP, because=j.unverified[0].rule)
        return LinkPlan(name, Action.KEEP)
    invalid = bool(rules & INVALID) or bool(rules & {Rule.MISSING_INERTIAL,
                                                      Rule.MISSING_INERTIAL_MERGED})
    negligible = _negligible(ev, robot)
    keep_mass = not rules & MASS_DISTRUST
    keep_com = keep_mass and not rules & COM_DISTRUST and ev.raw is not None \
        and inside(ev.raw, g.bounds, COM_KEEP_MARGIN)
    if not_body is not None and not unread and ev.options.geometry == "auto" \
            and not negligible and len(ev.roles) > 1:
        # the geometry judged is not the body; the link's other geometry may be
        plan = _recompute(ev, j, triggers, keep_mass=True, keep_com=keep_com,
                          plausible_only=True, because=Rule.GEOMETRY_NOT_BODY)
        if plan.action == Action.RECOMPUTE:
            return plan
    if not_body is not None or unread or not ev.roles:
        because = (Rule.GEOMETRY_NOT_BODY if not_body is not None else
                   j.unverified[0].rule if unread else Rule.NO_GEOMETRY)
        if invalid:
            return _repair(ev, j, triggers, because)
        if Rule.PLACEHOLDER_INERTIA in rules and not unread and ev.raw is not None and (
                not negligible or reaches_too_far(ev.raw)):
            # a placeholder is no value to keep and nothing here computes a better one:
            # the smallest honest body, unless it is a negligible part's harmless one
            return _repair(ev, j, triggers, because, placeholder=True)
        if negligible:
            return LinkPlan(name, Action.LEAVE, triggers, Rule.NEGLIGIBLE_BODY)
        return LinkPlan(name, Action.LEAVE, triggers, because, unresolved=True)
    plan = _recompute(ev, j, triggers, keep_mass=keep_mass, keep_com=keep_com)
    if plan.action != Action.LEAVE or not rules & INVALID:
        # a missing inertial whose geometry cannot be read is left, said so (a made-up
        # body would hide that the mesh is missing); invalid values get the minimal repair
        return plan
    repaired = _repair(ev, j, triggers, plan.because)
    return replace(repaired, notes=plan.notes + repaired.notes)


def _negligible(ev: LinkEvidence, robot: RobotEvidence) -> bool:
    """The link's written mass is below :data:`NEGLIGIBLE_SHARE` of the robot's."""
    raw = ev.raw
    if raw is None or not raw.mass_ok:
        return False
    return bool(0 < raw.mass < NEGLIGIBLE_SHARE * robot.total_mass)


def _recompute(ev: LinkEvidence, j: LinkJudgement, grounds: tuple[Rule, ...], *,
               keep_mass: bool, keep_com: bool, plausible_only: bool = False,
               mass: MassSource | None = None, because: Rule | None = None) -> LinkPlan:
    """Derive the link from the geometry that best represents the body (fallback: left,
    with why, when no geometry can be integrated)."""
    options = ev.options
    candidates = ev.all_candidates() if options.geometry == "auto" and not \
        ev.link.auto_inertial else [c for c in (ev.primary,) if c is not None]
    source = mass or link_mass_source(ev.link, options, trust_mass=keep_mass)
    kept_mass = source.total if source.kind == "kept" else None
    raw = ev.raw
    com = raw.com if keep_com and raw is not None and raw.com_ok and kept_mass else None
    if not candidates:
        dropped = _dropped(ev)
        notes = tuple(dropped)
        if dropped:
            first = dropped[0]
            more = f" and {len(dropped) - 1} more" if len(dropped) > 1 else ""
            cause = first.message.removeprefix("dropped: ")
            notes += (Finding(Rule.NO_GEOMETRY, ev.name, f"no usable geometry left "
                              f"({first.element} line {first.line}: {cause}{more})",
                              ev.link.line),)
        return LinkPlan(ev.name, Action.LEAVE, grounds, Rule.NO_GEOMETRY,
                        unresolved=bool(dropped) or bool(grounds), notes=notes)
    best, chosen = choose(candidates, kept_mass, com)
    prior = None
    # with a target mass (--total-mass, the spec's) the prior's masses are what is scaled
    if mass is None and source.kind == "density" and options.density_prior \
            and options.mass == "keep":
        prior = _mass_prior(ev, best, candidates)
        if prior is not None:
            source = MassSource("density", prior.density)
    lo, hi = PLAUSIBLE_DENSITY
    if plausible_only and chosen.density is not None and not lo <= chosen.density <= hi:
        return LinkPlan(ev.name, Action.LEAVE, grounds, Rule.GEOMETRY_NOT_BODY,
                        unresolved=True)
    try:
        with np.errstate(all="raise"):
            assembly = assemble(best.parts, source)
        if not _stateable(assembly.total):
            raise ValueError("the values are beyond what a description can state (1e9 in "
                             "SI units)")
    except (UrdfInertiaError, ValueError, FloatingPointError) as exc:
        cause = exc.cause if isinstance(exc, UrdfInertiaError) else str(exc)
        note = Finding(Rule.DERIVED_FROM_IMPLAUSIBLE, ev.name, f"mass properties cannot be "
                       f"computed from the {best.role} geometry: {cause}", ev.link.line)
        return LinkPlan(ev.name, Action.LEAVE, grounds, Rule.DERIVED_FROM_IMPLAUSIBLE,
                        unresolved=True, notes=(note,))
    keep = frozenset({"mass"} if assembly.mass_source.kind == "kept" else set())
    if com is not None and "mass" in keep:
        keep |= {"com"}
    return LinkPlan(ev.name, Action.RECOMPUTE, grounds, because, keep, assembly, best,
                    chosen, best.role, prior=prior, notes=tuple(best.dropped))


def _mass_prior(ev: LinkEvidence, best: Candidate, candidates: list[Candidate],
                ) -> MassPrior | None:
    """The mass prior of a link with no usable mass, over the geometry it is derived from
    (None: the geometry has no volume to put a density in)."""
    from urdfinertia.body.bounds import link_bounds
    from urdfinertia.priors.features import link_features
    from urdfinertia.priors.model import mass_prior

    if not best.volume > 0:
        return None
    try:
        box = link_bounds(best.refs, ev.robot.bounds_cache, ev.robot.urdf_dir)
    except (UrdfInertiaError, ValueError):
        box = None
    features = link_features(ev.name, ev.robot.prior_features, volume=best.volume, box=box,
                             geometry=best.kind, role=best.role,
                             others=tuple(c.volume for c in candidates))
    found = mass_prior(features)
    return found if math.isfinite(found.density) and found.density > 0 else None


def _dropped(ev: LinkEvidence) -> list[Finding]:
    """Every element of the link that could not be integrated, with why."""
    from urdfinertia.body.geometry_choice import usable_parts
    from urdfinertia.body.options import weighable

    found: list[Finding] = []
    for _, refs in ev.roles:
        usable_parts(ev.link, weighable(refs), ev.robot.meshes, ev.robot.urdf_dir, found)
    return list(dict.fromkeys(found))


def _from_spec(ev: LinkEvidence, spec, trust_mass: bool) -> LinkPlan:  # noqa: ANN001
    parts, _ = spec.parts(ev.link, ev.robot.meshes, ev.robot.urdf_dir)
    source = spec.mass_source(ev.link, ev.options, trust_mass=trust_mass)
    try:
        assembly = assemble(parts, source)
    except UrdfInertiaError as exc:  # the spec, not the description, made these parts
        raise exc.with_context(file=spec.path, link=ev.name) from None
    keep = frozenset({"mass"} if assembly.mass_source.kind == "kept" else set())
    return LinkPlan(ev.name, Action.RECOMPUTE, (), Rule.SPEC_NAMED, keep, assembly,
                    role="spec")


def _correct(ev: LinkEvidence, j: LinkJudgement) -> LinkPlan:
    slip = j.slip
    assert slip is not None
    grounds = tuple(r for r in RECOMPUTE if r in j.rules and r in SLIP_TRIGGERS)
    if j.convention is not None:
        grounds = (Rule.CONVENTION_INFERRED, *grounds)
    assembly = Assembly(slip.after, (), MassSource("kept", slip.after.mass))
    return LinkPlan(ev.name, Action.CORRECT, grounds, None,
                    frozenset(v for v in ("mass", "com", "tensor") if v not in slip.changed),
                    assembly, role="as written", slip=slip)


#: Below this radius of gyration (m) a written tensor holds no information to keep.
MIN_GYRATION = 1e-4
#: The body given to a moving link with no mass and nothing to compute from, kg and m:
#: light enough not to change a robot's mass, heavy enough for MuJoCo (1e-15 floor).
MIN_BODY_MASS = 1e-5
MIN_BODY_RADIUS = 0.01


def _repair(ev: LinkEvidence, j: LinkJudgement, grounds: tuple[Rule, ...],
            because: Rule | None = None, placeholder: bool = False) -> LinkPlan:
    """The minimal repair of a link with nothing to derive from.

    An invalid tensor is lifted (``--repair-only``'s repair). Two cases the lift cannot
    make usable get the smallest body a simulator accepts instead, reported as such: a
    tensor with no information left (radius of gyration below :data:`MIN_GYRATION`, e.g.
    iCub's ankles at 1e-20 kg m^2 for 0.27 kg) becomes a solid sphere of the written mass
    at ``options.density``; a moving link with no usable mass at all gets
    :data:`MIN_BODY_MASS` in a :data:`MIN_BODY_RADIUS` sphere. A ``placeholder`` tensor
    (valid, but no computed value: PR2's 10 g camera frames at a 0.39 m radius of
    gyration) gets the sphere as well.
    """
    from urdfinertia.inertia.massprops import MassProperties
    from urdfinertia.inertia.tensor_repair import repair_tensor
    from urdfinertia.inertia.validity import diagnose_tensor

    raw = ev.raw
    name = ev.name
    options = ev.options
    radius = (3 * raw.mass / (4 * math.pi * options.density)) ** (1 / 3) \
        if raw is not None and raw.mass_ok and 0 < raw.mass <= 1e6 else 0.0
    # a mass so small its sphere's moments underflow (1e-300 kg) is no usable mass either
    usable = radius > 0 and diagnose_tensor(_sphere(raw.mass, radius)).valid \
        if raw is not None else False
    if raw is None or not raw.mass_ok or raw.mass > 1e6 or (
            raw.mass == 0 and not raw.inertia.any()) or (0 < raw.mass and not usable):
        com = raw.com if raw is not None and raw.com_ok and _finite_com(raw.com) \
            else np.zeros(3)
        body = MassProperties(MIN_BODY_MASS, com, _sphere(MIN_BODY_MASS, MIN_BODY_RADIUS))
        note = Finding(Rule.MINIMAL_BODY, name, f"a moving body needs mass: given "
                       f"{MIN_BODY_MASS:g} kg, a {100 * MIN_BODY_RADIUS:g} cm sphere",
                       ev.link.line, "inertial")
        keep = frozenset({"com"}) if raw is not None and raw.com_ok else frozenset()
        return LinkPlan(name, Action.REPAIR, grounds, because, keep, Assembly(
            body, (), MassSource("kept", MIN_BODY_MASS)), role="none", notes=(note,))
    com = raw.com if raw.com_ok and _finite_com(raw.com) else np.zeros(3)
    keep = frozenset({"mass", "com"}) if raw.com_ok else frozenset({"mass"})
    with np.errstate(all="ignore"):
        finite = bool(np.all(np.isfinite(raw.inertia))) and float(
            np.abs(raw.inertia).max(initial=0.0)) < 1e6
    if finite and not placeholder:
        try:
            lifted = repair_tensor(raw.inertia)
            moments = np.linalg.eigvalsh(lifted.tensor)
            if diagnose_tensor(lifted.tensor).valid and \
                    math.sqrt(max(moments[-1], 0.0) / raw.mass) >= MIN_GYRATION:
                body = MassProperties(raw.mass, com, lifted.tensor)
                notes = tuple(Finding(Rule.TENSOR_LIFTED, name, change, ev.link.line,
                                      "inertial") for change in lifted.changes)
                return LinkPlan(name, Action.REPAIR, grounds, because, keep, Assembly(
                    body, (), MassSource("kept", raw.mass)), role="as written",
                    notes=notes)
        except (ValueError, np.linalg.LinAlgError):
            pass
    body = MassProperties(raw.mass, com, _sphere(raw.mass, radius))
    what = "placeholder" if placeholder else "tensor"
    note = Finding(Rule.TENSOR_HOLDS_NOTHING, name, f"the {what} holds nothing to keep: a "
                   f"solid sphere of the mass at {options.density:g} kg/m^3", ev.link.line,
                   "inertial")
    return LinkPlan(name, Action.REPAIR, grounds, because, keep, Assembly(
        body, (), MassSource("kept", raw.mass)), role="none", notes=(note,))


def _stateable(mp: MassProperties) -> bool:
    """Every value of ``mp`` within what the readers read back (a mesh scaled to the size
    of a planet gives a mass above 1e9 kg that no reader would accept)."""
    from urdfinertia.descriptions.urdf.read import MAX_MAGNITUDE

    values = np.abs(np.concatenate(([mp.mass], mp.com, mp.inertia.ravel())))
    return bool(np.all(np.isfinite(values)) and values.max() <= MAX_MAGNITUDE)


def _finite_com(com: np.ndarray) -> bool:
    return bool(np.all(np.abs(com) < 1e6))


def _sphere(mass: float, radius: float) -> np.ndarray:
    return np.eye(3) * (0.4 * mass * radius**2)


def every_link(options):  # noqa: ANN001, ANN201
    """``options`` asking for every link with geometry (what ``compare`` shows as B)."""
    return replace(options, recompute="all", links=())
