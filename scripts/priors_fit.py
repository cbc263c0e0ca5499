"""The analysis of ``bench_priors.py``: the measured records as rows, the mass model and the
structure prior fitted and cross-validated by package (leave one package out).

Nothing here reads meshes: it works on the JSON lines ``priors_corpus.py`` wrote, so the
tables can be printed again (``--from-samples``) without measuring.
"""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from urdfinertia.descriptions.model import Joint, Link, Origin, Robot
from urdfinertia.inertia.massprops import MassProperties
from urdfinertia.priors import fit
from urdfinertia.priors.features import (
    JointAxis,
    LinkFeatures,
    joint_axes,
    link_features,
    robot_features,
)
from urdfinertia.priors.structure import model_parts, prior_body
from urdfinertia.priors.terms import term_values

#: ridge penalties tried for the mass model
RIDGES = (0.01, 0.03, 0.1, 0.3, 1.0, 3.0)
#: band levels tried, lowest first: the lowest whose cross-validated coverage meets the
#: targets is kept (as ``bench_cad.py --calibrate`` does)
LEVELS = (0.80, 0.85, 0.90)
POOLED_TARGET = (0.75, 0.85)
PACKAGE_FLOOR = 0.60
BIG_PACKAGE = 10
#: a robot's total is judged over robots with at least this many CAD links
MIN_ROBOT_LINKS = 3
#: a structure cell is fitted on at least this many links, else the coarser cell is used
MIN_CELL = 20
#: a model other than the homogeneous body must beat it by this much (median error, on
#: the links it is fitted on) to be chosen
MARGIN = 0.005
#: ... and lower the median error in at least this share of the cell's training packages
#: of at least :data:`MIN_PACKAGE_LINKS` links
CONSISTENT = 2 / 3
MIN_PACKAGE_LINKS = 5


@dataclass
class TensorRow:
    """A unique CAD link with its mass and CoM kept: what the structure prior is tried on."""

    features: LinkFeatures
    centroid: np.ndarray
    com: np.ndarray
    per_kg: np.ndarray
    cad: np.ndarray
    mass: float
    axes: tuple[JointAxis, ...]
    tool: float
    tool_band: float
    oracle: float
    mujoco: float | None


@dataclass
class Row:
    """One CAD link of one robot record."""

    robot: int
    package: str
    file: str
    link: str
    unique: bool
    key: tuple[str, ...]
    mass: float
    features: LinkFeatures
    terms: dict[str, float]
    water: float
    fix_mass: float | None
    mujoco_mass: float | None
    tensor: TensorRow | None = None

    @property
    def y(self) -> float:
        return math.log10(self.mass / self.features.volume)


@dataclass
class Corpus:
    rows: list[Row]
    records: list[dict[str, Any]]
    kinds: list[str] = field(default_factory=list)  # robot kind per record
    whys: list[str] = field(default_factory=list)


def robot_of(record: dict[str, Any]) -> Robot:
    """The record's robot model: names and joints (no geometry)."""
    joints = tuple(Joint(j["name"], j["type"], j["parent"], j["child"],
                         Origin(tuple(j["xyz"]), tuple(j["rpy"])), axis=tuple(j["axis"]),
                         axis_point=tuple(j["point"])) for j in record["joints"])
    return Robot(record["robot"], tuple(Link(n) for n in record["links"]), joints,
                 format=record["format"])


def _box(c: dict[str, Any]) -> tuple[np.ndarray, np.ndarray] | None:
    return None if c["box"] is None else (np.array(c["box"][0]), np.array(c["box"][1]))


def _err(a: np.ndarray, b: np.ndarray) -> float:
    return float(np.linalg.norm(a - b) / np.linalg.norm(b))


def corpus_rows(records: list[dict[str, Any]]) -> Corpus:
    out = Corpus([], records)
    for i, rec in enumerate(records):
        robot = robot_of(rec)
        rf = robot_features(robot)
        out.kinds.append(rf.kind)
        out.whys.append(rf.why)
        for s in rec["samples"]:
            cands = s["candidates"]
            others = tuple(c["volume"] for c in cands)
            c = cands[s["nomass"]]
            f = link_features(s["link"], rf, volume=c["volume"], box=_box(c),
                              geometry=c["kind"], role=c["role"], others=others)
            mj = s["mujoco"]
            cad = np.asarray(s["inertia"]).reshape(3, 3)
            key = (f"{s['mass']:.6g}",
                   *(f"{m:.6g}" for m in np.linalg.eigvalsh(cad)))
            row = Row(i, rec["package"], rec["file"], s["link"], s["unique"], key, s["mass"],
                      f, term_values(f), c["water_mass"], s["fix_mass"],
                      None if mj is None else mj["mass"])
            if s["unique"] and s["tool"] is not None:
                k = cands[s["kept"]]
                fk = link_features(s["link"], rf, volume=k["volume"], box=_box(k),
                                   geometry=k["kind"], role=k["role"], others=others)
                per = [np.asarray(x["per_kg"]).reshape(3, 3) for x in cands]
                mjt = None
                if mj is not None and mj["mass"] > 0:
                    mjt = _err(np.asarray(mj["inertia"]).reshape(3, 3)
                               * (s["mass"] / mj["mass"]), cad)
                row.tensor = TensorRow(
                    fk, np.asarray(k["centroid"]), np.asarray(s["com"]),
                    per[s["kept"]], cad, s["mass"], joint_axes(robot, s["link"]),
                    s["tool"]["error"], s["tool"]["band"],
                    min(_err(s["mass"] * p, cad) for p in per), mjt)
            out.rows.append(row)
    return out


