"""The library's commands: `check`, `fix`, `compare`, `explain` and `report` in Python.

Each takes a description's path and the command line's options as keyword arguments, with
the command line's defaults, and returns typed objects: the same per-link verdicts
([LinkResult][urdfinertia.plan.results.LinkResult]) every command renders. The command line
is a thin shell over the same functions, so the answers agree link by link:

```python
import urdfinertia

found = urdfinertia.check("robot.urdf")          # geometry read, as the command line does
result = urdfinertia.fix("robot.urdf", density=1200.0)
print(result.recomputed, [r.status for r in result.links])
result.save("robot.fixed.urdf")                  # the bytes `fix -o` writes
```

The options every command that reads geometry takes are the fields of
[FixOptions][urdfinertia.body.options.FixOptions]; for xacro input also `xacro_args`
(NAME -> VALUE, as `--xacro-arg NAME:=VALUE`). A fixed xacro robot is written back into its
sources with [write_back][urdfinertia.plan.save.write_back]. The table under "The command
line in Python" maps every option of the command line to its keyword.

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
    """Let `func` take `xacro_args` (NAME -> VALUE) among its keyword options: xacro input
    read in the call is expanded with them and `package_dirs`; nothing outside the call is
    affected."""

    @functools.wraps(func)
    def wrapper(*args: Any, xacro_args: Mapping[str, str] | None = None,
                **kwargs: Any) -> Any:
        from urdfinertia.descriptions.xacro.expand import settings_for

        with settings_for(xacro_args, kwargs.get("package_dirs")):
            return func(*args, **kwargs)

    return cast(_F, wrapper)


def make_options(**options: Any) -> FixOptions:
    """The [FixOptions][urdfinertia.body.options.FixOptions] the keyword arguments ask for.

    Parameters
    ----------
    **options
        The fields of `FixOptions`, by name; `spec` may also be a path, `package_dirs` a
        mapping of names to folders given as strings or paths, `links` any sequence.

    Returns
    -------
    FixOptions
        The options, validated.

    Raises
    ------
    TypeError
        On a keyword that is not an option; the message lists the options.
    ValueError
        On a value out of range (an unknown geometry mode, a negative density).
    """
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
    if "density" in options:  # a density asked for is a constant one, as --density
        options.setdefault("density_prior", False)
    return FixOptions(**options)


@_xacro_options
def check(path: str | Path, *, geometry: bool = True, statics: bool = True,
          effort_margin: float | None = None, realizable: str = "ellipsoid",
          mass_tolerance: float | None = None, **options: Any) -> CheckResult:
    """Lint the description at `path`: its findings and what `fix` would do, per link.

    Nothing is written. The same as `urdf-inertia check`: the geometry is read, and every
    link gets the verdict `fix` would act on.

    Parameters
    ----------
    path : str or Path
        A URDF, xacro, SDFormat, MJCF or USD file.
    geometry : bool
        False checks the written values only and reads no mesh (`--no-geometry`).
    statics : bool
        False skips the joints' gravity loads (`--no-statics`).
    effort_margin : float, optional
        The fraction of a joint's effort limit that warns (`--effort-margin`, 0.2).
    realizable : {"ellipsoid", "hull"}
        Test the written inertials inside the geometry's bounding ellipsoid, or its convex
        hull (`--realizable`).
    mass_tolerance : float, optional
        The fraction by which the written masses may miss `total_mass` or a spec's target
        (`--mass-tolerance`, 0.01).
    **options
        The options of [fix][urdfinertia.api.fix], and `total_mass` (kg) to hold
        the written masses against. Note that `geometry` here is the boolean above: the
        geometry mode of `fix` is not an option of `check` in Python.

    Returns
    -------
    CheckResult
        `findings`, `links` (one verdict per link), `would_change`, `statics` (total mass,
        whole CoM, every joint's load) and `exit_code(strict=False)`, the command line's
        exit code without a baseline.

    Raises
    ------
    UrdfInertiaError
        When the file cannot be read at all (a problem inside it is a finding instead).

    Examples
    --------
    ```python
    checked = urdfinertia.check("robots/nm7mar.urdf")
    print(checked.counts(), checked.would_change)
    ```
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
    """Fix the inertials of the description at `path`; nothing is written.

    The links whose inertial is wrong are recomputed from their geometry (or a slip in
    their values undone); the others are kept byte for byte.

    Parameters
    ----------
    path : str or Path
        A URDF, xacro, SDFormat, MJCF or USD file.
    **options
        The options below (the command line's, with its defaults).

    Other Parameters
    ----------------
    geometry : {"auto", "collision", "visual"}
        Which of a link's geometry to use (`--geometry`, default "auto": per link, the set
        that best represents the body).
    mass : {"keep", "density"}
        "keep" keeps a link's positive mass and derives CoM and tensor; "density" derives
        the mass too, density x volume (`--mass`).
    density : float
        kg/m^3 for links without mass or with `mass="density"` (`--density`, 1000).
    package_dirs : mapping of str to path
        Where `package://NAME/` and `$(find NAME)` point: `{"NAME": "FOLDER"}`
        (`--package-dir NAME=FOLDER`). A relative folder is taken from the working
        directory.
    xacro_args : mapping of str to str
        Arguments of a xacro input: `{"NAME": "VALUE"}` (`--xacro-arg NAME:=VALUE`).
    max_faces : int
        Refuse larger meshes before reading them (`--max-faces`, 1,000,000).
    spec : str, path or Spec
        A decomposition spec (`--spec`): a TOML path or a spec from
        [load_spec][urdfinertia.body.spec.load_spec].
    strict : bool
        All or nothing (`--strict`): an element dropped or a link left as it was raises.
    keep_auto : bool
        SDFormat: leave `<inertial auto="true">` to the simulator (`--keep-auto`).
    recompute : {"needed", "all", "links"}
        Which links are recomputed: the wrong ones (default), every link with geometry
        (`--all`), or those named in `links` (`--links`).
    links : sequence of str
        The links to recompute; implies `recompute="links"`.
    slips : bool
        Undo a clear one-edit slip of a written value rather than derive it (default
        True; `--no-slips` is `slips=False`).
    total_mass : float
        kg the robot weighs: derived masses are scaled to meet it (`--total-mass`).
    scale_kept : bool
        With `total_mass`, scale the kept masses too (`--scale-kept`).

    Returns
    -------
    FixResult
        `links` (one [LinkResult][urdfinertia.plan.results.LinkResult] per link: status,
        action, values before and after, error bar), `changed`, `recomputed`,
        `changed_links`, `output` (the patched document) and `targets` (total mass
        before, target and after); `result.save(path)` writes what `fix -o` writes.

    Raises
    ------
    UrdfInertiaError
        When the file cannot be read at all, or with `strict=True` when a link is left as
        it was.
    TypeError
        On an unknown option (the message lists them).

    Examples
    --------
    ```python
    result = urdfinertia.fix("robots/nm7mar.urdf", spec="robots/nm7mar.inertia.toml")
    result.save("nm7mar.fixed.urdf")
    ```
    """
    from urdfinertia.plan.fix import fix_file

    return fix_file(path, make_options(**options))


@_xacro_options
def compare(path: str | Path, against: str | Path | None = None, *,
            tol_com: float | None = None, tol_inertia: float | None = None,
            tol_mass: float | None = None, **options: Any) -> list[LinkComparison]:
    """The written inertials of `path` against its geometry, or against another file's.

    Parameters
    ----------
    path : str or Path
        The description whose inertials are side A.
    against : str or Path, optional
        A second description: side B is its inertials (`--against`). By default side B is
        computed from the geometry of `path`, with `fix`'s decision for each link.
    tol_com : float, optional
        CoM distance / link size above which a link differs (`--tol-com`, 0.05).
    tol_inertia : float, optional
        Relative tensor error above which a link differs (`--tol-inertia`, 0.1).
    tol_mass : float, optional
        |mass ratio - 1| above which a link differs (`--tol-mass`, 0.05).
    **options
        The options of [fix][urdfinertia.api.fix], used to compute side B from the
        geometry (ignored with `against`).

    Returns
    -------
    list of LinkComparison
        One per link: both sides' mass properties, the mass ratio, CoM distance (absolute
        and relative to the link's size), tensor error, principal-axis angle and a verdict
        ("ok", "differs", "kept", "invalid", "missing").
    """
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
    """One link of `path`: what `fix` writes, and its geometry element by element.

    Parameters
    ----------
    path : str or Path
        The description.
    link : str
        The link's name (`--link`).
    **options
        The options of [fix][urdfinertia.api.fix].

    Returns
    -------
    Breakdown
        The link's total (what `fix` writes), its principal moments and axes, and each
        element's and part's contribution.

    Raises
    ------
    UrdfInertiaError
        When the file cannot be read or has no link of that name.
    """
    from urdfinertia.analysis.explain import explain_link
    from urdfinertia.descriptions.formats import read_description

    robot, _ = read_description(path)
    return explain_link(robot, link, make_options(**options))


@dataclass(frozen=True, eq=False)
class Report:
    """The HTML report of one description (what [report][urdfinertia.api.report] returns).

    Attributes
    ----------
    html : str
        One self-contained page: it loads nothing from the network.
    data : ReportData
        What the page shows: every link's verdict, values before and after, the 3-D scene.
    """

    html: str
    data: ReportData

    def save(self, path: str | Path) -> Path:
        """Write the page to `path` atomically (a reader never sees half a file).

        Parameters
        ----------
        path : str or Path
            Where to write the page.

        Returns
        -------
        Path
            `path`.
        """
        from urdfinertia.atomic import atomic_write_bytes

        atomic_write_bytes(Path(path), self.html.encode("utf-8"))
        return Path(path)


@_xacro_options
def report(path: str | Path, *, view: str = "visual", face_budget: int | None = None,
           **options: Any) -> Report:
    """The HTML report of `path`: a 3-D view with the inertia boxes before and after, and
    every link's verdict.

    Parameters
    ----------
    path : str or Path
        The description.
    view : {"visual", "collision"}
        The geometry drawn in the 3-D view (`--view`).
    face_budget : int, optional
        Faces the 3-D view's meshes share, decimated to fit (`--view-faces`, 100,000).
    **options
        The options of [fix][urdfinertia.api.fix].

    Returns
    -------
    Report
        `html` and `data`; `report.save("robot.html")` writes the page.
    """
    from urdfinertia.render.report import collect, render_html
    from urdfinertia.render.scene import DEFAULT_VIEW_FACES

    data = collect(path, make_options(**options), view=view,
                   face_budget=DEFAULT_VIEW_FACES if face_budget is None else face_budget)
    return Report(render_html(data), data)
