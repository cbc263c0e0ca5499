"""One answer per link: the [`LinkResult`][urdfinertia.plan.results.LinkResult] verdict,
and the [`FixResult`][urdfinertia.plan.results.FixResult] of a file.

A [`LinkResult`][urdfinertia.plan.results.LinkResult] is made once, by
`urdfinertia.plan.fix.link_verdicts`, and rendered by every command (`fix`, `check`,
`compare`, `explain`, `report`), by their JSON, SARIF and annotations, and by the Python
API. It carries the link's findings (each with its rule: the one channel of everything said
about the link), the plan's [`Action`][urdfinertia.plan.results.Action] with its grounds
(the rules it answers) and, where `fix` keeps or leaves a link despite findings, the rule
that says why; what was kept and what derived, the values before and after, the error bar
of a derived tensor, the geometry choice and the slip undone. Every text a surface shows is
rendered from these by `describe`.
"""

from __future__ import annotations

from dataclasses import dataclass
from enum import StrEnum
from pathlib import Path
from typing import TYPE_CHECKING

from urdfinertia.findings import Finding
from urdfinertia.rules import Rule, Scope, Severity

if TYPE_CHECKING:
    from urdfinertia.body.assemble import Assembly
    from urdfinertia.body.errorbar import ErrorBar
    from urdfinertia.body.geometry_choice import GeometryChoice
    from urdfinertia.descriptions.model import Inertial, Robot
    from urdfinertia.errors import UrdfError
    from urdfinertia.inertia.massprops import MassProperties
    from urdfinertia.judge.slips import SlipProposal
    from urdfinertia.plan.save import SaveReport
    from urdfinertia.plan.total_mass import TargetOutcome


class Status(StrEnum):
    """What happened to a link's inertial (string values: JSON stays readable)."""

    RECOMPUTED = "recomputed"
    """Derived from the geometry (or a spec), the trusted values kept."""
    REPAIRED = "repaired"
    """The minimal repair, or a slip undone: the values the author meant."""
    KEPT = "kept"
    """Plausible: kept byte for byte."""
    UNTOUCHED = "untouched"
    """Nothing to do or nothing to compute from: left byte for byte."""
    LEFT = "left"
    """It should have been changed but could not be: left as written
    ([`reason`][urdfinertia.plan.results.LinkResult.reason] says why).
    """


class Action(StrEnum):
    """What the plan decided for a link (`urdfinertia.plan.policy`)."""

    RECOMPUTE = "recompute"
    """Derive the values it distrusts from the geometry (or a spec), keep the rest."""
    KEEP = "keep"
    """Keep the written values byte for byte."""
    REPAIR = "repair"
    """The minimal repair of an invalid tensor (nothing to derive from)."""
    LEAVE = "leave"
    """Leave the link as it is (a frame; or nothing usable: then it is "left")."""
    CORRECT = "correct"
    """Undo a slip: one edit of the written values (`urdfinertia.judge.slips`)."""


#: Statuses whose inertial the output carries changed.
CHANGED = frozenset({Status.RECOMPUTED, Status.REPAIRED})
#: The findings that say some of a link's geometry could not be read (not verified).
UNREAD = frozenset({Rule.MESH_UNRESOLVED, Rule.GEOMETRY_UNREADABLE, Rule.MESH_TOO_LARGE,
                    Rule.MESH_REFUSED, Rule.MESH_ABSURD})
#: How a "because" rule reads in the decision of a link kept ("kept: {phrase}"), where
#: its finding's own message is not the phrase.
_BECAUSE_KEPT = {
    Rule.GEOMETRY_UNREADABLE: "valid as written; not verified against its geometry "
                              "(unreadable)",
    Rule.MESH_UNRESOLVED: "valid as written; not verified against its geometry (a mesh "
                          "does not resolve)",
    Rule.MESH_TOO_LARGE: "valid as written; not verified against its geometry (a mesh "
                         "over the limits)",
}
#: How a "because" rule reads in any other decision (or a kept one it has no phrase for).
_BECAUSE = {
    Rule.GEOMETRY_UNREADABLE: "geometry could not be read",
    Rule.MESH_UNRESOLVED: "geometry could not be read",
    Rule.MESH_TOO_LARGE: "geometry could not be read",
    Rule.MESH_REFUSED: "geometry could not be read",
    Rule.MESH_ABSURD: "geometry could not be read",
    Rule.NOT_ASKED: "not named",
    Rule.AUTO_INERTIAL_KEPT: "auto inertia kept (--keep-auto): the simulator computes it",
    Rule.INERTIAL_FROM_GEOMS: "computed by the simulator from its geometry: left as it is",
    Rule.NO_GEOMETRY: "no geometry to recompute from",
    Rule.NEGLIGIBLE_BODY: "under 0.1 % of the robot's mass: left as it is",
    Rule.SPEC_NAMED: "named in the spec",
    Rule.ASKED: "every link asked for",
}
_PAST = {Action.RECOMPUTE: "recomputed", Action.KEEP: "kept", Action.REPAIR: "repaired",
         Action.CORRECT: "corrected", Action.LEAVE: "left"}