# --- the mass model ---------------------------------------------------------------------


@dataclass
class MassFit:
    ridge: float
    criteria: dict[float, float]
    held: np.ndarray  # held-out log10 density per row
    coefficients: dict[str, float]


def fit_mass(corpus: Corpus, ridges: tuple[float, ...] = RIDGES) -> MassFit:
    """The ridge with the smallest weighted held-out squared log error on unique links;
    its held-out predictions of every row; its coefficients fitted on every unique link."""
    rows = corpus.rows
    terms = [r.terms for r in rows]
    y = np.array([r.y for r in rows])
    groups = [r.package for r in rows]
    unique = np.array([r.unique for r in rows])
    keys = [r.key for r in rows]
    w = fit.package_weights([g for g, u in zip(groups, unique, strict=True) if u])
    criteria, preds = {}, {}
    for ridge in ridges:
        p = fit.held_out(terms, y, groups, ridge, fit_mask=unique, keys=keys)
        preds[ridge] = p
        criteria[ridge] = float(np.average((y[unique] - p[unique]) ** 2, weights=w))
    best = min(criteria, key=criteria.__getitem__)
    idx = np.flatnonzero(unique)
    coefficients = fit.fit_ridge([terms[i] for i in idx], y[idx],
                                 fit.package_weights([groups[i] for i in idx]), best)
    return MassFit(best, criteria, preds[best], coefficients)


def robot_groups(corpus: Corpus) -> list[list[int]]:
    """Rows of each distinct robot (records with the same CAD links are one), robots with
    at least :data:`MIN_ROBOT_LINKS` CAD links."""
    by: dict[int, list[int]] = {}
    for i, r in enumerate(corpus.rows):
        by.setdefault(r.robot, []).append(i)
    seen: set[tuple] = set()
    out = []
    for _, idx in sorted(by.items()):
        key = tuple(sorted(corpus.rows[i].key for i in idx))
        if key in seen or len(idx) < MIN_ROBOT_LINKS:
            continue
        seen.add(key)
        out.append(idx)
    return out


def choose_level(residuals: np.ndarray, groups: list[str],
                 ) -> tuple[float, dict[float, dict[str, np.ndarray]]]:
    """The lowest of :data:`LEVELS` whose nested coverage meets the targets (pooled within
    :data:`POOLED_TARGET`, no group of :data:`BIG_PACKAGE` or more below
    :data:`PACKAGE_FLOOR`); else the lowest that meets the pooled target (a package below
    the floor at every level is one the model does not describe, and a wider band for
    every link would not describe it either); else the one nearest its level."""
    tried = {}
    pooled_ok, meets = [], []
    for level in LEVELS:
        cov = fit.nested_coverage(residuals, groups, level)
        tried[level] = cov
        pooled = float(np.mean(np.concatenate(list(cov.values()))))
        big = [float(np.mean(v)) for v in cov.values() if len(v) >= BIG_PACKAGE]
        if POOLED_TARGET[0] <= pooled <= POOLED_TARGET[1]:
            pooled_ok.append(level)
            if min(big, default=1.0) >= PACKAGE_FLOOR:
                meets.append(level)
    if meets or pooled_ok:
        return min(meets or pooled_ok), tried
    nearest = min(LEVELS, key=lambda lv: abs(float(np.mean(np.concatenate(
        list(tried[lv].values())))) - lv))
    return nearest, tried


# --- the structure prior ----------------------------------------------------------------

def structure_grid() -> list[dict[str, Any]]:
    """Every model the structure prior chooses among, the homogeneous body first."""
    grid: list[dict[str, Any]] = [{"model": "homogeneous"}]
    for share, radius, ends, hold in itertools.product(
            (0.05, 0.1, 0.2), (0.05, 0.15), (("parent",), ("child",), ("parent", "child")),
            ("housing", "rigid")):
        grid.append({"model": "actuators", "share": share, "radius": radius,
                     "ends": list(ends), "hold": hold, "max_share": 0.8})
    for share in (0.2, 0.4):
        grid.append({"model": "core", "share": share, "scale": 0.5})
    for scale in (0.5, 0.8):
        grid.append({"model": "shell", "scale": scale})
    return grid


