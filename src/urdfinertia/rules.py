"""The rule registry: every kind of finding, once, with what it means and what `fix` does.

Each code is a member of [Rule][urdfinertia.rules.Rule], a string Enum
(`Rule.PLACEHOLDER_INERTIA == "placeholder-inertia"`), and carries its stable id (`UI111`:
SARIF `ruleId`, baselines), its [Severity][urdfinertia.rules.Severity], its
[Scope][urdfinertia.rules.Scope] (what in the file a finding points at), what `fix` does
about it ([FixAction][urdfinertia.rules.FixAction]) and its documentation (meaning, an
example, how to silence it). The rules page of the documentation is generated from this
table, and no code is spelled as a literal anywhere else.

This is a leaf module: it imports nothing of the package. An id is never reused or
renumbered (baselines and code-scanning alerts are keyed on it); new kinds go at the end of
their block. UI1xx: the written values; UI2xx: against the geometry; UI3xx: the robot as
simulators merge it; UI4xx: loading and stepping in the engines; UI5xx: what the reader read
past; UI6xx: what the author meant, across links; UI7xx: the whole robot; UI8xx: what
`fix` did and why (notes on its verdicts).
"""

from __future__ import annotations

from dataclasses import dataclass
from enum import StrEnum


class Severity(StrEnum):
    """How bad a finding is."""

    ERROR = "error"
    """A simulator refuses it or misbehaves: `check` exits 1."""
    WARNING = "warning"
    """Very likely wrong: `check --strict` exits 1."""
    INFO = "info"
    """Worth knowing; never fails a run."""

    @property
    def rank(self) -> int:
        """The sort order, worst first: 0 for errors, 1 for warnings, 2 for info."""
        return (Severity.ERROR, Severity.WARNING, Severity.INFO).index(self)


class Scope(StrEnum):
    """What a finding points at in the file (its SARIF region)."""

    INERTIAL = "inertial"
    """The link's `<inertial>` (or the MJCF `<inertial>`, the USD MassAPI)."""
    LINK = "link"
    """The link (or body) element."""
    ELEMENT = "element"
    """One element of a link: a `<collision>`, `<visual>`, geom or mesh reference."""
    JOINT = "joint"
    """A joint."""
    ROBOT = "robot"
    """The document as a whole."""


class FixAction(StrEnum):
    """What `fix` (default options) does about a finding of a rule."""

    RECOMPUTE = "recompute"
    """Derives the values it distrusts from the geometry that represents the body; keeps the rest
    (a plausible mass, a CoM inside the body).
    """
    REPAIR = "repair"
    """The minimal repair: mass and CoM kept, the tensor lifted just enough to be valid."""
    CORRECT = "correct"
    """Undoes the slip: one edit of the written values."""
    KEEP = "keep"
    """Keeps the values as written: the finding is advice or a note."""
    NONE = "none"
    """Nothing: the finding is not about a value `fix` writes."""


@dataclass(frozen=True)
class RuleInfo:
    """The registry's row for one rule (see [Rule][urdfinertia.rules.Rule]).

    Attributes
    ----------
    id : str
        The stable id, "UI111": SARIF's `ruleId`, the key of baselines.
    severity : Severity
        How bad a finding of this rule is.
    scope : Scope
        What in the file a finding points at.
    fix : FixAction
        What `fix` (default options) does about it.
    summary : str
        One line, as tables and SARIF's short description say it.
    meaning : str
        What it means and why it matters (a paragraph).
    example : str
        A finding of this kind as the tool prints it, or the input that gives one.
    silence : str
        How to silence it when it is intended (empty: record it in a baseline).
    """

    id: str
    severity: Severity
    scope: Scope
    fix: FixAction
    summary: str
    meaning: str
    example: str
    silence: str = ""


_BASELINE = ("record it in a baseline (`check --write-baseline FILE`, then "
             "`--baseline FILE`) once you have looked at it")
_GEOMETRY = ("fix the geometry, or pass `--geometry collision|visual` to judge against the "
             "other; " + _BASELINE)