@dataclass(frozen=True, eq=False)
class LinkResult:
    """One link's verdict: what `fix` does with it and why, rendered by every command.

    Attributes
    ----------
    name : str
    status : Status
        What the output carries.
    action : Action
        What the plan decided.
    findings : tuple of Finding
        Everything said about the link: the reader's, the judgement's and what carrying
        the plan out found (a mesh repaired, a derived density no material has).
    grounds : tuple of Rule
        The findings the action answers ("placeholder-inertia" for a recompute).
    because : Rule or None
        Why the link is kept or left despite its findings, or why it is left
        ("geometry-not-body", "no-geometry"); None when nothing needs saying.
    geometry : str
        What the output's values come from: "collision", "visual", "geom", "spec",
        "none" or "as written".
    assembly : Assembly or None
        The new values and their parts (None: the written values stay).
    previous : Inertial or None
        The `<inertial>` as written.
    kept, derived : tuple of str
        Which of "mass", "com", "tensor" were kept as written and which derived.
    error_bar : ErrorBar or None
        The expected error of a tensor derived from homogeneous geometry.
    choice : GeometryChoice or None
        Which geometry a derived inertial integrates, and why.
    slip : SlipProposal or None
        The slip undone (action "correct").
    stated_mass : float or None
        A mass the description states without an inertial (a USD MassAPI's mass with no
        inertia): it counts in the robot's written total.
    """

    name: str
    status: Status
    action: Action
    findings: tuple[Finding, ...] = ()
    grounds: tuple[Rule, ...] = ()
    because: Rule | None = None
    geometry: str = "as written"
    assembly: Assembly | None = None
    previous: Inertial | None = None
    kept: tuple[str, ...] = ()
    derived: tuple[str, ...] = ()
    error_bar: ErrorBar | None = None
    choice: GeometryChoice | None = None
    slip: SlipProposal | None = None
    stated_mass: float | None = None

    def __post_init__(self) -> None:
        object.__setattr__(self, "status", Status(self.status))
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
        import numpy as np

        from urdfinertia.descriptions.inertial import RawInertial

        with np.errstate(all="ignore"):
            return RawInertial.from_inertial(self.previous).mass_properties()

    @property
    def after(self) -> MassProperties | None:
        """What the output carries: the new values, else the written ones (None: none)."""
        if self.changed:
            assert self.assembly is not None
            return self.assembly.total
        return self.before

    @property
    def why(self) -> str:
        """The action's reason in plain words: its grounds ("placeholder-inertia"), then
        what the "because" rule says ("geometry is a marker, not the body"); "plausible"
        for a link kept with nothing to say."""
        parts = [", ".join(self.grounds), self.because_text()]
        text = "; ".join(p for p in parts if p)
        return text or ("plausible" if self.action == Action.KEEP else "")

    def because_text(self) -> str:
        """The "because" rule in words: for a link kept or left as it is, its phrase
        ("not named"); else (and when it has none) its finding's message, which says what
        exactly (the mesh that is missing)."""
        if self.because is None:
            return ""
        phrase = (_BECAUSE_KEPT.get(self.because) if self.status == Status.KEPT
                  else None) or _BECAUSE.get(self.because)
        if phrase is not None and (self.status != Status.LEFT
                                   or self.because not in UNREAD | {Rule.NO_GEOMETRY}):
            return phrase
        for f in reversed(self.findings):  # the plan's own note, made last, first
            if f.rule == self.because:
                return f"{f.element}: {f.message}" if f.element and \
                    self.status == Status.LEFT else f.message
        return phrase or self.because.summary

    @property
    def decision(self) -> str:
        """The decision in one phrase, as `fix` says it ("kept: plausible")."""
        return describe(self, done=True)

    @property
    def planned(self) -> str:
        """The decision as a plan, as `check` says it ("would be kept: plausible")."""
        return describe(self, done=False)

    @property
    def reason(self) -> str | None:
        """Why a link was left as it was (status "left"), else None: what needed changing
        and why it could not be ("placeholder-inertia; no geometry to recompute from")."""
        if self.status != Status.LEFT:
            return None
        return self.why or "left as it was"

    @property
    def unverified(self) -> tuple[Finding, ...]:
        """What of the link's geometry could not be read (it was not verified)."""
        return tuple(f for f in self.findings if f.rule in UNREAD)

    @property
    def verified(self) -> bool:
        """Everything asked for could be read (no geometry unresolved or unreadable)."""
        return not self.unverified

    @property
    def dropped(self) -> tuple[Finding, ...]:
        """The elements left out of the link's inertia (each with its cause)."""
        return tuple(f for f in self.findings if f.rule.scope == Scope.ELEMENT
                     and f.severity != Severity.INFO)

    def keeps(self, finding: Finding) -> bool:
        """`fix` keeps the value `finding` is about, on purpose, and says why (`check
        --strict` does not fail on it): an info, or a finding on the values of a link
        that `fix` keeps as written or leaves on purpose (a frame on a fixed joint, a
        negligible part: [`Status.UNTOUCHED`][urdfinertia.plan.results.Status.UNTOUCHED])."""
        if finding.severity == Severity.INFO:
            return True
        return (finding.link == self.name and self.status in (Status.KEPT, Status.UNTOUCHED)
                and finding.rule.scope in (Scope.INERTIAL, Scope.LINK))

    @property
    def size(self) -> float:
        """A length scale of the link (radius of gyration plus CoM offset), m."""
        if self.assembly is None:
            return 0.0
        import numpy as np

        t = self.assembly.total
        return float(np.sqrt(np.trace(t.inertia) / t.mass) + np.linalg.norm(t.com))


