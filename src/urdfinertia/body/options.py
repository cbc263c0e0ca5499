"""What the user asked for: the options of every command that computes from geometry.

[`FixOptions`][urdfinertia.body.options.FixOptions] is a frozen value; `select_geometry` is
the one rule for which of a link's elements make its parts. Importable without numpy or lxml
(a warm batch run needs only this).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import TYPE_CHECKING

from urdfinertia.mesh.limits import DEFAULT_MAX_FACES

if TYPE_CHECKING:
    from urdfinertia.body.spec import Spec
    from urdfinertia.descriptions.model import GeometryRef, Link

GEOMETRY_MODES = ("auto", "collision", "visual")
MASS_MODES = ("keep", "density")
#: Which links ``fix`` recomputes (:mod:`urdfinertia.plan.policy`): "needed" (the links
#: whose inertial is wrong), "all" (every link with geometry), "links" (those named).
RECOMPUTE_MODES = ("needed", "all", "links")
#: The regions realizability holds a written inertial in (``check --realizable``).
REALIZABLE_METHODS = ("ellipsoid", "hull")
#: Densities outside this range (kg/m^3) suggest a unit slip or a placeholder mass.
PLAUSIBLE_DENSITY = (50.0, 25000.0)


@dataclass(frozen=True)
class FixOptions:
    """What `urdf-inertia fix` was asked to do.

    Attributes
    ----------
    geometry : {"auto", "collision", "visual"}
        "auto" (per link, the geometry that best represents the body:
        `urdfinertia.body.geometry_choice`), "collision" or "visual".
    mass : {"keep", "density"}
        "keep" (keep a link's existing positive mass, geometry gives CoM and tensor) or
        "density" (mass = density x volume).
    density : float
        kg/m^3 used when a link has no mass or with `mass="density"`.
    density_prior : bool
        A link with no usable mass gets the density the mass prior predicts for it
        (`urdfinertia.priors`: the robot's kind, the part's size and
        place, with a calibrated band) instead of `density`. False when a density is
        given (`--density`, `density=`): a constant density, as asked.
    package_dirs : mapping of str to Path
        Where `package://NAME/` points (`--package-dir NAME=PATH`).
    max_faces : int
        Meshes with more faces are refused before they are read (`--max-faces`).
    spec : Spec or None
        A decomposition spec, when given.
    strict : bool
        All or nothing: an element dropped, a value of a link ignored or a link left as it
        was makes [`fix_robot`][urdfinertia.plan.fix.fix_robot] raise (`--strict`).
    keep_auto : bool
        Leave inertials the description asks its simulator to compute (SDF `auto="true"`).
    recompute : {"needed", "all", "links"}
        Which links are recomputed (`RECOMPUTE_MODES`); `links` names them for "links".
        Links named in `spec` are always recomputed.
    links : tuple of str
        The links recomputed with `recompute="links"`.
    slips : bool
        Undo a clear one-edit slip of a flagged inertial (`urdfinertia.judge.slips`)
        instead of deriving it from the geometry (`--no-slips`: False).
    total_mass : float or None
        kg the robot weighs: derived masses are scaled to meet it
        (`urdfinertia.plan.total_mass`), kept ones too with `scale_kept`
        (`--total-mass`, `--scale-kept`).
    scale_kept : bool
        With `total_mass`, scale every mass, kept ones too.
    realizable : {"ellipsoid", "hull"}
        The region the written inertials are held in for realizability (UI210):
        "ellipsoid" (the geometry's bounding ellipsoid) or "hull" (its convex hull, slower).
    """

    geometry: str = "auto"
    mass: str = "keep"
    density: float = 1000.0
    density_prior: bool = True
    package_dirs: Mapping[str, Path] = field(default_factory=dict)
    max_faces: int = DEFAULT_MAX_FACES
    spec: Spec | None = None  # a decomposition spec, when given
    strict: bool = False
    keep_auto: bool = False
    recompute: str = "needed"
    links: tuple[str, ...] = ()
    slips: bool = True
    total_mass: float | None = None
    scale_kept: bool = False
    realizable: str = "ellipsoid"

    def __post_init__(self) -> None:
        if self.geometry not in GEOMETRY_MODES:
            raise ValueError(f"geometry must be one of {GEOMETRY_MODES}")
        if self.mass not in MASS_MODES:
            raise ValueError(f"mass must be one of {MASS_MODES}")
        if self.recompute not in RECOMPUTE_MODES:
            raise ValueError(f"recompute must be one of {RECOMPUTE_MODES}")
        if (self.recompute == "links") != bool(self.links):
            raise ValueError('links are named with recompute="links", and only then')
        if not (math.isfinite(self.density) and self.density > 0):
            raise ValueError("density must be positive")
        if self.total_mass is not None and not (math.isfinite(self.total_mass)
                                                and self.total_mass > 0):
            raise ValueError("total_mass must be a positive number of kg")
        if self.realizable not in REALIZABLE_METHODS:
            raise ValueError(f"realizable must be one of {REALIZABLE_METHODS}")


def select_geometry(link: Link, mode: str) -> tuple[str, tuple[GeometryRef, ...]]:
    """The elements that describe the link's body for the checks (see :class:`FixOptions`).

    ``auto`` on a link whose format says which elements count for inertia (MJCF) takes
    those ("geom"); when none count (every geom stated massless, or outside MuJoCo's
    inertia groups) the link's other geoms still have the body's shape. Otherwise the
    collisions, else the visuals. A derived inertial chooses among all of them per link
    (:func:`urdfinertia.body.geometry_choice.choose`).
    """
    if mode == "auto" and link.inertia_geometry:
        return "geom", link.inertia_geometry
    if mode == "collision" or (mode == "auto" and link.collisions):
        return "collision", weighable(link.collisions)
    if mode == "visual" or (mode == "auto" and link.visuals):
        return "visual", weighable(link.visuals)
    return "none", ()


def weighable(refs: tuple[GeometryRef, ...]) -> tuple[GeometryRef, ...]:
    """``refs`` with their stated materials, or none at all when some are stated massless.

    A geom stated massless (MJCF ``density="0"`` or ``mass="0"``, a display-only geom)
    still has the body's shape: used for an inertial, the kept mass is spread uniformly
    over the whole set.
    """
    if any(r.mass == 0 or (r.mass is None and r.density == 0) for r in refs):
        return tuple(replace(r, density=None, mass=None, relative=False) for r in refs)
    return refs
