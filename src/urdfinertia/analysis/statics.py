"""Whole-robot statics: total mass, whole CoM, and the gravity torque each joint must hold.

Per actuated joint, the largest gravity torque (N m; N for a prismatic joint) over its range
of motion and the other joints' ranges, sampled (seeded; the corners of every range and the
zero pose are among the samples, and the best sample is refined one joint at a time), with
the root held fixed (the robot as mounted; a floating root is held too: the figures are
those of a leg or arm lifted off the ground). Compared with the joint's declared effort:

* UI701 ``joint-cannot-hold`` error: the effort is below the torque needed even at the low
  end of the derived links' band; a warning when it is below only within the band.
* UI702 ``joint-effort-margin`` warning: the torque needed is within ``margin`` of the effort.

A joint with no effort (or effort 0) is passive: its load is computed (``Statics.loads``),
not judged (false alarms on passive joints are what a zero-pose check gets). The total mass
and whole CoM are :class:`Statics`' ``mass`` and ``com`` (``CheckResult.statics``), not
findings: every robot has them.

A mimic joint is driven by the joint it mimics: its torque times its multiplier is added to
that joint's (the actuator holds both), and it gets no verdict of its own.

Masses and CoMs are the values ``fix`` writes (the links' verdicts), or the written ones
without geometry. A link whose mass or CoM ``fix`` derives carries a relative band
(its verdict's error bar, see :mod:`urdfinertia.body.errorbar`; :data:`DERIVED_BAND` when it
has none) into the torque: each link's contribution is taken at ``1 +- band``.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

from urdfinertia.descriptions.inertial import RawInertial
from urdfinertia.descriptions.model import Joint, Robot
from urdfinertia.findings import Finding
from urdfinertia.inertia.rotation import pose_matrix
from urdfinertia.plan.results import LinkResult
from urdfinertia.rules import Rule

GRAVITY = 9.81
#: needed torque above (1 - margin) x effort: warning
DEFAULT_MARGIN = 0.2
#: relative band of a derived link's mass when its verdict states none
DERIVED_BAND = 0.3
#: random configurations sampled (besides the corners of the ranges and the zero pose)
SAMPLES = 256
#: budget of one statics run: configurations x (links + the links of every joint's
#: subtree), the arrays' elements: time and memory stay bounded on a long chain
MAX_WORK = 20_000_000
#: configurations of one joint's refinement at most (its sweep of every joint)
MAX_SWEEP = 2048
#: random configurations drawn however large the robot
MIN_SAMPLES = 16
#: a joint whose sampled load is above this fraction of its effort is refined (swept one
#: joint at a time from its worst sample); below it, far from any finding, it is not
REFINE_FROM = 0.5
#: continuous joints (and revolute ones without limits) are sampled over a full turn
_TURN = (-np.pi, np.pi)
_MOVING = ("revolute", "continuous", "prismatic")


@dataclass(frozen=True)
class Body:
    """A link's mass (kg) and CoM (link frame, m), with a relative band of its mass."""

    mass: float
    com: np.ndarray
    band: float = 0.0


@dataclass(frozen=True)
class JointLoad:
    """The largest gravity load of one joint: ``needed`` at the nominal masses, ``low`` and
    ``high`` at the ends of the derived links' band; ``effort`` as declared (None: not
    stated); ``passive`` when it has no effort; ``mimics`` the joints folded into it."""

    joint: Joint
    needed: float
    low: float
    high: float
    effort: float | None
    passive: bool
    unit: str
    mimics: tuple[str, ...] = ()


@dataclass(frozen=True)
class Statics:
    """The robot's total mass (kg), its CoM at the zero pose (root frame, m), and per
    actuated or passive joint its :class:`JointLoad`; ``note`` says when the sampling was
    coarsened to stay within its budget (empty: it was not), ``configurations`` how many
    configurations were sampled in all."""

    mass: float
    com: np.ndarray
    loads: tuple[JointLoad, ...]
    note: str = ""
    configurations: int = 0


def verdict_bodies(links: tuple[LinkResult, ...]) -> dict[str, Body]:
    """Every link's mass and CoM as ``fix`` writes them; a derived mass or CoM carries its
    verdict's error bar (:data:`DERIVED_BAND` when it has none) as its band."""
    out = {}
    for r in links:
        after = r.after
        if after is None or not after.mass > 0:
            continue
        band = 0.0
        if "mass" in r.derived or "com" in r.derived:
            band = r.error_bar.band if r.error_bar is not None else DERIVED_BAND
        out[r.name] = Body(after.mass, np.asarray(after.com), band)
    return out


