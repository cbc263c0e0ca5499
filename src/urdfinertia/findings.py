"""What ``check`` reports and ``fix``'s policy acts on: :class:`Finding`, with one stable
rule id per kind of finding (:data:`RULES`: SARIF ``ruleId``, baselines).

Severities: "error" (a simulator refuses or misbehaves), "warning" (very likely wrong),
"info" (worth knowing, e.g. masses lumped by fixed joints).
"""

from __future__ import annotations

from dataclasses import dataclass

SEVERITIES = ("error", "warning", "info")


@dataclass(frozen=True)
class Rule:
    """A kind of finding: ``id`` is stable across versions (SARIF ``ruleId``, baselines);
    ``element`` is what a finding of this kind points at in the file ("inertial", "link" or
    "robot"); ``severity`` is the usual one (SARIF's default level)."""

    id: str
    code: str
    element: str
    severity: str
    summary: str


def _rules(*rows: tuple[str, str, str, str, str]) -> dict[str, Rule]:
    return {code: Rule(rid, code, element, severity, summary)
            for rid, code, element, severity, summary in rows}


#: Every kind of finding, by code: the ONE place rule ids are given. An id is never reused
#: or renumbered (baselines and code-scanning alerts are keyed on it); add new kinds at the
#: end of their block. UI1xx: the written values; UI2xx: against the geometry; UI3xx:
#: the robot as simulators merge it; UI4xx: loading and stepping in the engines; UI5xx:
#: what the reader read past that other loaders refuse; UI6xx: what the author meant;
#: UI7xx: the whole robot: masses and statics.
RULES: dict[str, Rule] = _rules(
    ("UI101", "missing-inertial", "link", "error", "a moving link has no <inertial>"),
    ("UI102", "mass-not-finite", "inertial", "error", "mass is NaN or infinite"),
    ("UI103", "mass-not-positive", "inertial", "error", "a moving link's mass is <= 0"),
    ("UI104", "massless-frame", "inertial", "info", "zero mass on a link that does not move"),
    ("UI105", "com-not-finite", "inertial", "error", "CoM origin is NaN or infinite"),
    ("UI106", "inertia-not-finite", "inertial", "error", "inertia tensor has NaN/inf"),
    ("UI107", "inertia-zero", "inertial", "error", "mass with a zero inertia tensor"),
    ("UI108", "inertia-not-symmetric", "inertial", "error", "inertia tensor not symmetric"),
    ("UI109", "inertia-not-positive-definite", "inertial", "error",
     "inertia tensor not positive definite"),
    ("UI110", "triangle-inequality", "inertial", "error",
     "principal moments violate A + B >= C"),
    ("UI111", "placeholder-inertia", "inertial", "warning",
     "equal diagonal, no products: a placeholder tensor"),
    ("UI112", "mass-absurd", "inertial", "error",
     "a mass no robot link has (a unit slip such as mm^3 read as m^3)"),
    ("UI113", "inertia-absurd", "inertial", "error", "inertia components no robot link has"),
    ("UI114", "usd-negative-mass", "inertial", "error", "USD MassAPI: physics:mass < 0"),
    ("UI115", "usd-negative-density", "inertial", "error", "USD MassAPI: physics:density < 0"),
    ("UI116", "usd-density-without-mass", "inertial", "warning",
     "USD MassAPI: density given where mass is not (SimReady: give the mass)"),
    ("UI117", "usd-diagonal-inertia-invalid", "inertial", "error",
     "USD MassAPI: diagonalInertia negative or violating A + B >= C"),
    ("UI118", "usd-principal-axes-not-unit", "inertial", "error",
     "USD MassAPI: principalAxes is not a unit quaternion"),
    ("UI119", "usd-newton-mass-disagrees", "inertial", "warning",
     "USD: newton:inertia and the MassAPI tensor differ (engines disagree)"),
    ("UI201", "geometry-unreadable", "link", "warning", "the link's geometry cannot be read"),
    ("UI202", "implausible-density", "inertial", "warning",
     "mass / geometry volume is no material's density"),
    ("UI203", "com-outside-geometry", "inertial", "warning",
     "CoM far outside the geometry's bounding box"),
    ("UI204", "inertia-vs-geometry", "inertial", "warning",
     "tensor size implausible for the mass and geometry"),
    ("UI205", "mesh-unresolved", "link", "error",
     "a mesh reference does not resolve to a file"),
    ("UI210", "not-realizable", "inertial", "warning",
     "no mass inside the geometry's bounding ellipsoid gives the written CoM and tensor"),
    ("UI211", "gyration-implausible", "inertial", "warning",
     "a link without geometry whose tensor puts its mass over a metre from its CoM"),
    ("UI301", "lumped-mass", "link", "info", "fixed joints merge links into this body"),
    ("UI401", "engine-refused", "robot", "error", "a simulator refuses to load the robot"),
    ("UI402", "engine-nan", "robot", "error", "a passive run in a simulator produced NaN"),
    ("UI403", "engine-unstable", "robot", "error",
     "a simulator reported instability in a passive run"),
    ("UI404", "engine-runaway", "link", "error", "a joint speed ran away in a passive run"),
    ("UI405", "engine-crashed", "robot", "error",
     "a simulator crashed or hung loading or stepping the robot"),
    ("UI406", "engine-changes-inertial", "inertial", "warning",
     "a simulator silently replaces the written inertial"),
    ("UI407", "engine-default-inertial", "link", "warning",
     "a simulator gives a link without <inertial> default mass/inertia"),
    ("UI408", "engine-missing", "robot", "info", "a requested simulator is not installed"),
    ("UI409", "engine-regression", "robot", "error",
     "a simulator accepted the input and refuses the fixed output"),
    ("UI410", "engine-skipped", "robot", "info", "the engines cannot load this format"),
    ("UI501", "vector-unparseable", "link", "error",
     "a vector other loaders (urdfdom) cannot parse"),
    ("UI502", "unexpanded-substitution", "link", "error", "an unexpanded $(...) substitution"),
    ("UI503", "zero-size-primitive", "link", "warning", "a primitive of zero or negative size"),
    ("UI504", "unsupported-geometry", "link", "warning",
     "a geometry no inertia can come from (plane, unknown shape, two shapes)"),
    ("UI505", "missing-attribute", "link", "error", "a required attribute is missing"),
    ("UI506", "xml-read-leniently", "robot", "warning",
     "XML that strict parsers refuse (declaration, undeclared prefix, trailing content)"),
    ("UI507", "missing-layer", "robot", "error",
     "a USD sublayer, reference or payload names a layer that cannot be opened"),
    # UI6xx: what the author meant: slips, copies and twins
    ("UI601", "slip-proposed", "inertial", "warning",
     "one edit of the written values (a slip) makes the inertial valid and plausible"),
    ("UI602", "inertial-copied", "inertial", "warning",
     "the inertial equals another link's while their geometries differ (copy-pasted)"),
    ("UI603", "twins-disagree", "inertial", "warning",
     "mirror twins whose inertials disagree beyond the mirror map"),
    # UI7xx: the whole robot: masses and statics
    ("UI701", "joint-cannot-hold", "link", "error",
     "a joint's effort limit is below the gravity torque it must hold over its range"),
    ("UI702", "joint-effort-margin", "link", "warning",
     "a joint's gravity torque is within the margin of its effort limit"),
    ("UI703", "total-mass-mismatch", "robot", "warning",
     "the written masses of the robot (or a subtree) miss its known total"),
)


def rule_of(code: str) -> Rule:
    """The rule of a finding code; an unregistered code (a bug: tests list every code the
    checks emit) gets itself as id rather than crashing a report."""
    found = RULES.get(code)
    return found if found is not None else Rule(code, code, "link", "warning", code)


@dataclass(frozen=True)
class Finding:
    """One problem (or note) about one link; ``link`` is None for the whole robot."""

    link: str | None
    severity: str  # "error" | "warning" | "info"
    code: str
    message: str
    #: line in the description where known (additive: most value checks are per link)
    line: int | None = None

    def __post_init__(self) -> None:
        if self.severity not in SEVERITIES:
            raise ValueError(f"severity must be one of {SEVERITIES}")

    @property
    def rule(self) -> Rule:
        return rule_of(self.code)
