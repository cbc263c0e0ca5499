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
    # UI2xx: against the geometry
    GEOMETRY_UNREADABLE = "geometry-unreadable"
    IMPLAUSIBLE_DENSITY = "implausible-density"
    COM_OUTSIDE_GEOMETRY = "com-outside-geometry"
    INERTIA_VS_GEOMETRY = "inertia-vs-geometry"
    MESH_UNRESOLVED = "mesh-unresolved"
    NOT_REALIZABLE = "not-realizable"
    GYRATION_IMPLAUSIBLE = "gyration-implausible"
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
    # UI5xx: what the reader read past
    VECTOR_UNPARSEABLE = "vector-unparseable"
    UNEXPANDED_SUBSTITUTION = "unexpanded-substitution"
    ZERO_SIZE_PRIMITIVE = "zero-size-primitive"
    UNSUPPORTED_GEOMETRY = "unsupported-geometry"
    MISSING_ATTRIBUTE = "missing-attribute"
    XML_READ_LENIENTLY = "xml-read-leniently"
    MISSING_LAYER = "missing-layer"
    # UI6xx: what the author meant
    SLIP_PROPOSED = "slip-proposed"
    INERTIAL_COPIED = "inertial-copied"
    TWINS_DISAGREE = "twins-disagree"
    # UI7xx: the whole robot
    JOINT_CANNOT_HOLD = "joint-cannot-hold"
    JOINT_EFFORT_MARGIN = "joint-effort-margin"
    TOTAL_MASS_MISMATCH = "total-mass-mismatch"

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
        "UI205", E, Scope.ELEMENT, FixAction.KEEP,
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
}
del E, W, I_, R

if set(_TABLE) != set(Rule):  # pragma: no cover - a registry edit without its row
    raise RuntimeError(f"rules without a row: {sorted(set(Rule) - set(_TABLE))}")
if len({row.id for row in _TABLE.values()}) != len(_TABLE):  # pragma: no cover
    raise RuntimeError("two rules share an id")
