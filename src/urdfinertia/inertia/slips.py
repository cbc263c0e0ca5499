"""One-edit repairs of a written inertial: the slip an author made, searched and ranked.

Pure numpy. A wrong CAD inertial is usually wrong by one slip, not wholesale: a power of ten on one
entry, grams for kilograms, kg mm^2 for kg m^2, products of inertia with CAD's sign (`+integral(xy
dm)` where URDF wants `-integral(xy dm)`), the entries in another order, the tensor about the link
origin instead of the CoM, the CoM in millimetres, the origin's `rpy` applied twice or not at all.
[`candidate_edits`][urdfinertia.inertia.slips.candidate_edits] lists every such edit of the written
values; [`rank_edits`][urdfinertia.inertia.slips.rank_edits] scores each against the homogeneous
solid of the link's geometry ([`Solid`][urdfinertia.inertia.slips.Solid]) and
[`propose`][urdfinertia.inertia.slips.propose] returns the best edit when it is clearly the one.

The score
---------
The score of an edit is a negative log-likelihood (chi-square units: a difference of `d`
is a likelihood ratio of `exp(d / 2)`) of the edited inertial given the geometry, plus
the edit's prior cost:

- each diagonal entry against the solid's at the edited mass: ``(ln(I_ii / G_ii) /
  SIGMA_MOMENT)^2``; real links are hollow and uneven, so CAD's moments scatter around the
  solid's by a factor (`SIGMA_MOMENT`, measured on real robots), not a fraction;
- each product, normalised `I_ij / sqrt(I_ii I_jj)` (in -1..1), against the solid's:
  `(difference / SIGMA_PRODUCT)^2`;
- the implied density against a typical link's: `(ln(rho / RHO_TYPICAL) / SIGMA_DENSITY)^2`;
- the CoM's distance from the solid's centroid in box diagonals: `(d / SIGMA_COM)^2`;
- the prior cost of the edit (`PRIOR_COST`): no edit costs nothing, one unit slip of
  the whole inertial a little, a power of ten on one of six entries more.

An edit is *feasible* when its inertial is valid (positive mass, symmetric, positive definite,
triangle inequality), plausible against the geometry as `check` judges it
([`Limits`][urdfinertia.inertia.slips.Limits]), and its tensor lies within the geometry's error bar
(relative Frobenius difference at most `Limits.band`).
[`propose`][urdfinertia.inertia.slips.propose] gives the lowest-scoring feasible edit when it is not
"no edit" and the next feasible one (the runner-up, "no edit" included) scores at least `MARGIN`
more. A placeholder-shaped tensor (three equal diagonal entries) gets no proposal: it was typed, not
exported with a slip.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field
from decimal import Decimal

import numpy as np
from numpy.typing import ArrayLike

from urdfinertia.inertia.rotation import rpy_matrix
from urdfinertia.inertia.validity import diagnose_tensor

# The spreads below are measured on 123 de-duplicated CAD links that ``check`` finds
# plausible, from 10 packages (``scripts/bench_slips.py``'s corpus, 6 files a package):
SIGMA_MOMENT = 0.7
"""Spread of ln(CAD moment / homogeneous solid's moment): standard deviation 0.68 (the e-fold of the
factor by which a hollow, uneven link's moment differs from its solid's).
"""
SIGMA_PRODUCT = 0.12
"""Spread of a normalised product of inertia around the solid's: standard deviation 0.12."""
RHO_TYPICAL = 1000.0
"""A typical link's mass over its geometry's volume (kg/m^3; median 1000) and the spread of its
logarithm (standard deviation 0.96).
"""
SIGMA_DENSITY = 1.0
SIGMA_COM = 0.13
"""Spread of the CoM's distance from the solid's centroid, in box diagonals (rms 0.13)."""
MARGIN = 9.0
"""How much more the runner-up must score for the best edit to be proposed (chi-square units: a
likelihood ratio of exp(MARGIN / 2), about 90).
"""
PRIOR_COST = {"none": 0.0, "mass-unit": 2.0, "tensor-unit": 2.0, "inertial-unit": 3.0,
              "com-unit": 2.0, "products-sign": 2.0, "product-sign": 4.0, "order": 3.0,
              "parallel-axis": 2.0, "rpy": 3.0, "entry-power": 4.0}