class Rule(StrEnum):
    """Every kind of finding: a string Enum whose value is the code ("placeholder-inertia").

    `Rule.X.id`, `.severity`, `.scope`, `.fix`, `.summary`, `.meaning`, `.example` and
    `.silence` come from the registry's row ([RuleInfo][urdfinertia.rules.RuleInfo]); the
    rules page of the documentation lists every member with them.

    Examples
    --------
    >>> Rule.PLACEHOLDER_INERTIA.id
    'UI111'
    >>> Rule.by_id("UI204") is Rule.INERTIA_VS_GEOMETRY
    True
    """

    # UI1xx: the written values
    MISSING_INERTIAL = "missing-inertial"
    MASS_NOT_FINITE = "mass-not-finite"
    MASS_NOT_POSITIVE = "mass-not-positive"
    MASSLESS_FRAME = "massless-frame"
    COM_NOT_FINITE = "com-not-finite"
    INERTIA_NOT_FINITE = "inertia-not-finite"
    INERTIA_ZERO = "inertia-zero"
    INERTIA_NOT_SYMMETRIC = "inertia-not-symmetric"
    INERTIA_NOT_POSITIVE_DEFINITE = "inertia-not-positive-definite"
    TRIANGLE_INEQUALITY = "triangle-inequality"
    PLACEHOLDER_INERTIA = "placeholder-inertia"
    MASS_ABSURD = "mass-absurd"
    INERTIA_ABSURD = "inertia-absurd"
    USD_NEGATIVE_MASS = "usd-negative-mass"
    USD_NEGATIVE_DENSITY = "usd-negative-density"
    USD_DENSITY_WITHOUT_MASS = "usd-density-without-mass"
    USD_DIAGONAL_INERTIA_INVALID = "usd-diagonal-inertia-invalid"
    USD_PRINCIPAL_AXES_NOT_UNIT = "usd-principal-axes-not-unit"
    USD_NEWTON_MASS_DISAGREES = "usd-newton-mass-disagrees"
    MISSING_INERTIAL_MERGED = "missing-inertial-merged"
    MASS_ZERO_MERGED = "mass-zero-merged"
    INERTIA_ZERO_MERGED = "inertia-zero-merged"
    INERTIAL_FROM_GEOMS = "inertial-from-geoms"
    USD_MASS_WITHOUT_TENSOR = "usd-mass-without-tensor"
    # UI2xx: against the geometry
    GEOMETRY_UNREADABLE = "geometry-unreadable"
    IMPLAUSIBLE_DENSITY = "implausible-density"
    COM_OUTSIDE_GEOMETRY = "com-outside-geometry"
    INERTIA_VS_GEOMETRY = "inertia-vs-geometry"
    MESH_UNRESOLVED = "mesh-unresolved"
    NOT_REALIZABLE = "not-realizable"
    GYRATION_IMPLAUSIBLE = "gyration-implausible"
    COM_FAR_OUTSIDE_GEOMETRY = "com-far-outside-geometry"
    MESH_NO_VOLUME = "mesh-no-volume"
    MESH_TOO_LARGE = "mesh-too-large"
    MESH_REFUSED = "mesh-refused"
    MESH_REPAIRED = "mesh-repaired"
    MESH_ABSURD = "mesh-absurd"
    # UI3xx: the robot as simulators merge it
    LUMPED_MASS = "lumped-mass"
    # UI4xx: the engines
    ENGINE_REFUSED = "engine-refused"
    ENGINE_NAN = "engine-nan"
    ENGINE_UNSTABLE = "engine-unstable"
    ENGINE_RUNAWAY = "engine-runaway"
    ENGINE_CRASHED = "engine-crashed"
    ENGINE_CHANGES_INERTIAL = "engine-changes-inertial"
    ENGINE_DEFAULT_INERTIAL = "engine-default-inertial"
    ENGINE_MISSING = "engine-missing"
    ENGINE_REGRESSION = "engine-regression"
    ENGINE_SKIPPED = "engine-skipped"
    ENGINE_WARNED = "engine-warned"
    ENGINE_LESS_STABLE = "engine-less-stable"
    # UI5xx: what the reader read past
    DESCRIPTION_UNREADABLE = "description-unreadable"
    VECTOR_UNPARSEABLE = "vector-unparseable"
    UNEXPANDED_SUBSTITUTION = "unexpanded-substitution"
    ZERO_SIZE_PRIMITIVE = "zero-size-primitive"
    UNSUPPORTED_GEOMETRY = "unsupported-geometry"
    MISSING_ATTRIBUTE = "missing-attribute"
    XML_READ_LENIENTLY = "xml-read-leniently"
    MISSING_LAYER = "missing-layer"
    VECTOR_COMMAS = "vector-commas"
    INCLUDE_NOT_FOLLOWED = "include-not-followed"
    VALUE_UNREADABLE = "value-unreadable"
    DUPLICATE_NAME = "duplicate-name"
    READER_NOTE = "reader-note"
    SPEC_INVALID = "spec-invalid"
    JOINT_UNREADABLE = "joint-unreadable"
    OUTPUT_FAILED = "output-failed"
    MISSING_EXTRA = "missing-extra"
    # UI6xx: what the author meant
    SLIP_PROPOSED = "slip-proposed"
    INERTIAL_COPIED = "inertial-copied"
    TWINS_DISAGREE = "twins-disagree"
    CONVENTION_INFERRED = "convention-inferred"
    CLOSED_FORM_SCALED = "closed-form-scaled"
    GEOMETRY_UNIT_SLIP = "geometry-unit-slip"
    TWIN_VOUCHES = "twin-vouches"
    # UI7xx: the whole robot
    JOINT_CANNOT_HOLD = "joint-cannot-hold"
    JOINT_EFFORT_MARGIN = "joint-effort-margin"
    TOTAL_MASS_MISMATCH = "total-mass-mismatch"
    MASS_DISTRIBUTION = "mass-distribution"
    JOINT_MAY_NOT_HOLD = "joint-may-not-hold"
    MASS_PRIOR = "mass-prior"
    TOTAL_MASS_CHANGED = "total-mass-changed"
    MASS_TARGET_MET = "mass-target-met"
    STATICS_COARSENED = "statics-coarsened"
    # UI8xx: what fix did and why
    GEOMETRY_NOT_BODY = "geometry-not-body"
    NEGLIGIBLE_BODY = "negligible-body"
    NO_GEOMETRY = "no-geometry"
    AUTO_INERTIAL_KEPT = "auto-inertial-kept"
    READ_ONLY_BODY = "read-only-body"
    DERIVED_FROM_IMPLAUSIBLE = "derived-from-implausible"
    GEOMETRY_SPANS_FAR = "geometry-spans-far"
    MINIMAL_BODY = "minimal-body"
    TENSOR_HOLDS_NOTHING = "tensor-holds-nothing"
    NOT_ASKED = "not-asked"
    ASKED = "asked"
    SPEC_NAMED = "spec-named"
    TENSOR_LIFTED = "tensor-lifted"

    @property
    def info(self) -> RuleInfo:
        """The registry's row of this rule."""
        return _TABLE[self]

    @property
    def id(self) -> str:
        """The stable id ("UI111")."""
        return _TABLE[self].id

    @property
    def severity(self) -> Severity:
        """How bad a finding of this rule is."""
        return _TABLE[self].severity

    @property
    def scope(self) -> Scope:
        """What in the file a finding of this rule points at."""
        return _TABLE[self].scope

    @property
    def fix(self) -> FixAction:
        """What `fix` (default options) does about it."""
        return _TABLE[self].fix

    @property
    def summary(self) -> str:
        """One line, as tables and SARIF's short description say it."""
        return _TABLE[self].summary

    @property
    def meaning(self) -> str:
        """What it means and why it matters (a paragraph)."""
        return _TABLE[self].meaning

    @property
    def example(self) -> str:
        """A finding of this kind as the tool prints it, or the input that gives one."""
        return _TABLE[self].example

    @property
    def silence(self) -> str:
        """How to silence it when it is intended (by default: record it in a baseline)."""
        return _TABLE[self].silence or _BASELINE

    @property
    def anchor(self) -> str:
        """The rule's anchor on the rules page of the documentation ("ui111": `rules/#ui111`)."""
        return self.id.lower()

    @classmethod
    def by_id(cls, rule_id: str) -> Rule:
        """The rule whose stable id is `rule_id`.

        Parameters
        ----------
        rule_id : str
            A stable id, "UI111".

        Returns
        -------
        Rule
            The member with that id.

        Raises
        ------
        KeyError
            When no rule has that id.
        """
        for rule in cls:
            if rule.id == rule_id:
                return rule
        raise KeyError(rule_id)


