"""The library's commands: ``check``, ``fix``, ``compare``, ``explain`` and ``report`` in Python.

Each takes a description's path and the command line's options as keyword arguments with
the command line's defaults, and returns typed objects: the same per-link verdicts
(:class:`~urdfinertia.plan.results.LinkResult`) every command renders. The command line
is a thin shell over the same functions, so the answers agree link by link::

    import urdfinertia
    found = urdfinertia.check("robot.urdf")          # geometry read, as the CLI does
    result = urdfinertia.fix("robot.urdf", density=1200.0)
    print(result.recomputed, [r.status for r in result.links])

Options (:class:`~urdfinertia.body.options.FixOptions`): ``geometry`` ("auto",
"collision", "visual"), ``mass`` ("keep", "density"), ``density`` (kg/m^3),
``package_dirs`` (package name -> folder), ``max_faces``, ``spec`` (a path or a loaded
spec), ``strict``, ``keep_auto``, ``recompute`` ("needed", "all", "links") and ``links``;
for xacro input also ``xacro_args`` (NAME -> VALUE, as ``--xacro-arg NAME:=VALUE``).
A fixed xacro robot is written back into its sources with
:func:`~urdfinertia.plan.save.write_back`.
This module may import every layer below the command line.
"""

from __future__ import annotations

import functools
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any, TypeVar, cast

if TYPE_CHECKING:
    from urdfinertia.analysis.check import CheckResult
    from urdfinertia.analysis.compare import LinkComparison
    from urdfinertia.analysis.explain import Breakdown
    from urdfinertia.body.options import FixOptions
    from urdfinertia.plan.results import FixResult
    from urdfinertia.render.report import ReportData


_F = TypeVar("_F", bound=Callable[..., Any])


def _xacro_options(func: _F) -> _F:
    """Let ``func`` take ``xacro_args`` (NAME -> VALUE) among its keyword options: xacro
    input read in the call is expanded with them and ``package_dirs``; nothing outside the
    call is affected."""

    @functools.wraps(func)
    def wrapper(*args: Any, xacro_args: Mapping[str, str] | None = None,
                **kwargs: Any) -> Any:
        from urdfinertia.descriptions.xacro.expand import settings_for

        with settings_for(xacro_args, kwargs.get("package_dirs")):
            return func(*args, **kwargs)

    return cast(_F, wrapper)


def make_options(**options: Any) -> FixOptions:
    """:class:`FixOptions` from keyword arguments; ``spec`` may be a path, ``package_dirs``
    a mapping of names to folders given as strings or paths."""
    import dataclasses

    from urdfinertia.body.options import FixOptions
    from urdfinertia.body.spec import load_spec

    known = [f.name for f in dataclasses.fields(FixOptions)]
    unknown = [name for name in options if name not in known]
    if unknown:
        hint = (" (fix writes nothing: save the result with result.save(path), or use "
                "`urdf-inertia fix -o`)" if {"output", "out", "in_place"} & set(unknown)
                else "")
        raise TypeError(f"unknown option{'s' if len(unknown) > 1 else ''} "
                        f"{', '.join(map(repr, unknown))}{hint}; the options are "
                        f"{', '.join(known)}")
    spec = options.get("spec")
    if isinstance(spec, str | Path):
        options["spec"] = load_spec(spec)
    dirs = options.get("package_dirs")
    if isinstance(dirs, Mapping):  # relative folders are the working directory's
        options["package_dirs"] = {str(k): Path(v).expanduser().absolute()
                                   for k, v in dirs.items()}
    elif dirs is not None:
        raise TypeError(f"package_dirs must be a mapping of package names to folders, "
                        f"e.g. {{'my_robot': 'src/my_robot'}}, not {type(dirs).__name__}")
    links = options.get("links")
    if links:
        options["links"] = tuple(links)
        options.setdefault("recompute", "links")
    return FixOptions(**options)