"""Prior cost of an edit by class: how unlikely the slip is before looking at the numbers."""
SLIP_CLASSES = tuple(k for k in PRIOR_COST if k != "none")
"""Slip classes, in the order the docs list them."""
ENTRIES = ("ixx", "ixy", "ixz", "iyy", "iyz", "izz")
ENTRY_POWERS = tuple(k for k in range(-9, 10) if k != 0)
"""Powers of ten tried on a single entry."""
_DIAG = (0, 3, 5)
_PRODUCTS = ((1, 0, 1), (2, 0, 2), (4, 1, 2))  # (entry index, row, column)
SAME_RTOL = 1e-9
"""Two edits whose values agree to this relative tolerance are the same edit."""


@dataclass(frozen=True, eq=False)
class Written:
    """An inertial as written: the values a slip is made in, in the file's own terms.

    Attributes
    ----------
    mass : float
        kg.
    xyz : (3,) float
        The CoM in the link frame, m.
    rpy : (3,) float
        The inertial origin's angles, rad.
    entries : (6,) float
        `ixx ixy ixz iyy iyz izz` along the origin's axes, URDF sign convention
        (`ixy = -integral(xy dm)`), kg m^2.
    """

    mass: float
    xyz: np.ndarray
    rpy: np.ndarray
    entries: np.ndarray

    def __post_init__(self) -> None:
        for name, shape in (("xyz", (3,)), ("rpy", (3,)), ("entries", (6,))):
            value = np.asarray(getattr(self, name), dtype=np.float64)
            if value.shape != shape:
                raise ValueError(f"{name} must have shape {shape}, got {value.shape}")
            object.__setattr__(self, name, value)
        object.__setattr__(self, "mass", float(self.mass))

    def tensor(self) -> np.ndarray:
        """The (3, 3) tensor about the CoM along the link frame's axes, kg m^2."""
        rot = rpy_matrix(self.rpy)
        turned: np.ndarray = rot @ _matrix(self.entries) @ rot.T
        return turned


@dataclass(frozen=True, eq=False)
class Solid:
    """The homogeneous solid of the link's geometry, the reference an edit is held to.

    Attributes
    ----------
    volume : float
        m^3.
    centroid : (3,) float
        In the link frame, m.
    inertia : (3, 3) float
        About the centroid along the link's axes at unit mass (kg m^2 per kg: scaled by the
        mass under test).
    lo, hi : (3,) float
        The geometry's bounding box in the link frame, m.
    """

    volume: float
    centroid: np.ndarray
    inertia: np.ndarray
    lo: np.ndarray
    hi: np.ndarray

    @property
    def diagonal(self) -> float:
        """The length of the bounding box's diagonal, m."""
        return float(np.linalg.norm(np.asarray(self.hi) - np.asarray(self.lo)))


@dataclass(frozen=True)
class Limits:
    """What `check` accepts, so that an edit it proposes is not flagged again.

    Attributes
    ----------
    density : (float, float)
        The plausible densities (lo, hi), kg/m^3.
    com_outside : float
        The CoM may lie outside the geometry's box by at most this fraction of its diagonal.
    ratio : float
        The tensor's trace is within this factor of the solid's, either way.
    band : float
        The error bar: the relative Frobenius difference from the solid's tensor an edit may
        have.
    com_slip : float
        A CoM is taken as written in millimetres (the x1e-3 edit) only when it lies farther
        than this many box diagonals outside the geometry (nearer, it is a modelling error,
        not a unit).
    edited_density : (float, float)
        An edit that changes the mass must give a density a robot part has (lo, hi),
        kg/m^3: narrower than `density`, what any material has, since a correction must
        make the value fit the body, not only land inside a window.
    """

    density: tuple[float, float] = (50.0, 25000.0)
    com_outside: float = 0.25
    ratio: float = 100.0
    band: float = 0.8
    com_slip: float = 10.0
    edited_density: tuple[float, float] = (100.0, 10000.0)