def tensor_errors(rows: list[TensorRow], grid: list[dict[str, Any]]) -> np.ndarray:
    """(links, models) relative Frobenius error of each model's tensor against CAD."""
    out = np.empty((len(rows), len(grid)))
    for i, t in enumerate(rows):
        housing = MassProperties(1.0, t.centroid, t.per_kg)
        for j, cell in enumerate(grid):
            parts = model_parts(cell, centroid=t.centroid, com=t.com,
                                diagonal=t.features.diagonal, axes=t.axes)
            body = prior_body(parts, housing, t.mass)
            out[i, j] = _err(np.asarray(body.inertia), t.cad)
    return out


def cell_keys(f: LinkFeatures) -> tuple[str, str, str]:
    return (f"{f.part}/{f.geometry}", f.part, "*")


def fit_cells(keys: list[tuple[str, str, str]], errors: np.ndarray, train: np.ndarray,
              groups: np.ndarray) -> dict[str, int]:
    """Per cell with at least :data:`MIN_CELL` training links, the model (grid column) of
    the smallest median training error, if it also lowers the median error in at least
    :data:`CONSISTENT` of the cell's training packages of :data:`MIN_PACKAGE_LINKS` or
    more links and beats the homogeneous body by :data:`MARGIN` pooled; else the
    homogeneous body (column 0)."""
    cells: dict[str, list[int]] = {}
    for i in np.flatnonzero(train):
        for k in keys[i]:
            cells.setdefault(k, []).append(int(i))
    out = {}
    for k, idx in cells.items():
        if len(idx) < MIN_CELL and k != "*":
            continue
        med = np.median(errors[idx], axis=0)
        j = int(np.argmin(med))
        out[k] = j if med[j] < med[0] - MARGIN and _consistent(errors, idx, groups, j) else 0
    return out


def _consistent(errors: np.ndarray, idx: list[int], groups: np.ndarray, j: int) -> bool:
    by: dict[str, list[int]] = {}
    for i in idx:
        by.setdefault(str(groups[i]), []).append(i)
    big = [v for v in by.values() if len(v) >= MIN_PACKAGE_LINKS]
    if len(big) < 2:
        return False  # one package alone cannot show that a model carries over
    wins = sum(np.median(errors[v, j]) < np.median(errors[v, 0]) for v in big)
    return wins >= CONSISTENT * len(big)


def lookup(cells: dict[str, Any], key: tuple[str, str, str]) -> Any:
    for k in key:
        if k in cells:
            return cells[k]
    return cells["*"]


def structure_cv(rows: list[TensorRow], groups: list[str], errors: np.ndarray,
                 ) -> tuple[np.ndarray, np.ndarray]:
    """Held-out (by package) model column and error of every link."""
    keys = [cell_keys(t.features) for t in rows]
    groups_a = np.asarray(groups)
    chosen = np.zeros(len(rows), int)
    for g in np.unique(groups_a):
        cells = fit_cells(keys, errors, groups_a != g, groups_a)
        for i in np.flatnonzero(groups_a == g):
            chosen[i] = lookup(cells, keys[i])
    return chosen, errors[np.arange(len(rows)), chosen]


def cell_bands(keys: list[tuple[str, str, str]], errors: np.ndarray, level: float,
               train: np.ndarray) -> dict[str, float]:
    """The ``level`` quantile of the errors per cell (cells as :func:`fit_cells`)."""
    cells: dict[str, list[float]] = {}
    for i in np.flatnonzero(train):
        for k in keys[i]:
            cells.setdefault(k, []).append(float(errors[i]))
    return {k: float(np.quantile(v, level)) for k, v in cells.items()
            if len(v) >= MIN_CELL or k == "*"}


def confirm_cells(cells: dict[str, int], keys: list[tuple[str, str, str]],
                  errors: np.ndarray, held: np.ndarray) -> dict[str, int]:
    """``cells`` (fitted on every package) with the homogeneous body put back in every
    cell whose links' held-out error (``held``: each link under the model its fold chose)
    is not below the homogeneous body's by :data:`MARGIN`: a model is kept only where it
    was measured to win on packages it was not fitted on."""
    out = dict(cells)
    for k, j in cells.items():
        if j == 0:
            continue
        idx = [i for i, key in enumerate(keys) if next(x for x in key if x in cells) == k]
        if not idx or not np.median(held[idx]) < np.median(errors[idx, 0]) - MARGIN:
            out[k] = 0
    return out