E, W, I_ = Severity.ERROR, Severity.WARNING, Severity.INFO
R = Rule
_TABLE: dict[Rule, RuleInfo] = {
    R.MISSING_INERTIAL: RuleInfo(
        "UI101", E, Scope.LINK, FixAction.RECOMPUTE,
        "a moving link has no <inertial>",
        "A link that is the child of a moving joint carries no mass properties. Simulators "
        "give it a default (Gazebo and PyBullet a 1 kg unit body, Drake refuses it), which "
        "changes the dynamics. A link on a fixed joint or the root without an inertial is a "
        "frame, not a body, and is not reported.",
        "link 'forearm' (child of revolute joint 'elbow') has no <inertial>",
        "give the link an inertial, or run `fix`: it integrates the link's geometry at the "
        "density `--density` (kg/m^3, default 1000) or at the mass a spec states"),
    R.MASS_NOT_FINITE: RuleInfo(
        "UI102", E, Scope.INERTIAL, FixAction.RECOMPUTE,
        "mass is NaN or infinite",
        "The written mass is not a number. Every simulator refuses it or propagates NaN.",
        '<mass value="nan"/>'),
    R.MASS_NOT_POSITIVE: RuleInfo(
        "UI103", E, Scope.INERTIAL, FixAction.RECOMPUTE,
        "a moving link's mass is <= 0",
        "A moving body needs a positive mass; a negative mass is never physical. MuJoCo "
        "refuses a moving body with zero mass, Drake and Pinocchio give singular dynamics.",
        '<mass value="0"/> on the child of a revolute joint'),
    R.MASSLESS_FRAME: RuleInfo(
        "UI104", I_, Scope.INERTIAL, FixAction.KEEP,
        "zero mass on a link that does not move",
        "A link with zero mass on a fixed joint (or the root) is a frame: a tool flange, a "
        "sensor mount. It is left as it is.",
        '<mass value="0"/> on the child of a fixed joint', "nothing to silence: it is info"),
    R.COM_NOT_FINITE: RuleInfo(
        "UI105", E, Scope.INERTIAL, FixAction.RECOMPUTE,
        "CoM origin is NaN or infinite",
        "The inertial origin's xyz or rpy is not a number, so the CoM is unknown.",
        '<origin xyz="0 nan 0"/> in <inertial>'),
    R.INERTIA_NOT_FINITE: RuleInfo(
        "UI106", E, Scope.INERTIAL, FixAction.RECOMPUTE,
        "inertia tensor has NaN/inf",
        "An entry of the inertia tensor is not a number. The mass and CoM, when valid, are "
        "kept; the tensor is derived.",
        '<inertia ixx="nan" .../>'),
    R.INERTIA_ZERO: RuleInfo(
        "UI107", E, Scope.INERTIAL, FixAction.RECOMPUTE,
        "mass with a zero inertia tensor",
        "A body with mass and no rotational inertia is a point mass. MuJoCo refuses it on "
        "a moving body; other engines divide by zero.",
        '<mass value="1.2"/> with every inertia entry 0'),
    R.INERTIA_NOT_SYMMETRIC: RuleInfo(
        "UI108", E, Scope.INERTIAL, FixAction.REPAIR,
        "inertia tensor not symmetric",
        "Formats that store the full matrix (SDFormat and MJCF fullinertia store six values, "
        "USD principal axes) can describe an asymmetric tensor, which no body has.",
        "tensor asymmetry 0.2"),
    R.INERTIA_NOT_POSITIVE_DEFINITE: RuleInfo(
        "UI109", E, Scope.INERTIAL, FixAction.REPAIR,
        "inertia tensor not positive definite",
        "A principal moment is zero or negative: no distribution of positive mass has it. "
        "Usually a slip (a sign, a power of ten on one entry); `fix` undoes a clear slip, "
        "else lifts the moments just enough (the minimal repair) or derives the tensor.",
        "principal moments (-0.001, 0.02, 0.03) kg m^2"),
    R.TRIANGLE_INEQUALITY: RuleInfo(
        "UI110", E, Scope.INERTIAL, FixAction.REPAIR,
        "principal moments violate A + B >= C",
        "The principal moments of any body satisfy A + B >= C. MuJoCo refuses a tensor that "
        "does not (\"inertia must satisfy A + B >= C\").",
        "principal moments A+B<C by 0.2 of C (0.001, 0.002, 0.0036) kg m^2; MuJoCo refuses "
        "it"),
    R.PLACEHOLDER_INERTIA: RuleInfo(
        "UI111", W, Scope.INERTIAL, FixAction.RECOMPUTE,
        "a placeholder tensor (round isotropic values, or a radius of gyration beyond the "
        "part)",
        "Equal diagonal entries and no products (ixx=iyy=izz=1, 1e-3, 1e-6) typed in by hand "
        "or by an exporter's default, not computed from a body. A valid placeholder still "
        "gives wrong dynamics. A sphere or a cube computed on purpose has such a tensor too: "
        "one that reproduces its own geometry's closed form is kept (UI805).",
        "ixx=iyy=izz=0.001, no products: a placeholder, not a computed tensor",
        "write the computed tensor; " + _BASELINE),
    R.MASS_ABSURD: RuleInfo(
        "UI112", E, Scope.INERTIAL, FixAction.RECOMPUTE,
        "a mass no robot link has (a unit slip such as mm^3 read as m^3)",
        "A link mass above 1e6 kg describes no robot part.",
        "mass 6.2e+09 kg is beyond any robot link (above 1e+06 kg)"),
    R.INERTIA_ABSURD: RuleInfo(
        "UI113", E, Scope.INERTIAL, FixAction.RECOMPUTE,
        "inertia components no robot link has",
        "An inertia entry above 1e6 kg m^2 describes no robot part: a unit slip (g mm^2 "
        "read as kg m^2 goes the other way; mm^2 read as m^2 this way).",
        "inertia component 4.5e+07 kg m^2 is above 1e+06: a unit slip?"),
    R.USD_NEGATIVE_MASS: RuleInfo(
        "UI114", E, Scope.INERTIAL, FixAction.RECOMPUTE,
        "USD MassAPI: physics:mass < 0",
        "A negative mass in a USD MassAPI. Zero means \"not set\" in USD; below zero is "
        "invalid.", "physics:mass = -1"),
    R.USD_NEGATIVE_DENSITY: RuleInfo(
        "UI115", E, Scope.INERTIAL, FixAction.RECOMPUTE,
        "USD MassAPI: physics:density < 0",
        "A negative density in a USD MassAPI.", "physics:density = -1000"),
    R.USD_DENSITY_WITHOUT_MASS: RuleInfo(
        "UI116", W, Scope.INERTIAL, FixAction.KEEP,
        "USD MassAPI: density given where mass is not (SimReady: give the mass)",
        "The engines compute the mass from the colliders' volume at this density, so it "
        "depends on collider approximation. SimReady asks for an explicit mass.",
        "physics:density = 2700 and no physics:mass"),
    R.USD_DIAGONAL_INERTIA_INVALID: RuleInfo(
        "UI117", E, Scope.INERTIAL, FixAction.REPAIR,
        "USD MassAPI: diagonalInertia negative or violating A + B >= C",
        "The principal moments a USD MassAPI states are not those of any body.",
        "physics:diagonalInertia = (0.1, 0.1, 0.5)"),
    R.USD_PRINCIPAL_AXES_NOT_UNIT: RuleInfo(
        "UI118", E, Scope.INERTIAL, FixAction.REPAIR,
        "USD MassAPI: principalAxes is not a unit quaternion",
        "The principal axes' quaternion does not have unit length, so the tensor's "
        "orientation is undefined (engines normalise it differently).",
        "physics:principalAxes = (2, 0, 0, 0)"),
    R.USD_NEWTON_MASS_DISAGREES: RuleInfo(
        "UI119", W, Scope.INERTIAL, FixAction.KEEP,
        "USD: newton:inertia and the MassAPI tensor differ (engines disagree)",
        "The prim carries both Newton's own inertia attribute and a MassAPI; they differ, "
        "so Newton and PhysX simulate different bodies.", "newton:inertia differs by 40 %"),
    R.GEOMETRY_UNREADABLE: RuleInfo(
        "UI201", W, Scope.ELEMENT, FixAction.KEEP,
        "the link's geometry cannot be read",
        "A mesh exists but cannot be read (unsupported format, no triangles, encloses no "
        "volume). The geometry checks of the link are skipped; a valid inertial is kept as "
        "written and the link is counted as not verified.",
        "geometry checks skipped: meshes/foot.dae: no triangles",
        "repair or replace the mesh; " + _BASELINE),
    R.IMPLAUSIBLE_DENSITY: RuleInfo(
        "UI202", W, Scope.INERTIAL, FixAction.RECOMPUTE,
        "mass / geometry volume is no material's density",
        "The written mass over the volume of the geometry that represents the body is "
        "outside 50..25,000 kg/m^3. When the geometry is the body this is a slip (grams, a "
        "mesh in millimetres); when the geometry is a marker, contact spheres or an "
        "envelope it says nothing about the mass (UI801), and the value is kept.",
        "2.3 kg in 1.1e-07 m^3 of collision geometry is 2.1e+07 kg/m^3, outside "
        "50..25000 (x0.001 would fit: mass in g?)", _GEOMETRY),
    R.COM_OUTSIDE_GEOMETRY: RuleInfo(
        "UI203", W, Scope.INERTIAL, FixAction.RECOMPUTE,
        "CoM far outside the geometry's bounding box",
        "The written CoM lies more than a quarter of the box diagonal outside the box of "
        "every geometry element of the link. A body's CoM lies inside its convex hull.",
        "CoM [0.0, 0.0, 0.35] m is 0.21 m (0.9 box diagonals) outside the geometry's "
        "bounding box", _GEOMETRY),
    R.INERTIA_VS_GEOMETRY: RuleInfo(
        "UI204", W, Scope.INERTIAL, FixAction.RECOMPUTE,
        "tensor size implausible for the mass and geometry",
        "The written tensor's trace is more than 100 times larger or smaller than the "
        "homogeneous body of the geometry at the written mass, or larger than all of the "
        "mass on the far corners of its box allows.",
        "tensor trace 0.42 kg m^2 is 234x the geometry's 0.0018 at 1.2 kg", _GEOMETRY),
    R.MESH_UNRESOLVED: RuleInfo(
        "UI205", W, Scope.ELEMENT, FixAction.KEEP,
        "a mesh reference does not resolve to a file",
        "A `package://` or relative mesh reference names no file, so loaders fail on it and "
        "the link's geometry cannot be checked.",
        "collision[0]: cannot resolve package 'ur_description' (pass --package-dir "
        "ur_description=PATH)",
        "pass `--package-dir NAME=PATH` (or `package_dirs={NAME: PATH}` in Python), or "
        "`--no-geometry` to check the written values only"),
    R.NOT_REALIZABLE: RuleInfo(
        "UI210", W, Scope.INERTIAL, FixAction.KEEP,
        "no mass inside the geometry's bounding ellipsoid gives the written CoM and tensor",
        "The written CoM and tensor cannot come from positive mass inside the region the "
        "geometry bounds (its bounding ellipsoid, or its convex hull with "
        "`--realizable hull`). Often the geometry is a simplified stand-in that is smaller "
        "than the body; `fix` keeps the value unless other evidence shows it wrong.",
        "no distribution of mass inside the geometry's bounding ellipsoid has this tensor",
        "`--realizable hull` for the tighter test; " + _BASELINE),
    R.GYRATION_IMPLAUSIBLE: RuleInfo(
        "UI211", W, Scope.INERTIAL, FixAction.KEEP,
        "a link without geometry whose tensor puts its mass over a metre from its CoM",
        "With no geometry to hold it against, a radius of gyration over 1 m is still no "
        "robot part.", "radius of gyration 3.2 m with no geometry"),
    R.LUMPED_MASS: RuleInfo(
        "UI301", I_, Scope.LINK, FixAction.NONE,
        "fixed joints merge links into this body",
        "Simulators that merge fixed joints (MuJoCo, Drake, PyBullet) see one body: the "
        "merged mass, CoM and tensor are shown.",
        "fixed joints merge 2 link(s) (flange, tool0) into it: merged body 2.1 kg",
        "nothing to silence: it is info"),
    R.ENGINE_REFUSED: RuleInfo(
        "UI401", E, Scope.ROBOT, FixAction.NONE,
        "a simulator refuses to load the robot",
        "`check --engines` loaded the robot in the engine and it refused.",
        "mujoco: mass and inertia of moving bodies must be larger than mjMINVAL"),
    R.ENGINE_NAN: RuleInfo(
        "UI402", E, Scope.ROBOT, FixAction.NONE,
        "a passive run in a simulator produced NaN",
        "A passive run (no control) of a few seconds gave NaN states.", "pybullet: NaN at "
        "step 312"),
    R.ENGINE_UNSTABLE: RuleInfo(
        "UI403", E, Scope.ROBOT, FixAction.NONE,
        "a simulator reported instability in a passive run",
        "The engine warned of instability (MuJoCo's mjWARN_BADQACC).", "mujoco: Nan, Inf or "
        "huge value in QACC"),
    R.ENGINE_RUNAWAY: RuleInfo(
        "UI404", E, Scope.LINK, FixAction.NONE,
        "a joint speed ran away in a passive run",
        "A joint's speed exceeded any plausible value in a passive run: usually a tiny "
        "inertia under a heavy child.", "joint 'finger_1' reached 4.1e+04 rad/s"),
    R.ENGINE_CRASHED: RuleInfo(
        "UI405", E, Scope.ROBOT, FixAction.NONE,
        "a simulator crashed or hung loading or stepping the robot",
        "The engine's child process died or did not finish in time.", "pybullet: crashed "
        "(signal 11)"),
    R.ENGINE_CHANGES_INERTIAL: RuleInfo(
        "UI406", W, Scope.INERTIAL, FixAction.KEEP,
        "a simulator silently replaces the written inertial",
        "The engine loads the robot but simulates other mass properties than written (for "
        "example MuJoCo's `balanceinertia`, PyBullet's defaults).",
        "pybullet replaces the mass 0 with 1 kg"),
    R.ENGINE_DEFAULT_INERTIAL: RuleInfo(
        "UI407", W, Scope.LINK, FixAction.RECOMPUTE,
        "a simulator gives a link without <inertial> default mass/inertia",
        "A link without an inertial gets the engine's default body.", "pybullet: link "
        "'camera' without <inertial> gets 1 kg"),
    R.ENGINE_MISSING: RuleInfo(
        "UI408", I_, Scope.ROBOT, FixAction.NONE,
        "a requested simulator is not installed",
        "`--engines` named an engine that cannot be imported.", "pinocchio is not "
        "installed (pip install 'urdfinertia[engines]')", "install the engine"),
    R.ENGINE_REGRESSION: RuleInfo(
        "UI409", E, Scope.ROBOT, FixAction.NONE,
        "a simulator accepted the input and refuses the fixed output",
        "`fix --engines` loaded input and output: the output fares worse. This is a bug of "
        "the tool; please report it.", "mujoco: input loads, output refused"),
    R.ENGINE_SKIPPED: RuleInfo(
        "UI410", I_, Scope.ROBOT, FixAction.NONE,
        "the engines cannot load this format",
        "The requested engines do not read this description format.", "pybullet cannot "
        "load USD", "nothing to silence: it is info"),
    R.ENGINE_WARNED: RuleInfo(
        "UI411", W, Scope.ROBOT, FixAction.NONE,
        "a simulator warned in a passive run (a warning it recovers from)",
        "The engine printed a warning it does not reset the simulation for (MuJoCo's "
        "contact or constraint buffer warnings).", "mujoco warned mjWARN_CNSTRFULL x3"),
    R.DESCRIPTION_UNREADABLE: RuleInfo(
        "UI500", E, Scope.ROBOT, FixAction.NONE,
        "the document cannot be read as a whole (not XML, not a robot, a security "
        "refusal, a nameless or duplicate link)",
        "Only what makes the whole document unreadable stops a run; `check` and `fix` exit "
        "2 with one line naming the file and line.", "robot.urdf:3: malformed XML",
        "fix the document"),
    R.ENGINE_LESS_STABLE: RuleInfo(
        "UI412", W, Scope.ROBOT, FixAction.NONE,
        "a simulator runs the input stably and the fixed output less so",
        "`fix --engines`: the output loads, but a passive run of it is less stable than the "
        "input's. Please report it.", "mujoco runs the input stably but not the fixed output"),
    R.VECTOR_UNPARSEABLE: RuleInfo(
        "UI501", E, Scope.ELEMENT, FixAction.NONE,
        "a vector other loaders (urdfdom) cannot parse",
        "A number or vector that urdfdom refuses (`1,2,3`, `0.1.2`). The tool reads what it "
        "can and drops the element when it cannot.", 'origin xyz="0,0,0.1"'),
    R.UNEXPANDED_SUBSTITUTION: RuleInfo(
        "UI502", E, Scope.ELEMENT, FixAction.NONE,
        "an unexpanded $(...) substitution",
        "A `$(find pkg)` or `$(arg x)` left in a URDF: the file is a template that was not "
        "expanded.", 'filename="$(find robot)/meshes/a.stl"',
        "expand the xacro (pass the .xacro file itself, with `--xacro-arg NAME:=VALUE`)"),
    R.ZERO_SIZE_PRIMITIVE: RuleInfo(
        "UI503", W, Scope.ELEMENT, FixAction.NONE,
        "a primitive of zero or negative size",
        "A box, cylinder or sphere with a zero or negative dimension: MuJoCo refuses it; "
        "the element holds no volume.", '<box size="0 0.1 0.1"/>'),
    R.UNSUPPORTED_GEOMETRY: RuleInfo(
        "UI504", W, Scope.ELEMENT, FixAction.NONE,
        "a geometry no inertia can come from (plane, unknown shape, two shapes)",
        "An element with no volume to integrate (a plane, a heightfield, an unknown tag).",
        "<plane> in <collision>"),
    R.MISSING_ATTRIBUTE: RuleInfo(
        "UI505", E, Scope.ELEMENT, FixAction.NONE,
        "a required attribute is missing",
        "An element lacks an attribute its format requires (a mesh without filename, a "
        "box without size).", "<mesh/> without filename"),
    R.XML_READ_LENIENTLY: RuleInfo(
        "UI506", W, Scope.ROBOT, FixAction.NONE,
        "XML that strict parsers refuse (declaration, undeclared prefix, trailing content)",
        "The document is read the way urdfdom reads it, but strict XML parsers refuse it.",
        '<?xml version="0.0"?>'),
    R.MISSING_LAYER: RuleInfo(
        "UI507", E, Scope.ROBOT, FixAction.NONE,
        "a USD sublayer, reference or payload names a layer that cannot be opened",
        "Part of the stage is missing, so bodies may be missing too.",
        "@./payloads/robot_physics.usda@ cannot be opened"),
    R.SLIP_PROPOSED: RuleInfo(
        "UI601", W, Scope.INERTIAL, FixAction.CORRECT,
        "one edit of the written values (a slip) makes the inertial valid and plausible",
        "A wrong CAD value is usually wrong by one slip: a power of ten on one entry, grams "
        "for kilograms, the products' sign, the tensor about the joint origin. `fix` undoes "
        "it when one edit clearly beats every other and makes the value fit the body.",
        "izz looks 1000x too large: izz x1e-3 (0.0123 -> 1.23e-05) makes the inertial "
        "valid and plausible", "`--no-slips` derives from the geometry instead"),
    R.INERTIAL_COPIED: RuleInfo(
        "UI602", W, Scope.INERTIAL, FixAction.KEEP,
        "the inertial equals another link's while their geometries differ (copy-pasted)",
        "Two links carry the same inertial to the last digit, but their geometries differ "
        "and one fits it clearly worse: it was likely copied.",
        "inertial equals hand_pitch_link's (byte for byte) while their geometries differ"),
    R.TWINS_DISAGREE: RuleInfo(
        "UI603", W, Scope.INERTIAL, FixAction.KEEP,
        "mirror twins whose inertials disagree beyond the mirror map",
        "Links whose names pair left and right and whose geometries mirror each other carry "
        "masses, CoM offsets or principal moments that differ beyond the mirror map. The "
        "finding is on the side that agrees worse with its geometry.",
        "mirror twin of left_knee with the same geometry, but mass 2.1 kg against 3.4"),
    R.JOINT_CANNOT_HOLD: RuleInfo(
        "UI701", E, Scope.JOINT, FixAction.NONE,
        "a joint's effort limit is below the gravity torque it must hold over its range",
        "Holding the robot still against gravity somewhere in the joint's range takes more "
        "torque than its effort limit: either a mass or an effort limit is wrong.",
        "joint 'shoulder' needs 182 N m against its 150 N m limit",
        "`check --no-statics`; " + _BASELINE),
    R.JOINT_EFFORT_MARGIN: RuleInfo(
        "UI702", W, Scope.JOINT, FixAction.NONE,
        "a joint's gravity torque is within the margin of its effort limit",
        "The gravity torque comes within `--effort-margin` (default 20 %) of the limit.",
        "joint 'elbow' needs 88 % of its effort limit",
        "`--effort-margin 0.1`; `check --no-statics`; " + _BASELINE),
    R.TOTAL_MASS_MISMATCH: RuleInfo(
        "UI703", W, Scope.ROBOT, FixAction.NONE,
        "the written masses of the robot (or a subtree) miss its known total",
        "`--total-mass KG` or a spec's target: the written masses sum to something else.",
        "written masses sum to 17.2 kg against the 18 kg target (-4.4 %)",
        "`fix --total-mass KG` scales derived masses to meet it; `--mass-tolerance`"),

    R.MISSING_INERTIAL_MERGED: RuleInfo(
        "UI120", W, Scope.LINK, FixAction.RECOMPUTE,
        "a moving link has no <inertial>; links fixed to it carry mass only where fixed "
        "joints are merged",
        "The link moves and has no inertial of its own, but links attached to it by fixed "
        "joints have mass: simulators that merge fixed joints (MuJoCo, Drake, PyBullet) see "
        "a body with that mass; Gazebo and others that keep the link see none.",
        "moving link has no <inertial>; links fixed to it give it 0.45 kg only in simulators "
        "that merge fixed joints"),
    R.MASS_ZERO_MERGED: RuleInfo(
        "UI121", W, Scope.INERTIAL, FixAction.RECOMPUTE,
        "a moving link's mass is 0; links fixed to it carry mass only where fixed joints are "
        "merged",
        "As UI120, with an inertial of zero mass.", '<mass value="0"/> on a moving link whose '
        "fixed children have mass"),
    R.INERTIA_ZERO_MERGED: RuleInfo(
        "UI122", W, Scope.INERTIAL, FixAction.RECOMPUTE,
        "mass with a zero inertia tensor on a link that does not move on its own",
        "A point mass on a link that is merged into a body by fixed joints (or does not "
        "move): harmless where fixed joints are merged, a refused body where they are not.",
        "0.1 kg with a zero inertia tensor on the child of a fixed joint"),
    R.INERTIAL_FROM_GEOMS: RuleInfo(
        "UI123", I_, Scope.LINK, FixAction.KEEP,
        "MJCF: a body without <inertial> whose mass properties MuJoCo computes from its geoms",
        "Under `<compiler inertiafromgeom=\"auto\">` (the default) or `\"true\"`, MuJoCo "
        "derives a body's mass, CoM and tensor from its geoms (their density or mass). That "
        "is a valid description: it is judged on what MuJoCo will compute, an error only "
        "when that is invalid (a moving body whose geoms give no mass).",
        "mass 1.2 kg, CoM and tensor computed by MuJoCo from 3 geoms",
        "nothing to silence: it is info"),
    R.USD_MASS_WITHOUT_TENSOR: RuleInfo(
        "UI124", I_, Scope.INERTIAL, FixAction.RECOMPUTE,
        "USD MassAPI: a mass and no tensor (the engines derive it from the colliders)",
        "A MassAPI that states a mass and no inertia is valid: the engines derive the "
        "tensor from the colliders at that mass. The mass counts in the robot's total; "
        "`fix` writes the tensor derived at that mass.",
        "physics:mass = 1.02, no physics:diagonalInertia", "nothing to silence: it is info"),
    R.COM_FAR_OUTSIDE_GEOMETRY: RuleInfo(
        "UI212", E, Scope.INERTIAL, FixAction.RECOMPUTE,
        "CoM more than ten box diagonals outside the geometry: a unit slip",
        "The written CoM lies so far outside the geometry (more than 10 diagonals of its "
        "box) that no modelling choice explains it: a CoM in millimetres, or a CoM in "
        "another link's frame.", "CoM [0, 0, 120] m is 119.9 m (800 box diagonals) outside "
        "the geometry's bounding box", _GEOMETRY),
    R.MESH_NO_VOLUME: RuleInfo(
        "UI206", W, Scope.ELEMENT, FixAction.NONE,
        "a mesh that encloses no volume (a flat or open surface beyond repair)",
        "The mesh's triangles cannot be closed into a solid, so no mass can come from it: "
        "the element is left out of the link's inertia (it still collides and shows).",
        "collision[0]: mesh 'plate.stl' encloses no volume"),
    R.MESH_TOO_LARGE: RuleInfo(
        "UI207", W, Scope.ELEMENT, FixAction.NONE,
        "a mesh over the face, size or time limit",
        "A mesh with more faces than `--max-faces`, more bytes than the size limit, or "
        "whose repair ran over `--mesh-seconds`, is left out of the link's inertia.",
        "visual[0]: 5,000,000 faces, more than 2,000,000 (raise it with --max-faces)",
        "raise `--max-faces` or `--mesh-seconds`"),
    R.MESH_REFUSED: RuleInfo(
        "UI208", E, Scope.ELEMENT, FixAction.NONE,
        "a mesh reference the tool refuses to read (a URL, a path outside what it may read)",
        "Mesh references that are URLs (http, https, ftp) are never fetched, and a mesh "
        "reference that is no regular file (a device, a FIFO) is never opened.",
        "collision[0]: 'https://example.com/a.stl': URLs are not fetched"),
    R.MESH_REPAIRED: RuleInfo(
        "UI209", I_, Scope.ELEMENT, FixAction.NONE,
        "a mesh was repaired to integrate it (holes closed, faces oriented, bodies united)",
        "Real meshes are often open, inverted or made of overlapping bodies; the repair "
        "that makes them a closed solid says what it did and how much volume it changed.",
        "collision[0]: 3 holes closed (+0.4 % volume)", "nothing to silence: it is info"),
    R.MESH_ABSURD: RuleInfo(
        "UI213", W, Scope.ELEMENT, FixAction.NONE,
        "a mesh whose unit, coordinates or size is absurd (not finite, zero or negative "
        "unit)",
        "A COLLADA `<unit meter>` that is zero, negative or not a number, or coordinates "
        "that are not finite: the mesh is not read as if it were right.",
        'visual[0]: <unit meter="0"> is not a length'),
    R.VECTOR_COMMAS: RuleInfo(
        "UI508", W, Scope.ELEMENT, FixAction.NONE,
        "numbers separated by commas (urdfdom refuses them): read as spaces",
        "`xyz=\"0.1, 0, 0\"` has one reading, so it is read; urdfdom and the loaders built "
        "on it refuse it.", 'origin xyz="0.1, 0, 0"', "write the numbers with spaces"),
    R.INCLUDE_NOT_FOLLOWED: RuleInfo(
        "UI509", W, Scope.ROBOT, FixAction.NONE,
        "an SDFormat <include> the tool does not follow",
        "Included models are not read: their links are neither checked nor fixed.",
        "<include> of 'model://sensor' is not followed"),
    R.VALUE_UNREADABLE: RuleInfo(
        "UI510", W, Scope.ELEMENT, FixAction.NONE,
        "a value not needed for inertials could not be read (a joint origin, an axis, a "
        "limit, a pose)",
        "The value is taken as its default (a zero pose, the x axis) and what depends on it "
        "(statics, the placement of a link) is said to be unsure.",
        "joint 'j1' origin: <origin xyz=\"a b c\"> is not a number"),
    R.DUPLICATE_NAME: RuleInfo(
        "UI511", W, Scope.LINK, FixAction.NONE,
        "a second element with a name already taken (read once)",
        "Two links or bodies share a name; the second is not read.", "second link named "
        "'base'"),
    R.READER_NOTE: RuleInfo(
        "UI512", I_, Scope.ROBOT, FixAction.NONE,
        "something the reader wants said about how it read the document",
        "How a construct of the format was read (an SDFormat submesh, a placement frame, an "
        "MJCF body in an included file).", "<submesh> 'arm' not honoured: the whole mesh "
        "file is read", "nothing to silence: it is info"),
    R.SPEC_INVALID: RuleInfo(
        "UI513", E, Scope.ROBOT, FixAction.NONE,
        "the decomposition spec cannot be used (unknown link, bad value, parts that do not "
        "add up)", "A spec error stops the run: the spec is the user's own statement.",
        "arm.inertia.toml:12: link 'forearm' is not in the robot", "fix the spec"),
    R.OUTPUT_FAILED: RuleInfo(
        "UI514", E, Scope.ROBOT, FixAction.NONE,
        "an output cannot be written", "Nothing is left half-written: the write is atomic.",
        "out/robot.urdf: permission denied", "write elsewhere"),
    R.MISSING_EXTRA: RuleInfo(
        "UI516", E, Scope.ROBOT, FixAction.NONE,
        "a feature needs an optional dependency that is not installed",
        "The report and the plots need the `report` extra; the compiled winding numbers the "
        "`fast` extra (numpy's are the fallback). The message is the install command.",
        "the report needs the report extra: pip install 'urdfinertia[report]'",
        "install the extra"),
    R.JOINT_UNREADABLE: RuleInfo(
        "UI515", W, Scope.JOINT, FixAction.NONE,
        "a joint's axis, limit or effort could not be read: statics judges it without",
        "Only whole-robot statics (`check`) uses a joint's motion: the value is left out "
        "(the axis taken as its default, an unbounded effort not judged), and `fix` does "
        "not repeat it.", "joint 'elbow': <limit><effort> unreadable: left out",
        "`check --no-statics`"),
    R.CONVENTION_INFERRED: RuleInfo(
        "UI604", W, Scope.ROBOT, FixAction.CORRECT,
        "the file writes its inertials in another convention (tensors about the joint "
        "origin, the products' sign, grams)",
        "An author's convention shows on many links at once: every tensor about the joint "
        "origin instead of the CoM, every product of inertia with CAD's sign, every mass in "
        "grams. It is inferred from all links jointly and undone on every link the "
        "evidence supports; the count is in the summary.",
        "22 of 26 links write the tensor about the joint origin: undone on 22",
        "`--no-slips` leaves the values as written"),
    R.CLOSED_FORM_SCALED: RuleInfo(
        "UI605", I_, Scope.INERTIAL, FixAction.KEEP,
        "the tensor is its own geometry's closed form, scaled by a round factor: computed "
        "on purpose",
        "A tensor that reproduces the closed form of the link's own primitive exactly (or "
        "times 10, 100, ...) was computed on purpose (a rotor's inertia scaled for a slowed "
        "simulation, say). It is kept, and said so.",
        "the tensor is the box's closed form at 0.005 kg, times 10: kept",
        "nothing to silence: it is info"),
    R.GEOMETRY_UNIT_SLIP: RuleInfo(
        "UI607", W, Scope.LINK, FixAction.KEEP,
        "the geometry, not the inertial, has a unit slip (a mesh in millimetres without its "
        "scale)",
        "The written mass over the geometry's volume is a power of 1000 from any material's "
        "density, and the geometry's size explains it: the mesh is read in the wrong unit. "
        "Recomputing from it would make things worse: the written values are kept.",
        "implausible density explained by the geometry: mesh in mm without scale 0.001?",
        'give the mesh its scale (scale="0.001 0.001 0.001")'),
    R.TWIN_VOUCHES: RuleInfo(
        "UI606", I_, Scope.INERTIAL, FixAction.KEEP,
        "identical to another link's inertial, which fits that link's (same) geometry: kept "
        "as its twin is",
        "Identical inputs get identical verdicts. A link whose values equal a twin's, with "
        "geometry that mirrors it, is judged as its twin is: when the twin's own geometry "
        "agrees with the values, this link's small differences of geometry (a coarser "
        "mesh, one contact sphere more) are no evidence against them.",
        "identical to left_ankle_link's inertial, which fits its geometry: kept",
        "nothing to silence: it is info"),
    R.JOINT_MAY_NOT_HOLD: RuleInfo(
        "UI707", W, Scope.JOINT, FixAction.NONE,
        "a joint's effort limit holds the gravity torque only at the low end of the band the "
        "derived masses give",
        "The derived links' error bars give a band of gravity torques: the effort limit is "
        "inside it, so whether the joint holds depends on values `fix` could only estimate.",
        "joint 'knee' must hold up to 41 N m: its effort limit 38 N m holds it only at the "
        "band's low end", "give the links their CAD masses; `check --no-statics`"),
    R.MASS_PRIOR: RuleInfo(
        "UI708", I_, Scope.ROBOT, FixAction.NONE,
        "links with no mass got the mass prior's: the robot's total with its band",
        "A link with no usable mass is given the effective density the mass prior predicts "
        "for it (the robot's kind, the part's size and place in the chain: "
        "docs/priors.md), with a calibrated band; the robot's total is stated beside what "
        "1000 kg/m³ gives, with the band robots' totals held to.",
        "6 links with no mass: 17.7 kg at 1000 kg/m³; the prior gives 21.2 kg (10.9-40.1, "
        "78 %)", "`--density KG_PER_M3` for a constant density; `--total-mass KG`"),
    R.MASS_DISTRIBUTION: RuleInfo(
        "UI704", E, Scope.INERTIAL, FixAction.CORRECT,
        "a link heavier than the rest of the robot, or ten times its mirror twin",
        "The robot's mass distribution is evidence: one link that outweighs all others "
        "together, or ten times its twin, is a slip (grams, a power of ten) with the "
        "likely edit named, not a design.",
        "link5 weighs 1226 kg, more than the other 16 links together (17.2 kg): mass x1e-3 "
        "gives 1.226 kg"),
    R.TOTAL_MASS_CHANGED: RuleInfo(
        "UI705", W, Scope.ROBOT, FixAction.NONE,
        "fix changes the robot's total mass by more than 1 %",
        "Derived masses (links without a mass, slips undone) change what the robot weighs. "
        "Check the links given mass, or state the robot's mass with `--total-mass`.",
        "total mass 47 kg -> 56.4 kg (+20.0 %)", "`fix --total-mass KG`"),
    R.MASS_TARGET_MET: RuleInfo(
        "UI706", I_, Scope.ROBOT, FixAction.NONE,
        "derived masses scaled to meet a target mass",
        "`--total-mass` or a spec's target: the derived (or, with `--scale-kept`, all) "
        "masses were scaled to meet it.", "total mass 51.2 kg -> 55 kg (target 55 kg)",
        "nothing to silence: it is info"),
    R.STATICS_COARSENED: RuleInfo(
        "UI709", I_, Scope.ROBOT, FixAction.NONE,
        "the statics sampled fewer configurations than usual: the robot is large",
        "The gravity loads are sampled over a bounded number of configurations (total and "
        "per joint, `urdfinertia.analysis.statics.MAX_WORK`), so that time and memory stay "
        "bounded on a long chain; beyond the bound fewer random configurations are drawn "
        "and fewer joints refined, and the loads found may be lower than the true largest.",
        "statics sampled 39 configurations, not 259, and refined 0 of 372 joints near their "
        "limit (1000 links): the loads found may be below the largest",
        "nothing to silence: it is info; `check --no-statics` skips the statics"),
    R.GEOMETRY_NOT_BODY: RuleInfo(
        "UI801", I_, Scope.LINK, FixAction.KEEP,
        "the geometry is not the body (contact spheres, a marker, a pin, an envelope): no "
        "evidence about the written values",
        "Geometry that does not represent the body says nothing about its density or size: "
        "contact spheres on a foot, a marker box, a pin, an envelope around a light link. "
        "Findings judged against it are not acted on; the written value is kept.",
        "collision (4 spheres, 5 mm): contact spheres, not the body", "nothing to silence: "
        "it is info"),
    R.NEGLIGIBLE_BODY: RuleInfo(
        "UI802", I_, Scope.LINK, FixAction.KEEP,
        "a frame body lighter than 0.1 % of the robot: left as it is",
        "A placeholder on a link that carries a negligible share of the robot's mass (a "
        "sensor frame, a 1 g hip) changes nothing a simulator does; with nothing to derive "
        "it from, it is left as it is without failing the run.",
        "under 0.1 % of the robot's mass: left as it is", "nothing to silence: it is info"),
    R.NO_GEOMETRY: RuleInfo(
        "UI803", W, Scope.LINK, FixAction.NONE,
        "nothing to compute from: the link has no usable geometry",
        "A link `fix` would recompute has no geometry element it can integrate: it is left "
        "as it was (`fix` exits 1) unless its values are invalid, which get the minimal "
        "repair.", "placeholder-inertia; no geometry to recompute from: left as it is",
        "give the link a collision or visual element, or a spec entry"),
    R.AUTO_INERTIAL_KEPT: RuleInfo(
        "UI804", I_, Scope.INERTIAL, FixAction.KEEP,
        "SDFormat <inertial auto=\"true\">: the simulator computes it (kept with --keep-auto)",
        "Gazebo computes the inertial from the collisions at load time.", '<inertial '
        'auto="true"/>', "nothing to silence: it is info"),
    R.READ_ONLY_BODY: RuleInfo(
        "UI805", W, Scope.LINK, FixAction.NONE,
        "the new values cannot be written where the inertial lives (an included file)",
        "An MJCF body defined in an included file: `fix` writes only the file it was given, "
        "so the link is left as it was.", "body 'hand' is defined in hand.xml (included)",
        "run `fix` on the included file"),
    R.DERIVED_FROM_IMPLAUSIBLE: RuleInfo(
        "UI806", W, Scope.LINK, FixAction.NONE,
        "a derived inertial whose implied density is no material's (asked for by --all, "
        "--geometry or --links)",
        "The geometry asked for holds the kept mass at a density no material has: the "
        "derived tensor is likely wrong.", "implied density 41000 kg/m^3 is outside "
        "50..25000"),
    R.GEOMETRY_SPANS_FAR: RuleInfo(
        "UI807", W, Scope.LINK, FixAction.NONE,
        "the geometry spans more than 10 m: a millimetre mesh without scale?",
        "A robot part more than 10 m across is a unit slip of the mesh.", "geometry spans "
        "152 m: millimetre mesh without scale?", 'add scale="0.001 0.001 0.001"'),
    R.MINIMAL_BODY: RuleInfo(
        "UI808", W, Scope.INERTIAL, FixAction.REPAIR,
        "a moving link with no usable mass and nothing to compute from: given the smallest "
        "body a simulator accepts",
        "A moving body needs mass: it gets 1e-5 kg, a 1 cm sphere, reported as such.",
        "given 1e-05 kg, a 1 cm sphere"),
    R.TENSOR_HOLDS_NOTHING: RuleInfo(
        "UI809", W, Scope.INERTIAL, FixAction.REPAIR,
        "a tensor with no information left (radius of gyration below 0.1 mm): replaced by "
        "a sphere of the written mass",
        "Lifting such a tensor would still leave it below MuJoCo's floor: it becomes a solid "
        "sphere of the written mass at `--density`.", "the tensor holds nothing to keep: a "
        "solid sphere of the mass at 1000 kg/m^3"),
    R.NOT_ASKED: RuleInfo(
        "UI810", I_, Scope.LINK, FixAction.KEEP,
        "not among the links `--links` names: kept as written",
        "`fix --links A B` recomputes the links named only.", "not named",
        "nothing to silence: it is info"),
    R.ASKED: RuleInfo(
        "UI813", I_, Scope.LINK, FixAction.RECOMPUTE,
        "recomputed because the options ask for it (`--all`, or named by `--links`)",
        "`fix --all` derives every link with geometry, `--links A B` the links named, "
        "whatever they carry; an invalid value of a link not asked for still gets the "
        "minimal repair.", "every link asked for", "nothing to silence: it is info"),
    R.SPEC_NAMED: RuleInfo(
        "UI811", I_, Scope.LINK, FixAction.RECOMPUTE,
        "named in the decomposition spec: recomputed from its parts",
        "A link the spec names is always computed from the spec's elements and parts (the "
        "paper's decomposition), whatever it carries.", "named in the spec",
        "nothing to silence: it is info"),
    R.TENSOR_LIFTED: RuleInfo(
        "UI812", I_, Scope.INERTIAL, FixAction.REPAIR,
        "the minimal repair: principal moments lifted just enough to be valid",
        "Mass and CoM are kept; the principal moments are raised by the least that makes "
        "the tensor positive definite and satisfy A + B >= C, in the link's own axes.",
        "principal moment 1 raised 2.1e-06 -> 2.4e-06 kg m^2 (A + B >= C)",
        "nothing to silence: it is info"),
}
del E, W, I_, R

if set(_TABLE) != set(Rule):  # pragma: no cover - a registry edit without its row
    raise RuntimeError(f"rules without a row: {sorted(set(Rule) - set(_TABLE))}")
if len({row.id for row in _TABLE.values()}) != len(_TABLE):  # pragma: no cover
    raise RuntimeError("two rules share an id")