def describe(r: LinkResult, done: bool = True) -> str:
    """The decision of ``r`` in words: "recomputed: placeholder-inertia" after a fix,
    "would be recomputed: ..." before one (``done=False``)."""
    verb = _PAST[r.action]
    if r.status == Status.LEFT:
        verb = "left as it was"
        return f"{verb if done else 'would be ' + verb}: {r.reason}"
    if r.action == Action.LEAVE:
        return r.why if "left as it is" in r.why else f"left as it is: {r.why}"
    if r.action == Action.CORRECT and r.slip is not None:
        text = f"{r.slip.edit} (slip: {', '.join(r.grounds)})" if r.grounds else r.slip.edit
    else:
        text = r.why
    return f"{verb if done else 'would be ' + verb}: {text}"


def strict_blocking(f: Finding) -> bool:
    """An element of a link dropped, or a value of its inertial that could not be read:
    ``fix --strict`` writes nothing (a joint's value is never needed for inertials)."""
    if f.link is None or f.severity == Severity.INFO or f.rule in _READ_AS_WRITTEN:
        return False
    return f.rule.scope == Scope.ELEMENT


#: Element findings that read the element anyway (``--strict`` does not refuse them).
_READ_AS_WRITTEN = frozenset({Rule.VALUE_UNREADABLE, Rule.VECTOR_COMMAS})


@dataclass(frozen=True, eq=False)
class FixResult:
    """A file's verdicts and its patched document (`output`; the input is `original`).

    Attributes
    ----------
    path : Path
    robot : Robot
    links : tuple of LinkResult
        Every link's verdict, in document order.
    original, output : bytes
        The document as read and as `fix` writes it.
    targets : tuple of TargetOutcome
        The target masses met, innermost first.
    findings : tuple of Finding
        What is said of the robot as a whole (the reader's notes on the document, the
        conventions inferred, the change of its total mass).
    """

    path: Path
    robot: Robot
    links: tuple[LinkResult, ...]
    original: bytes
    output: bytes
    targets: tuple[TargetOutcome, ...] = ()
    robot_findings: tuple[Finding, ...] = ()

    @property
    def changed(self) -> bool:
        """The output differs from the input."""
        return self.output != self.original

    def link(self, name: str) -> LinkResult:
        """The verdict of link `name` (KeyError if there is none)."""
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
        """Every finding: the robot's, then every link's, in link order."""
        return self.robot_findings + tuple(f for r in self.links for f in r.findings)

    @property
    def unverified(self) -> tuple[LinkResult, ...]:
        """Links some of whose geometry could not be read: they were not verified."""
        return tuple(r for r in self.links if r.unverified)

    @property
    def left(self) -> tuple[LinkResult, ...]:
        """Links that should have been changed and were left as they were."""
        return tuple(r for r in self.links if r.status == Status.LEFT)

    def save(self, path: str | Path | None = None, *, in_place: bool = False,
             backup: bool = True, keep_mesh_paths: bool = False) -> SaveReport:
        """Write the fixed document, as `urdf-inertia fix -o PATH` (or `--in-place`).

        Relative references are rewritten to resolve from `path`'s folder, the write is
        atomic, and `in_place` keeps `<input>.bak` unless `backup=False`. See
        [`save_result`][urdfinertia.plan.save.save_result] for the parameters and errors.

        Returns
        -------
        SaveReport
            The file written, whether it was, and the references rewritten.
        """
        from urdfinertia.plan.save import save_result

        return save_result(self, path, in_place=in_place, backup=backup,
                           keep_mesh_paths=keep_mesh_paths)

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
        """What `--strict` refuses: the first element dropped or value of a link not
        read, else the first link left as it was; None when the result is whole."""
        from urdfinertia.errors import UrdfError

        for f in self.findings:
            if strict_blocking(f):
                cause = f"{f.element}: {f.message}" if f.element else f.message
                return UrdfError(cause, file=self.path, line=f.line, link=f.link)
        left = self.left
        return self.left_error(left[0]) if left else None