@dataclass(frozen=True, eq=False)
class Edit:
    """One candidate edit of the written values.

    Attributes
    ----------
    slip : str
        Its class (a key of `PRIOR_COST`).
    name : str
        Short: "izz x1e-3".
    words : str
        What the author likely did: "izz looks 1000x too large".
    written : Written
        The values after the edit.
    changed : frozenset of str
        Which of "mass", "com", "tensor" the edit changes.
    link_tensor : (3, 3) float or None
        The edited tensor in the link frame (None: `written`'s).
    """

    slip: str
    name: str
    words: str
    written: Written
    changed: frozenset[str]
    link_tensor: np.ndarray | None = field(default=None)

    def tensor(self) -> np.ndarray:
        """The edited (3, 3) tensor in the link frame, kg m^2."""
        return self.link_tensor if self.link_tensor is not None else self.written.tensor()


@dataclass(frozen=True, eq=False)
class Scored:
    """An edit with its score, feasibility and tensor error.

    Attributes
    ----------
    edit : Edit
        The candidate.
    score : float
        Lower is likelier.
    feasible : bool
        The edited values are valid and pass `check`'s limits.
    tensor_error : float
        The relative Frobenius difference from the solid's tensor at the edited mass.
    why_not : str
        Why it is not feasible (empty when it is).
    """

    edit: Edit
    score: float
    feasible: bool
    tensor_error: float
    why_not: str = ""
    """Why it is not feasible ("" when it is)"""


@dataclass(frozen=True, eq=False)
class Proposal:
    """The edit proposed and the runner-up: the next feasible edit, else the next-best
    infeasible one (None: no other edit). `margin`: how much more the next feasible
    edit scores (inf: none is feasible)."""

    best: Scored
    runner_up: Scored | None
    margin: float


def _matrix(e: np.ndarray) -> np.ndarray:
    return np.array([[e[0], e[1], e[2]], [e[1], e[3], e[4]], [e[2], e[4], e[5]]])


def _entries(t: np.ndarray) -> np.ndarray:
    return np.array([t[0, 0], t[0, 1], t[0, 2], t[1, 1], t[1, 2], t[2, 2]])


def decimal_shift(x: np.ndarray | float, k: int) -> np.ndarray:
    """`x` x 10^k as the decimal shift of its shortest text (1.05 x 1e-3 is 0.00105, not
    0.0010500000000000002): a slip undone gives back the number the author typed.

    Parameters
    ----------
    x : float or array of float
        The written values.
    k : int
        The power of ten.

    Returns
    -------
    array of float
        `x` shifted, element by element.
    """
    values = np.atleast_1d(np.asarray(x, dtype=np.float64))
    return np.array([float(Decimal(repr(float(v))).scaleb(k)) if np.isfinite(v) else v
                     for v in values])


def _times(k: int) -> str:
    return f"{10.0 ** abs(k):g}x too {'large' if k > 0 else 'small'}"


def no_edit(w: Written) -> Edit:
    """The written values as they are: the baseline every edit is ranked against.

    Parameters
    ----------
    w : Written
        The inertial as written.

    Returns
    -------
    Edit
        The edit that changes nothing.
    """
    return Edit("none", "no edit", "as written", w, frozenset())


