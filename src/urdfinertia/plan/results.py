"""One answer per link: the :class:`LinkResult` verdict, and the :class:`FixResult` of a file.

A :class:`LinkResult` is computed once, by :func:`urdfinertia.plan.fix.link_verdicts`, and
rendered by every command (``fix``, ``check``, ``compare``, ``explain``, ``report``), by
their JSON, SARIF and annotations, and by the Python API. It carries the link's findings
(with rule ids), the decision (:class:`Action`) and its reason in plain words, what was
kept and what derived, the values before and after, the error bar of a derived tensor,
and what could not be verified.
"""

from __future__ import annotations

from dataclasses import dataclass
from enum import StrEnum
from pathlib import Path
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from urdfinertia.body.assemble import Assembly
    from urdfinertia.body.errorbar import ErrorBar
    from urdfinertia.body.geometry_choice import GeometryChoice
    from urdfinertia.descriptions.model import Inertial, Problem, Robot
    from urdfinertia.errors import UrdfError
    from urdfinertia.findings import Finding
    from urdfinertia.inertia.massprops import MassProperties
    from urdfinertia.judge.slips import SlipProposal
    from urdfinertia.plan.save import SaveReport
    from urdfinertia.plan.total_mass import TargetOutcome


class Status(StrEnum):
    """What happened to a link's inertial (string values: JSON stays readable)."""

    #: derived from the geometry (or a spec), the trusted values kept
    RECOMPUTED = "recomputed"
    #: the minimal repair: mass and CoM kept, the tensor lifted (or a smallest body given)
    REPAIRED = "repaired"
    #: plausible: kept byte for byte
    KEPT = "kept"
    #: nothing to do or nothing to compute from: left byte for byte
    UNTOUCHED = "untouched"
    #: it should have been computed but could not be: left as written (``reason`` says why)
    LEFT = "left"


class Action(StrEnum):
    """What the policy decided for a link (:mod:`urdfinertia.plan.policy`)."""

    RECOMPUTE = "recompute"
    KEEP = "keep"
    REPAIR = "repair"
    LEAVE = "leave"
    #: undo a slip: one edit of the written values (:mod:`urdfinertia.judge.slips`)
    CORRECT = "correct"


#: Statuses whose inertial the output carries changed.
CHANGED = frozenset({Status.RECOMPUTED, Status.REPAIRED})


#: Problem kinds that ``--strict`` refuses ("lenient" readings are warnings even then).
STRICT_KINDS = ("dropped", "ignored")


@dataclass(frozen=True, eq=False)
class LinkResult:
    """One link's verdict: what ``fix`` does with it and why, rendered by every command.

    status : :class:`Status` (what the output carries); ``reason`` says why a link was
        left as it was.
    action, why, decision : the policy's :class:`Action`, its reason in plain words, and
        both in one phrase ("kept: plausible", "recomputed: inertia-zero").
    kept, derived : which of "mass", "com", "tensor" were kept as written and which derived.
    previous, before, after : the ``<inertial>`` as written, its values, and what the
        output carries (:class:`~urdfinertia.inertia.massprops.MassProperties`).
    findings : what ``check`` reports about the link as written.
    unverified : what could not be read (unresolved or unreadable meshes).
    problems : the link's elements dropped and values ignored (read and compute time).
    """

    name: str
    status: Status
    geometry: str  # "collision" | "visual" | "spec" | "none" | "as written"
    assembly: Assembly | None
    previous: Inertial | None
    warnings: tuple[str, ...] = ()
    problems: tuple[Problem, ...] = ()
    reason: str | None = None
    #: the policy's decision in words ("kept: plausible", "recomputed: inertia-zero", ...)
    decision: str = ""
    #: which of "mass", "com", "tensor" were kept as written and which derived
    kept: tuple[str, ...] = ()
    derived: tuple[str, ...] = ()
    #: expected error of a tensor derived from homogeneous geometry (None otherwise)
    error_bar: ErrorBar | None = None
    #: the policy's action (None: computed outside the policy, e.g. ``explain``)
    action: Action | None = None
    #: why, in plain words ("plausible", "inertia-zero, com-outside-geometry", ...)
    why: str = ""
    #: what ``check`` reports about the link as written, rule ids with them
    findings: tuple[Finding, ...] = ()
    #: what could not be verified, e.g. "mesh meshes/arm.stl: cannot resolve package 'x'"
    unverified: tuple[str, ...] = ()
    #: which geometry a derived inertial integrates, and why (None: none derived)
    choice: GeometryChoice | None = None
    #: the slip undone (action "correct") or proposed (:mod:`urdfinertia.judge.slips`)
    slip: SlipProposal | None = None

    def __post_init__(self) -> None:
        object.__setattr__(self, "status", Status(self.status))
        if self.action is not None:
            object.__setattr__(self, "action", Action(self.action))

    @property
    def changed(self) -> bool:
        """The output carries a new inertial for this link."""
        return self.status in CHANGED and self.assembly is not None

    @property
    def before(self) -> MassProperties | None:
        """The inertial as written (link frame, about its CoM); None if absent or invalid."""
        if self.previous is None:
            return None
        from urdfinertia.descriptions.inertial import RawInertial

        return RawInertial.from_inertial(self.previous).mass_properties()

    @property
    def after(self) -> MassProperties | None:
        """What the output carries: the new values, else the written ones (None: none)."""
        if self.changed:
            assert self.assembly is not None
            return self.assembly.total
        return self.before

    @property
    def planned(self) -> str:
        """The decision as a plan, as ``check`` says it: "would be kept: plausible"."""
        if self.decision.startswith(("recomputed", "kept", "repaired", "left", "corrected")):
            return "would be " + self.decision
        return self.decision

    @property
    def verified(self) -> bool:
        """Everything asked for could be read (no geometry unresolved or unreadable)."""
        return not self.unverified

    @property
    def size(self) -> float:
        """A length scale of the link (radius of gyration plus CoM offset), m."""
        if self.assembly is None:
            return 0.0
        import numpy as np

        t = self.assembly.total
        return float(np.sqrt(np.trace(t.inertia) / t.mass) + np.linalg.norm(t.com))


