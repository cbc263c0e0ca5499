"""The structure prior of a link's tensor: its housing plus dense parts, as plain data.

A derived tensor integrates the link's geometry as one homogeneous body. A real link puts
part of its mass elsewhere: actuators on its joint axes, a dense core, or a hollow shell.
The structure prior says which, per kind of link (the data file's ``structure.cells``,
fitted by ``scripts/bench_priors.py`` with one package left out at a time), as a list of
`PriorPart` that sum to the link's mass with its kept
centre of mass:

- ``homogeneous``: one part, the geometry itself (what ``fix`` integrates today); kept
  wherever nothing else was measured to do better;
- ``actuators``: the geometry (the housing) with ``1 - n s`` of the mass, and a solid
  cylinder of ``s`` of the mass on each of the link's ``n`` moving joint axes (its parent
  joint's, its children's or both), of radius and length ``radius`` times the geometry's
  box diagonal. ``hold="housing"`` moves the housing so that the total keeps the CoM (the
  actuators stay on their axes); ``hold="rigid"`` moves every part together;
- ``core``: the geometry with ``1 - s`` of the mass and the geometry shrunk by ``scale``
  about its centroid with ``s`` (a dense core), moved together onto the kept CoM;
- ``shell``: the geometry less the geometry shrunk by ``scale`` (a hollow shell): a solid
  part of share ``1 / (1 - scale^3)`` and a cavity of share ``-scale^3 / (1 - scale^3)``.

`prior_body` turns the parts into mass properties (pure
numpy) so that the lead's
element/part decomposition and the benchmark compute the same tensor.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from urdfinertia.inertia.massprops import MassProperties, combine
from urdfinertia.priors.data import PriorTable, load_table
from urdfinertia.priors.features import JointAxis, LinkFeatures

MODELS = ("homogeneous", "actuators", "core", "shell")
#: shapes of a `PriorPart`
SHAPES = ("geometry", "scaled geometry", "cylinder")


@dataclass(frozen=True)
class PriorPart:
    """One part of a structure prior, in the link frame.

    name : "housing", "core", "cavity" or "actuator '<joint>'".
    share : of the link's mass (negative for a cavity; the shares sum to 1).
    position : (3,) where the part's centre of mass is, m.
    shape : "geometry" (the link's geometry, homogeneous, moved so that its centroid is at
        ``position``), "scaled geometry" (the geometry shrunk by ``scale`` about its
        centroid, then moved so), or "cylinder" (a solid cylinder of ``radius`` and full
        ``length`` along ``axis``, centred at ``position``).
    """

    name: str
    share: float
    position: tuple[float, float, float]
    shape: str
    scale: float | None = None
    axis: tuple[float, float, float] | None = None
    radius: float | None = None
    length: float | None = None

    def as_dict(self) -> dict[str, Any]:
        return {k: v for k, v in self.__dict__.items() if v is not None}


@dataclass(frozen=True)
class StructurePrior:
    """A link's structure prior: its parts, the cell and model that gave them, the band.

    band : the relative Frobenius error of the tensor against CAD that held for ``level``
        of the measured links of the cell, held out by package (None: the table has none
        for the cell). For the homogeneous body the tool's own error bar, which also
        knows the centroid-to-CoM offset, is finer.
    """

    model: str
    cell: str
    parts: tuple[PriorPart, ...]
    band: float | None
    level: float
    why: str


def cell_of(features: LinkFeatures, table: PriorTable) -> tuple[str, dict[str, Any]]:
    """The table's cell for a link: its part kind with its geometry, its part kind, or
    "*" (every link)."""
    cells = table.structure["cells"]
    for key in (f"{features.part}/{features.geometry}", features.part, "*"):
        if key in cells:
            return key, cells[key]
    return "*", {"model": "homogeneous"}


def _t3(v: np.ndarray) -> tuple[float, float, float]:
    return (float(v[0]), float(v[1]), float(v[2]))


def model_parts(cell: dict[str, Any], *, centroid: np.ndarray, com: np.ndarray,
                diagonal: float, axes: Sequence[JointAxis]) -> tuple[PriorPart, ...]:
    """The parts of one model (a cell's parameters) for a link whose geometry has its
    centroid at ``centroid`` and whose kept CoM is ``com`` (both (3,), link frame, m)."""
    centroid = np.asarray(centroid, dtype=np.float64)
    com = np.asarray(com, dtype=np.float64)
    model = cell.get("model", "homogeneous")
    if model == "actuators":
        ends = tuple(cell.get("ends", ("parent", "child")))
        chosen = [a for a in axes if a.end in ends]
        if chosen:
            return _actuators(cell, chosen, centroid, com, diagonal)
        model = "homogeneous"
    if model == "core":
        s, c = float(cell["share"]), float(cell["scale"])
        return (PriorPart("housing", 1.0 - s, _t3(com), "geometry"),
                PriorPart("core", s, _t3(com), "scaled geometry", scale=c))
    if model == "shell":
        c = float(cell["scale"])
        solid = 1.0 / (1.0 - c ** 3)
        return (PriorPart("housing", solid, _t3(com), "geometry"),
                PriorPart("cavity", 1.0 - solid, _t3(com), "scaled geometry", scale=c))
    if model != "homogeneous":
        raise ValueError(f"unknown structure model {model!r}")
    return (PriorPart("housing", 1.0, _t3(com), "geometry"),)


def _actuators(cell: dict[str, Any], axes: Sequence[JointAxis], centroid: np.ndarray,
               com: np.ndarray, diagonal: float) -> tuple[PriorPart, ...]:
    n = len(axes)
    s = min(float(cell["share"]), float(cell.get("max_share", 0.8)) / n)
    size = float(cell["radius"]) * diagonal
    points = np.array([a.point for a in axes], dtype=np.float64)
    housing_share = 1.0 - n * s
    if cell.get("hold", "housing") == "housing":
        # the actuators stay on their axes; the housing takes the rest of the kept CoM
        housing = (com - s * points.sum(axis=0)) / housing_share
        shift = np.zeros(3)
    else:
        housing = centroid
        shift = com - (housing_share * centroid + s * points.sum(axis=0))
        housing = housing + shift
    out = [PriorPart("housing", housing_share, _t3(housing), "geometry")]
    for a, p in zip(axes, points, strict=True):
        out.append(PriorPart(f"actuator '{a.name}'", s, _t3(p + shift), "cylinder",
                             axis=a.direction, radius=size, length=size))
    return tuple(out)


def structure_prior(features: LinkFeatures, *, centroid: np.ndarray, com: np.ndarray,
                    axes: Sequence[JointAxis], table: PriorTable | None = None,
                    ) -> StructurePrior:
    """The structure prior of a link whose mass and CoM are kept.

    Parameters
    ----------
    features : the link's features (`link_features`),
        of the geometry the tensor integrates.
    centroid : (3,) that geometry's centroid in the link frame, m.
    com : (3,) the kept centre of mass in the link frame, m.
    axes : the link's moving joints (`joint_axes`).
    """
    table = table or load_table()
    key, cell = cell_of(features, table)
    parts = model_parts(cell, centroid=centroid, com=com, diagonal=features.diagonal,
                        axes=axes)
    model = cell.get("model", "homogeneous") if len(parts) > 1 else "homogeneous"
    band = cell.get("band")
    why = cell.get("why", "") or f"{model} for {key} links"
    return StructurePrior(model, key, parts, None if band is None else float(band),
                          float(table.structure["level"]), why)


def _cylinder(mass: float, radius: float, length: float, axis: np.ndarray) -> np.ndarray:
    d = np.asarray(axis, dtype=np.float64)
    d = d / np.linalg.norm(d)
    along = 0.5 * mass * radius ** 2
    across = mass * (3.0 * radius ** 2 + length ** 2) / 12.0
    tensor: np.ndarray = across * np.eye(3) + (along - across) * np.outer(d, d)
    return tensor


def prior_body(parts: Sequence[PriorPart], housing: MassProperties, mass: float,
               ) -> MassProperties:
    """The link's mass properties from a structure prior's parts.

    ``housing`` is the link's geometry as one homogeneous body of any mass (its centroid
    and central tensor in the link frame); ``mass`` the link's kept mass, kg.
    """
    if not housing.mass > 0:
        raise ValueError("the housing must have a positive mass")
    per_kg = np.asarray(housing.inertia) / housing.mass
    bodies = []
    for p in parts:
        m = p.share * mass
        at = np.asarray(p.position, dtype=np.float64)
        if p.shape == "geometry":
            bodies.append(MassProperties(m, at, m * per_kg))
        elif p.shape == "scaled geometry":
            assert p.scale is not None
            bodies.append(MassProperties(m, at, m * p.scale ** 2 * per_kg))
        elif p.shape == "cylinder":
            assert p.radius is not None and p.length is not None and p.axis is not None
            bodies.append(MassProperties(m, at, _cylinder(m, p.radius, p.length,
                                                          np.asarray(p.axis))))
        else:
            raise ValueError(f"unknown part shape {p.shape!r}")
    return combine(bodies)