def candidate_edits(w: Written) -> list[Edit]:
    """Every one-slip edit of `w` (no edit first), duplicates of an earlier one dropped.

    Each single entry x10^k (k in -9..9), the mass x10^+-3, the tensor x10^+-3, +-6, +-9,
    mass and tensor x1e-3 together (an inertial in grams; not x1e3: a link 1000x too light
    throughout cannot be told from a light envelope geometry), the products negated (all, or
    one), the entries read in another order (diagonal first, a swap of two products), the
    parallel-axis term removed (a tensor about the link origin), the CoM x10^+-3, and the
    origin's rpy ignored or inverted.

    Parameters
    ----------
    w : Written
        The inertial as written.

    Returns
    -------
    list of Edit
        The candidates, the unchanged values first.
    """
    out = [no_edit(w)]

    def add(slip: str, name: str, words: str, changed: str, mass: float | None = None,
            xyz: np.ndarray | None = None, entries: np.ndarray | None = None,
            link_tensor: np.ndarray | None = None) -> None:
        edited = Written(w.mass if mass is None else mass, w.xyz if xyz is None else xyz,
                         w.rpy, w.entries if entries is None else entries)
        out.append(Edit(slip, name, words, edited, frozenset(changed.split()), link_tensor))

    for i, label in enumerate(ENTRIES):
        if w.entries[i] == 0:
            continue
        for k in ENTRY_POWERS:
            e = w.entries.copy()
            e[i] = decimal_shift(e[i], -k)[0]
            add("entry-power", f"{label} x1e{-k:+d}", f"{label} looks {_times(k)}", "tensor",
                entries=e)
    for k in (3, -3):
        add("mass-unit", f"mass x1e{-k:+d}", "mass in grams" if k > 0 else
            "mass 1000x too small", "mass", mass=decimal_shift(w.mass, -k)[0])
        if k > 0:  # 1000x too light throughout is a light envelope's signature: not tried
            add("inertial-unit", f"mass and tensor x1e{-k:+d}", "mass and tensor in grams",
                "mass tensor", mass=decimal_shift(w.mass, -k)[0],
                entries=decimal_shift(w.entries, -k))
        add("com-unit", f"com x1e{-k:+d}", "CoM in millimetres" if k > 0 else
            "CoM 1000x too small", "com", xyz=decimal_shift(w.xyz, -k))
    units = {3: "g m^2 or kg mm^2 x 1e-3", 6: "kg mm^2", 9: "g mm^2"}
    for k in (3, 6, 9, -3, -6, -9):
        words = f"tensor in {units[k]}" if k > 0 else f"tensor {_times(k)}"
        add("tensor-unit", f"tensor x1e{-k:+d}", words, "tensor",
            entries=decimal_shift(w.entries, -k))
    sign = w.entries.copy()
    sign[[1, 2, 4]] *= -1
    add("products-sign", "products negated", "products of inertia with CAD's sign "
        "(+integral xy dm; URDF wants -integral xy dm)", "tensor", entries=sign)
    for i, _, _ in _PRODUCTS:
        e = w.entries.copy()
        e[i] *= -1
        add("product-sign", f"{ENTRIES[i]} negated", f"{ENTRIES[i]} with the opposite sign",
            "tensor", entries=e)
    e = w.entries
    # read as URDF's ixx ixy ixz iyy iyz izz, written in MuJoCo's ixx iyy izz ixy ixz iyz
    add("order", "entries diagonal-first", "entries written diagonal first (ixx iyy izz ixy "
        "ixz iyz) and read as ixx ixy ixz iyy iyz izz", "tensor",
        entries=np.array([e[0], e[3], e[4], e[1], e[5], e[2]]))
    add("order", "entries upper-triangle", "entries written row by row (ixx ixy ixz iyy iyz "
        "izz) and read diagonal first", "tensor",
        entries=np.array([e[0], e[3], e[5], e[1], e[2], e[4]]))
    for a, b in ((1, 2), (1, 4), (2, 4)):
        s = e.copy()
        s[[a, b]] = s[[b, a]]
        add("order", f"{ENTRIES[a]}/{ENTRIES[b]} swapped", f"{ENTRIES[a]} and {ENTRIES[b]} "
            "swapped", "tensor", entries=s)
    rot = rpy_matrix(w.rpy)
    shift = w.mass * (float(w.xyz @ w.xyz) * np.eye(3) - np.outer(w.xyz, w.xyz))
    add("parallel-axis", "parallel axis removed", "tensor about the link origin, not the CoM "
        "(the parallel-axis shift forgotten)", "tensor", link_tensor=w.tensor() - shift)
    if np.any(w.rpy != 0):
        add("rpy", "rpy ignored", "tensor already along the link's axes: the origin's rpy "
            "applied to it by mistake", "tensor", link_tensor=_matrix(w.entries))
        add("rpy", "rpy inverted", "the origin's rotation given the other way round",
            "tensor", link_tensor=rot.T @ _matrix(w.entries) @ rot)
    return _distinct(out)