@dataclass(frozen=True, eq=False)
class FixResult:
    """A file's verdicts and its patched document (``output``; the input is ``original``).

    Saving the output where it belongs (relocated references, atomic write) is
    :mod:`urdfinertia.plan.save`'s job.
    """

    path: Path
    robot: Robot
    links: tuple[LinkResult, ...]
    original: bytes
    output: bytes
    #: the target masses met (:mod:`urdfinertia.plan.total_mass`), innermost first
    targets: tuple[TargetOutcome, ...] = ()

    @property
    def changed(self) -> bool:
        return self.output != self.original

    def link(self, name: str) -> LinkResult:
        """The verdict of link ``name`` (KeyError if there is none)."""
        for r in self.links:
            if r.name == name:
                return r
        raise KeyError(name)

    @property
    def recomputed(self) -> tuple[str, ...]:
        """Names of the links recomputed from their geometry (or a spec)."""
        return tuple(r.name for r in self.links if r.status == Status.RECOMPUTED)

    @property
    def changed_links(self) -> tuple[str, ...]:
        """Names of the links whose inertial the output changes (recomputed or repaired)."""
        return tuple(r.name for r in self.links if r.changed)

    @property
    def findings(self) -> tuple[Finding, ...]:
        """Every link's findings, in link order."""
        return tuple(f for r in self.links for f in r.findings)

    @property
    def unverified(self) -> tuple[LinkResult, ...]:
        """Links some of whose geometry could not be read: they were not verified."""
        return tuple(r for r in self.links if r.unverified)
    def save(self, path: str | Path | None = None, *, in_place: bool = False,
             backup: bool = True, keep_mesh_paths: bool = False) -> SaveReport:
        """Write the fixed document, as ``urdf-inertia fix -o PATH`` (or ``--in-place``).

        Relative references are rewritten to resolve from ``path``'s folder, the write is
        atomic, and ``in_place`` keeps ``<input>.bak`` unless ``backup=False``. See
        :func:`urdfinertia.plan.save.save_result` for the parameters and errors.

        Returns
        -------
        SaveReport
            The file written, whether it was, and the references rewritten.
        """
        from urdfinertia.plan.save import save_result

        return save_result(self, path, in_place=in_place, backup=backup,
                           keep_mesh_paths=keep_mesh_paths)

    @property
    def left(self) -> tuple[LinkResult, ...]:
        """Links that should have been computed and were left as they were."""
        return tuple(r for r in self.links if r.status == Status.LEFT)

    def left_error(self, r: LinkResult) -> UrdfError:
        """A link left as it was, as an error naming file, line and link."""
        from urdfinertia.errors import UrdfError

        line = r.previous.line if r.previous is not None else None
        if line is None:
            try:
                line = self.robot.link(r.name).line
            except KeyError:
                pass
        return UrdfError(r.reason or "left as it was", file=self.path, line=line,
                         link=r.name)

    def strict_refusal(self) -> UrdfError | None:
        """What ``--strict`` refuses: the first element dropped or value ignored, else
        the first link left as it was; None when the result is whole."""
        from urdfinertia.errors import UrdfError

        for p in self.problems:
            # a joint's value is never needed for inertials: not even --strict refuses it
            if p.kind in STRICT_KINDS and p.link is not None:
                cause = f"{p.element}: {p.cause}" if p.element else p.cause
                return UrdfError(cause, file=self.path, line=p.line, link=p.link)
        left = self.left
        return self.left_error(left[0]) if left else None

    @property
    def problems(self) -> tuple[Problem, ...]:
        """Everything read past: the document's own notes, then each link's problems."""
        own = tuple(p for p in self.robot.problems if p.link is None)
        return own + tuple(p for r in self.links for p in r.problems)