def written_bodies(robot: Robot) -> dict[str, Body]:
    """Every link's written mass and CoM, where they are a body (positive finite mass)."""
    out = {}
    for link in robot.links:
        if link.inertial is None:
            continue
        raw = RawInertial.from_inertial(link.inertial)
        if raw.mass_ok and raw.com_ok:
            out[link.name] = Body(raw.mass, raw.com)
    return out


def _motion(joint: Joint, q: np.ndarray) -> np.ndarray:
    """(n, 4, 4) motion of ``joint`` at the ``n`` values ``q``."""
    n = len(q)
    out = np.tile(np.eye(4), (n, 1, 1))
    axis = np.asarray(joint.axis, dtype=np.float64)
    norm = np.linalg.norm(axis)
    if joint.type not in _MOVING or norm == 0:
        return out
    axis = axis / norm
    if joint.type == "prismatic":
        out[:, :3, 3] = q[:, None] * axis
        return out
    k = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    s, c = np.sin(q)[:, None, None], np.cos(q)[:, None, None]
    out[:, :3, :3] = np.eye(3) + s * k + (1 - c) * (k @ k)  # Rodrigues
    # about the axis line through axis_point p: x -> p + R (x - p)
    p = np.asarray(joint.axis_point, dtype=np.float64)
    out[:, :3, 3] = p - out[:, :3, :3] @ p
    return out


def _range(joint: Joint) -> tuple[float, float]:
    if joint.type == "prismatic":
        lo, hi = joint.lower or 0.0, joint.upper or 0.0
    elif joint.type == "continuous" or joint.lower is None or joint.upper is None:
        lo, hi = _TURN
    else:
        lo, hi = joint.lower, joint.upper
    return (lo, hi) if lo <= hi else (hi, lo)