@_xacro_options
def check(path: str | Path, *, geometry: bool = True, statics: bool = True,
          effort_margin: float | None = None, realizable: str = "ellipsoid",
          mass_tolerance: float | None = None, **options: Any) -> CheckResult:
    """Lint the description at ``path``: findings and what ``fix`` would do, per link.

    ``geometry=False`` checks the written values only (``check --no-geometry``).
    ``statics=False`` skips the joints' gravity loads (``check --no-statics``);
    ``effort_margin`` is ``--effort-margin`` (default 0.2); ``result.statics`` holds the
    total mass, whole CoM and every joint's load.
    ``realizable="hull"`` tests the written inertials in the geometry's convex hull instead
    of its bounding ellipsoid (``check --realizable hull``). ``total_mass=KG`` (or a spec's
    targets) is held against the written masses within ``mass_tolerance`` (a fraction,
    default 0.01; ``check --total-mass``, ``--mass-tolerance``).
    ``result.exit_code()`` is the command line's exit code without a baseline.
    """
    from urdfinertia.analysis.check import check_description
    from urdfinertia.analysis.statics import DEFAULT_MARGIN
    from urdfinertia.descriptions.formats import read_description
    from urdfinertia.plan.total_mass import DEFAULT_MASS_TOLERANCE

    opts = make_options(realizable=realizable, **options)
    robot, _ = read_description(path)
    margin = DEFAULT_MARGIN if effort_margin is None else effort_margin
    tolerance = DEFAULT_MASS_TOLERANCE if mass_tolerance is None else mass_tolerance
    return check_description(robot, options=opts, geometry=geometry, statics=statics,
                             effort_margin=margin, mass_tolerance=tolerance)


@_xacro_options
def fix(path: str | Path, **options: Any) -> FixResult:
    """Fix the inertials of the description at ``path``; nothing is written.

    ``result.output`` holds the patched document, ``result.links`` the verdicts.
    ``slips=False`` derives a flagged inertial from its geometry even where one edit of the
    written values undoes a slip (``fix --no-slips``). ``total_mass=KG`` scales the derived
    masses so that the robot weighs KG (``scale_kept=True``: every mass); ``result.targets``
    says before, target and after (``fix --total-mass``, ``--scale-kept``).
    """
    from urdfinertia.plan.fix import fix_file

    return fix_file(path, make_options(**options))


@_xacro_options
def compare(path: str | Path, against: str | Path | None = None, *,
            tol_com: float | None = None, tol_inertia: float | None = None,
            tol_mass: float | None = None, **options: Any) -> list[LinkComparison]:
    """The written inertials of ``path`` against its geometry (with ``fix``'s decision for
    each link), or against the inertials of the description ``against``."""
    from urdfinertia.analysis import compare as _compare

    tols = {"tol_com": _compare.DEFAULT_TOL_COM if tol_com is None else tol_com,
            "tol_inertia": _compare.DEFAULT_TOL_INERTIA if tol_inertia is None
            else tol_inertia,
            "tol_mass": _compare.DEFAULT_TOL_MASS if tol_mass is None else tol_mass}
    if against is not None:
        return _compare.compare_files(path, against, **tols)
    return _compare.compare_with_geometry(path, make_options(**options),
                                          tol_com=tols["tol_com"],
                                          tol_inertia=tols["tol_inertia"],
                                          tol_mass=tols["tol_mass"])


@_xacro_options
def explain(path: str | Path, link: str, **options: Any) -> Breakdown:
    """Link ``link`` of ``path``: what ``fix`` writes and its geometry element by element."""
    from urdfinertia.analysis.explain import explain_link
    from urdfinertia.descriptions.formats import read_description

    robot, _ = read_description(path)
    return explain_link(robot, link, make_options(**options))


@dataclass(frozen=True, eq=False)
class Report:
    """The HTML report of one description: ``html`` (one self-contained page) and the
    ``data`` it shows."""

    html: str
    data: ReportData

    def save(self, path: str | Path) -> Path:
        """Write the page to ``path`` atomically; returns the path."""
        from urdfinertia.atomic import atomic_write_bytes

        atomic_write_bytes(Path(path), self.html.encode("utf-8"))
        return Path(path)


@_xacro_options
def report(path: str | Path, *, view: str = "visual", face_budget: int | None = None,
           **options: Any) -> Report:
    """The HTML report of ``path`` (``report.save("robot.html")`` writes it)."""
    from urdfinertia.render.report import collect, render_html
    from urdfinertia.render.scene import DEFAULT_VIEW_FACES

    data = collect(path, make_options(**options), view=view,
                   face_budget=DEFAULT_VIEW_FACES if face_budget is None else face_budget)
    return Report(render_html(data), data)