def _distinct(edits: list[Edit]) -> list[Edit]:
    """Drop an edit whose values equal an earlier one's (a zero product negated is no edit)."""
    keys = np.array([np.concatenate(([e.written.mass], e.written.xyz, _entries(e.tensor())))
                     for e in edits])
    kept: list[int] = []
    for i, key in enumerate(keys):
        if kept:
            same = np.all(np.abs(keys[kept] - key) <= SAME_RTOL * np.abs(key), axis=1)
            if np.any(same):
                continue
        kept.append(i)
    return [edits[i] for i in kept]


def score_edit(edit: Edit, solid: Solid, limits: Limits) -> Scored:
    """The edit's score against `solid` (module doc) and whether it is feasible.

    Parameters
    ----------
    edit : Edit
        A candidate.
    solid : Solid
        The homogeneous solid of the link's geometry.
    limits : Limits
        What `check` accepts.

    Returns
    -------
    Scored
        The score (lower is likelier), feasibility, tensor error and why not.
    """
    w = edit.written
    tensor = edit.tensor()
    prior = PRIOR_COST[edit.slip]
    if not (math.isfinite(w.mass) and w.mass > 0 and np.all(np.isfinite(w.xyz))
            and np.all(np.isfinite(tensor))):
        return Scored(edit, math.inf, False, math.inf, "not finite or mass not positive")
    geo = w.mass * np.asarray(solid.inertia)
    err = float(np.linalg.norm(tensor - geo)) / max(float(np.linalg.norm(geo)), 1e-300)
    # a moment below a thousandth of the trace is compared as that thousandth: a flat
    # plate's smallest moment says nothing, and an edit is not scored on round-off
    floor = 1e-3 * float(np.trace(geo))
    d = np.maximum(np.diag(tensor), 1e-3 * max(float(np.trace(tensor)), floor))
    g = np.maximum(np.diag(geo), floor)
    fit = float(np.sum((np.log(d / g) / SIGMA_MOMENT) ** 2))
    for _, r, c in _PRODUCTS:
        mine = tensor[r, c] / (math.sqrt(d[r]) * math.sqrt(d[c]))
        theirs = geo[r, c] / (math.sqrt(g[r]) * math.sqrt(g[c]))
        fit += ((mine - theirs) / SIGMA_PRODUCT) ** 2
    rho = w.mass / solid.volume
    fit += (math.log(rho / RHO_TYPICAL) / SIGMA_DENSITY) ** 2
    diag = solid.diagonal
    if diag > 0:
        fit += (float(np.linalg.norm(w.xyz - solid.centroid)) / diag / SIGMA_COM) ** 2
    score = fit + prior
    why = _infeasible(w, tensor, geo, err, solid, limits, "mass" in edit.changed)
    return Scored(edit, score, not why, err, why)


def _infeasible(w: Written, tensor: np.ndarray, geo: np.ndarray, err: float, solid: Solid,
                limits: Limits, mass_edited: bool = False) -> str:
    if not diagnose_tensor(tensor).valid:
        return "tensor invalid"
    lo, hi = limits.edited_density if mass_edited else limits.density
    if not lo <= w.mass / solid.volume <= hi:
        return "implausible density"
    if _outside(w.xyz, solid) > limits.com_outside * solid.diagonal:
        return "CoM outside the geometry"
    if float(np.trace(tensor)) > _ceiling(w.mass, w.xyz, solid):
        return "radius of gyration beyond the part"
    ratio = float(np.trace(tensor) / np.trace(geo))
    if not 1 / limits.ratio <= ratio <= limits.ratio:
        return "tensor size implausible"
    if err > limits.band:
        return f"tensor {100 * err:.0f} % from the geometry's, beyond its error bar"
    return ""