def robot_statics(robot: Robot, bodies: Mapping[str, Body], *, samples: int = SAMPLES,
                  seed: int = 0, max_work: int = MAX_WORK) -> Statics:
    """The robot's statics (see the module docstring) from ``bodies`` by link name.

    The configurations sampled are bounded by ``max_work`` (see :data:`MAX_WORK`): a large
    robot gets fewer random samples and fewer refined joints, said in ``Statics.note``.
    """
    names = {link.name for link in robot.links}
    parent_joint: dict[str, Joint] = {}
    for j in robot.joints:
        if j.child in names and j.parent in names:
            parent_joint.setdefault(j.child, j)
    order = _topological(robot, parent_joint)
    free = [j for j in robot.joints if j.type in _MOVING and j.mimic is None
            and parent_joint.get(j.child) is j]
    # the cost of one configuration: every link placed, every joint's subtree summed
    per_config = len(order) + sum(_subtree_sizes(order, parent_joint).values())
    budget = max(max_work // max(per_config, 1), 3 + MIN_SAMPLES)
    drawn = min(samples, budget - 3)
    rng = np.random.default_rng(seed)
    ranges = np.array([_range(j) for j in free]).reshape(-1, 2)
    cols = [np.clip(0.0, ranges[:, 0], ranges[:, 1])]  # the zero pose, where in range
    if len(free):
        cols += [ranges[:, 0], ranges[:, 1]]
        cols += list(ranges[:, 0] + (ranges[:, 1] - ranges[:, 0]) * rng.random((drawn,
                                                                                 len(free))))
    q = np.array(cols)  # (n, joints)
    index = {j.name: i for i, j in enumerate(free)}
    per_joint, folded = _per_joint(robot, bodies, parent_joint, order, index, q)
    rows = {name: np.ones(len(q), dtype=bool) for name in per_joint}
    wanted: list[tuple[float, str]] = []
    refined: list[str] = []
    grid = np.linspace(0.0, 1.0, min(9, max(2, MAX_SWEEP // max(len(free), 1))))
    size = len(free) * len(grid)
    if len(free):
        # refine: from each joint's worst sample, sweep every joint over its range once,
        # the joints nearest their limit first while the budget lasts
        efforts = {j.name: j.effort for j in robot.joints}
        for name, (nom, _) in per_joint.items():
            effort = efforts.get(name)
            if effort is None or effort <= 0 or np.max(np.abs(nom)) < REFINE_FROM * effort:
                continue  # passive, or far from its limit: the samples decide
            wanted.append((-float(np.max(np.abs(nom))) / effort, name))
        room = max(budget - len(q), 0) // size
        blocks = []
        for _, name in sorted(wanted)[:room]:
            start = q[int(np.argmax(np.abs(per_joint[name][0])))]
            block = np.repeat(start[None, :], size, axis=0)
            for k in range(len(free)):
                block[k * len(grid):(k + 1) * len(grid), k] = (
                    ranges[k, 0] + grid * (ranges[k, 1] - ranges[k, 0]))
            blocks.append(block)
            refined.append(name)
        extra = np.vstack(blocks) if blocks else np.zeros((0, len(free)))
        more, _ = _per_joint(robot, bodies, parent_joint, order, index, extra)
        for i, name in enumerate(refined):
            mask = np.zeros(len(extra), dtype=bool)
            mask[i * size:(i + 1) * size] = True
            per_joint[name] = (np.concatenate([per_joint[name][0], more[name][0]]),
                               np.concatenate([per_joint[name][1], more[name][1]]))
            rows[name] = np.concatenate([rows[name], mask])
    loads = []
    for j in robot.joints:
        if j.name not in per_joint or (j.mimic is not None and j.mimic[0] in per_joint):
            continue
        nom, spr = (v[rows[j.name]] for v in per_joint[j.name])
        passive = j.effort is None or j.effort <= 0
        loads.append(JointLoad(j, float(np.max(np.abs(nom))),
                               max(float(np.max(np.abs(nom) - spr)), 0.0),
                               float(np.max(np.abs(nom) + spr)), j.effort, passive,
                               "N" if j.type == "prismatic" else "N m",
                               tuple(folded.get(j.name, ()))))
    zero = _poses(order, parent_joint, index, np.zeros((1, len(free))))
    total = sum(b.mass for name, b in bodies.items() if name in zero)
    com = np.zeros(3)
    for name, b in bodies.items():
        if name in zero:
            com += b.mass * (zero[name][0, :3, :3] @ b.com + zero[name][0, :3, 3])
    com = com / total if total > 0 else com
    note = ""
    if drawn < samples or len(refined) < len(wanted) or (refined and len(grid) < 9):
        note = (f"statics sampled {len(q)} configurations, not {3 + samples}, and refined "
                f"{len(refined)} of {len(wanted)} joints near their limit"
                + (f" on {len(grid)} points per joint, not 9" if len(grid) < 9 and refined
                   else "")
                + f" ({len(order)} links): the loads found may be below the largest")
    return Statics(float(total), com, tuple(loads), note, len(q) + len(refined) * size)


def _subtree_sizes(order: list[str], parent_joint: dict[str, Joint]) -> dict[str, int]:
    """Links in each link's subtree (itself included)."""
    size = dict.fromkeys(order, 1)
    for name in reversed(order):
        j = parent_joint.get(name)
        if j is not None and j.parent in size:
            size[j.parent] += size[name]
    return size


def _topological(robot: Robot, parent_joint: dict[str, Joint]) -> list[str]:
    children: dict[str, list[str]] = {}
    for child, j in parent_joint.items():
        children.setdefault(j.parent, []).append(child)
    roots = [link.name for link in robot.links if link.name not in parent_joint]
    order, stack, seen = [], list(reversed(roots)), set()
    while stack:
        name = stack.pop()
        if name in seen:
            continue
        seen.add(name)
        order.append(name)
        stack.extend(reversed(children.get(name, [])))
    return order


def _poses(order: list[str], parent_joint: dict[str, Joint], index: dict[str, int],
           q: np.ndarray) -> dict[str, np.ndarray]:
    """(n, 4, 4) pose of every link in the root's frame at the ``n`` configurations ``q``."""
    n = len(q)
    poses: dict[str, np.ndarray] = {}
    for name in order:
        j = parent_joint.get(name)
        if j is None:
            poses[name] = np.tile(np.eye(4), (n, 1, 1))
            continue
        if j.parent not in poses:
            continue
        if j.mimic is not None and j.mimic[0] in index:
            values = q[:, index[j.mimic[0]]] * j.mimic[1] + j.mimic[2]
        elif j.name in index:
            values = q[:, index[j.name]]
        else:
            values = np.zeros(n)
        origin = pose_matrix(j.origin.xyz, j.origin.rpy)
        poses[name] = poses[j.parent] @ origin @ _motion(j, values)
    return poses


def _per_joint(robot: Robot, bodies: Mapping[str, Body], parent_joint: dict[str, Joint],
               order: list[str], index: dict[str, int], q: np.ndarray,
               ) -> tuple[dict[str, tuple[np.ndarray, np.ndarray]], dict[str, list[str]]]:
    """Per joint, its signed gravity load at each configuration of ``q`` and the spread of
    the derived links' band; and the mimic joints folded into each joint."""
    poses = _poses(order, parent_joint, index, q)
    g = np.array([0.0, 0.0, -GRAVITY])
    # every link's mass, band and CoM per configuration, in the depth-first order of
    # `order`: a subtree is a contiguous run of it (its root, then `sizes` - 1 more)
    placed = [name for name in order if name in poses]
    at = np.zeros((len(placed), len(q), 3))
    mass = np.zeros(len(placed))
    band = np.zeros(len(placed))
    for i, name in enumerate(placed):
        b = bodies.get(name)
        if b is not None:
            p = poses[name]
            at[i] = p[:, :3, :3] @ b.com + p[:, :3, 3]
            mass[i], band[i] = b.mass, b.band
    where = {name: i for i, name in enumerate(placed)}
    sizes = _subtree_sizes(placed, parent_joint)
    per_joint: dict[str, tuple[np.ndarray, np.ndarray]] = {}
    for j in robot.joints:
        if j.type not in _MOVING or parent_joint.get(j.child) is not j or j.child not in poses:
            continue
        frame = poses[j.child]  # the joint frame moved: its origin and axis
        axis = np.asarray(j.axis, dtype=np.float64)
        axis = axis / max(float(np.linalg.norm(axis)), 1e-300)
        axis_w = frame[:, :3, :3] @ axis
        run = slice(where[j.child], where[j.child] + sizes[j.child])
        if j.type == "prismatic":
            parts = mass[run, None] * (axis_w @ g)[None, :]
        else:
            # axis . ((at - pivot) x m g) = m (at - pivot) . (g x axis)
            pivot = frame[:, :3, :3] @ np.asarray(j.axis_point) + frame[:, :3, 3]
            lever = np.cross(g, axis_w)
            parts = mass[run, None] * (np.einsum("lnk,nk->ln", at[run], lever)
                                       - np.einsum("nk,nk->n", pivot, lever)[None, :])
        per_joint[j.name] = (parts.sum(axis=0), (band[run, None] * np.abs(parts)).sum(axis=0))
    # mimic joints: their actuator is the joint they mimic
    folded: dict[str, list[str]] = {}
    for j in robot.joints:
        if j.mimic is not None and j.name in per_joint and j.mimic[0] in per_joint:
            nom, spr = per_joint[j.mimic[0]]
            mnom, mspr = per_joint[j.name]
            per_joint[j.mimic[0]] = (nom + j.mimic[1] * mnom, spr + abs(j.mimic[1]) * mspr)
            folded.setdefault(j.mimic[0], []).append(j.name)
    return per_joint, folded


def statics_findings(robot: Robot, statics: Statics, margin: float = DEFAULT_MARGIN,
                     ) -> list[Finding]:
    """The findings of :func:`robot_statics`'s result (see the module docstring)."""
    out: list[Finding] = []
    if statics.note:
        out.append(Finding(Rule.STATICS_COARSENED, None, statics.note))
    for load in statics.loads:
        j = load.joint
        child = j.child
        band = (f" ({load.low:.3g}..{load.high:.3g} with the derived links' band)"
                if load.high > load.low + 1e-12 else "")
        mimics = f"; with mimic joint(s) {', '.join(load.mimics)}" if load.mimics else ""
        needed = (f"joint '{j.name}' must hold up to {load.needed:.3g} {load.unit} against "
                  f"gravity over its range{band}{mimics}")
        if load.passive or load.effort is None:
            continue
        if load.low > load.effort:
            out.append(Finding(Rule.JOINT_CANNOT_HOLD, child,
                               f"{needed}, above its effort limit {load.effort:g} "
                               f"{load.unit}", j.line))
        elif load.high > load.effort:
            out.append(Finding(Rule.JOINT_MAY_NOT_HOLD, child,
                               f"{needed}: its effort limit {load.effort:g} {load.unit} "
                               "holds it only at the band's low end", j.line))
        elif load.high > (1 - margin) * load.effort:
            out.append(Finding(Rule.JOINT_EFFORT_MARGIN, child,
                               f"{needed}, {100 * load.high / load.effort:.0f} % of its "
                               f"effort limit {load.effort:g} {load.unit} (margin "
                               f"{100 * margin:.0f} %)", j.line))
    return out