def placeholder_shaped(w: Written) -> bool:
    """Three equal diagonal entries: a placeholder someone typed (0.001 three times, 1e-8 on
    a 0.1 g camera, "5 5 5" with a product added), not a CAD value with a slip in it; no
    edit of it is what the author meant. (A CAD sphere or cube has them too: its slips are
    missed.)

    Parameters
    ----------
    w : Written
        The inertial as written.

    Returns
    -------
    bool
        Whether its three diagonal entries are equal.
    """
    e = w.entries
    return bool(e[0] == e[3] == e[5])


def _ceiling(mass: float, com: np.ndarray, solid: Solid) -> float:
    """The largest trace of a tensor about ``com`` of ``mass`` inside the solid's box:
    trace = 2 integral |r - c|^2 dm <= 2 m max |corner - c|^2."""
    lo, hi = np.asarray(solid.lo), np.asarray(solid.hi)
    corners = np.array([[x, y, z] for x in (lo[0], hi[0]) for y in (lo[1], hi[1])
                        for z in (lo[2], hi[2])])
    return 2 * mass * float(np.max(np.sum((corners - com) ** 2, axis=1)))


def _outside(xyz: np.ndarray, solid: Solid) -> float:
    """How far `xyz` lies outside the geometry's box (0 inside), m."""
    lo, hi = np.asarray(solid.lo), np.asarray(solid.hi)
    return float(np.linalg.norm(np.maximum(np.maximum(lo - xyz, xyz - hi), 0.0)))


def rank_edits(w: Written, solid: Solid, limits: Limits | None = None) -> list[Scored]:
    """Every candidate edit ([`candidate_edits`][urdfinertia.inertia.slips.candidate_edits])
    scored, best (lowest) first.

    Parameters
    ----------
    w : Written
        The inertial as written.
    solid : Solid
        The homogeneous solid of the link's geometry.
    limits : Limits, optional
        What `check` accepts (default: `Limits()`).

    Returns
    -------
    list of Scored
        Best first.
    """
    limits = limits or Limits()
    far = _outside(w.xyz, solid) > limits.com_slip * solid.diagonal
    scored = [score_edit(e, solid, limits) for e in candidate_edits(w)]
    scored = [dataclasses.replace(s, feasible=False, why_not="CoM not far enough out to be "
                                  "in millimetres")
              if s.edit.slip == "com-unit" and s.feasible and not far else s for s in scored]
    return sorted(scored, key=lambda s: (s.score, PRIOR_COST[s.edit.slip]))


def propose(w: Written, solid: Solid, limits: Limits | None = None) -> Proposal | None:
    """The edit that undoes the slip, when one is clearly it (module doc).

    Parameters
    ----------
    w : Written
        The inertial as written.
    solid : Solid
        The homogeneous solid of the link's geometry.
    limits : Limits, optional
        What `check` accepts (default: `Limits()`).

    Returns
    -------
    Proposal or None
        The edit and why, or None when no edit clearly beats every other.
    """
    if placeholder_shaped(w):
        return None
    ranked = rank_edits(w, solid, limits)
    feasible = [s for s in ranked if s.feasible]
    if not feasible or feasible[0].edit.slip == "none":
        return None
    best = feasible[0]
    if len(feasible) > 1:
        runner: Scored | None = feasible[1]
        margin = feasible[1].score - best.score
    else:
        runner = next((s for s in ranked if s is not best), None)
        margin = math.inf
    return Proposal(best, runner, margin) if margin >= MARGIN else None


def written(mass: float, xyz: ArrayLike, rpy: ArrayLike, entries: ArrayLike) -> Written:
    """A [`Written`][urdfinertia.inertia.slips.Written] from plain values.

    Parameters
    ----------
    mass : float
        kg.
    xyz : (3,) float
        The CoM, m.
    rpy : (3,) float
        The inertial origin's angles, rad.
    entries : (6,) float
        `ixx ixy ixz iyy iyz izz`, kg m^2.

    Returns
    -------
    Written
        The values, checked for shape.
    """
    return Written(mass, np.asarray(xyz, dtype=np.float64), np.asarray(rpy, dtype=np.float64),
                   np.asarray(entries, dtype=np.float64))
