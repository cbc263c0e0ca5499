"""Every option and argument type shared by more than one subcommand: one home each."""

from __future__ import annotations

import argparse
from pathlib import Path

from urdfinertia.body.options import GEOMETRY_MODES, MASS_MODES, FixOptions
from urdfinertia.mesh.limits import BYTES_PER_FACE, DEFAULT_MAX_FACES


def positive_int(text: str) -> int:
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"not an integer: {text!r}") from None
    if value < 1:
        raise argparse.ArgumentTypeError(f"must be at least 1: {text!r}")
    return value


def package_dir(text: str) -> tuple[str, Path]:
    """``NAME=PATH``, the folder absolute: a relative one is read from the working
    directory, never from the folder of the xacro file that asks for the package."""
    name, sep, path = text.partition("=")
    if not sep or not name or not path:
        raise argparse.ArgumentTypeError(f"expected NAME=PATH, got {text!r}")
    return name, user_path(path)


def user_path(text: str) -> Path:
    """A path typed on the command line, made absolute from the working directory now
    (``~`` expanded), so that nothing later joins it to another folder."""
    return Path(text).expanduser().absolute()


def xacro_arg(text: str) -> tuple[str, str]:
    name, sep, value = text.partition(":=")
    if not sep or not name.strip():
        raise argparse.ArgumentTypeError(f"expected NAME:=VALUE, got {text!r}")
    return name.strip(), value


#: Upper bound of --density, kg/m^3: the densest element (osmium) is 22,590; a larger value
#: is a unit slip (g/cm^3 read as kg/m^3 goes the other way, but 1e6+ is never a material).
MAX_DENSITY = 1e6


def density_value(text: str) -> float:
    value = positive_float(text)
    if value > MAX_DENSITY:
        raise argparse.ArgumentTypeError(f"{text} kg/m^3 is denser than any material "
                                         f"(limit {MAX_DENSITY:g})")
    return value


def positive_float(text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"not a number: {text!r}") from None
    if not (value > 0 and value != float("inf")):
        raise argparse.ArgumentTypeError(f"must be positive and finite: {text!r}")
    return value


def add_geometry_source_arguments(p: argparse.ArgumentParser) -> None:
    """Which geometry, where packages are, how large a mesh: every command reading meshes."""
    p.add_argument("--geometry", choices=GEOMETRY_MODES, default="auto",
                   help="geometry to use (default: auto): auto judges a written "
                        "inertial against the collision geometry when the link has any, "
                        "else the visual, and derives from the set that best represents "
                        "the body, per link")
    p.add_argument("--package-dir", type=package_dir, action="append", default=[],
                   metavar="NAME=PATH", help="where package://NAME/ points (repeatable)")
    p.add_argument("--xacro-arg", type=xacro_arg, action="append", default=[],
                   metavar="NAME:=VALUE", help="argument of a xacro input (repeatable)")
    p.add_argument("--max-faces", type=int, default=DEFAULT_MAX_FACES, metavar="N",
                   help=f"refuse meshes with more faces, or mesh files larger than "
                        f"{BYTES_PER_FACE} bytes per face plus 1 MiB, before reading them "
                        f"(default {DEFAULT_MAX_FACES})")


def add_common_geometry_arguments(p: argparse.ArgumentParser) -> None:
    """Options shared by every command that computes from geometry."""
    add_geometry_source_arguments(p)
    p.add_argument("--mass", choices=MASS_MODES, default="keep",
                   help="keep: keep a link's existing positive mass and take CoM and tensor "
                        "from the geometry; density: mass = density x volume (default: keep)")
    p.add_argument("--density", type=density_value, default=None, metavar="KG_PER_M3",
                   help="a constant density for links without mass or with --mass density "
                        "(kg/m^3; default: the mass prior's for each link without mass, "
                        "1000 with --mass density)")
    p.add_argument("--spec", type=user_path, metavar="TOML",
                   help="decomposition spec: parts with known mass, density or material")


def add_policy_arguments(p: argparse.ArgumentParser) -> None:
    """Which links ``fix`` recomputes (urdfinertia.plan.policy); default: the wrong ones."""
    which = p.add_mutually_exclusive_group()
    which.add_argument("--all", action="store_true", dest="recompute_all",
                       help="recompute every link that has geometry (by default only links "
                            "whose inertial is missing, invalid, a placeholder or implausible "
                            "are recomputed; the others are kept byte for byte)")
    which.add_argument("--links", nargs="+", metavar="NAME", default=None,
                       help="recompute exactly these links (links in --spec always are)")


def recompute_from_args(args: argparse.Namespace) -> tuple[str, tuple[str, ...]]:
    if getattr(args, "recompute_all", False):
        return "all", ()
    links = getattr(args, "links", None)
    if links:
        return "links", tuple(links)
    return "needed", ()


def options_from_args(args: argparse.Namespace) -> FixOptions:
    spec = None
    if getattr(args, "spec", None) is not None:
        from urdfinertia.body.spec import load_spec

        spec = load_spec(args.spec)
    return FixOptions(
        geometry=args.geometry,
        mass=args.mass,
        density=1000.0 if args.density is None else args.density,
        density_prior=args.density is None,
        package_dirs=dict(args.package_dir),
        max_faces=args.max_faces,
        spec=spec,
        strict=bool(getattr(args, "strict", False)),
        keep_auto=getattr(args, "keep_auto", False),
        recompute=recompute_from_args(args)[0],
        links=recompute_from_args(args)[1],
        slips=not getattr(args, "no_slips", False),
    )


def configure_descriptions(args: argparse.Namespace) -> None:
    """Settings that reading a description needs beyond its path: xacro's arguments and
    where ``$(find PKG)`` points (set for the whole run; commands without them reset).

    Only the settings are set: xacro support itself (the ``xacro`` package, ``xml.dom``,
    lxml) is imported by the first expansion, so a run without xacro input, or whose every
    file comes from the cache, never loads it.
    """
    from urdfinertia.descriptions.xacro.settings import configure

    configure(dict(getattr(args, "xacro_arg", None) or []),
              dict(getattr(args, "package_dir", None) or []))


def engine_list(text: str) -> tuple[str, ...]:
    from urdfinertia.engines.run import parse_engines

    try:
        return parse_engines(text)
    except ValueError as exc:
        raise argparse.ArgumentTypeError(str(exc)) from None


def add_engine_arguments(p: argparse.ArgumentParser) -> None:
    """``--engines``: load and step in simulators (check, and fix on its output)."""
    p.add_argument("--engines", type=engine_list, metavar="LIST",
                   help="also load the description in these engines (mujoco, pinocchio, "
                        "pybullet, or all) and step a passive run; an engine that is not "
                        "installed is a note (pip install 'urdfinertia[engines]')")
    p.add_argument("--engine-seconds", type=positive_float, default=2.0, metavar="S",
                   help="simulated seconds of the passive run (default 2)")
    p.add_argument("--engine-timeout", type=positive_float, default=120.0, metavar="S",
                   help="wall-clock seconds an engine may take per file before it counts "
                        "as hung (default 120)")


def engine_request(args: argparse.Namespace):
    """The :class:`~urdfinertia.engines.EngineCheck` the arguments ask for, or None."""
    if not getattr(args, "engines", None):
        return None
    from urdfinertia.engines.run import EngineCheck

    return EngineCheck(args.engines, seconds=args.engine_seconds,
                       timeout=args.engine_timeout)


#: How every option of every command is said in Python (``urdfinertia.check``, ``fix``,
#: ``compare``, ``explain``, ``report``): the keyword argument and its value, or what takes
#: the option's place. The API reference's command-line table is generated from the parser
#: and this table, and a test fails on an option of the parser that is missing here (or an
#: entry no parser has), so the two cannot drift. Keys are the option's long name; an
#: option that means something else in one command is keyed ``"command --option"``.
PYTHON_EQUIVALENTS: dict[str, str] = {
    # reading the description and its geometry
    "urdf": "`path` (the first argument; one file: loop over files in Python)",
    "more": "call `fix` once per file",
    "--geometry": '`geometry="auto"`, `"collision"` or `"visual"`',
    "--package-dir": '`package_dirs={"NAME": "PATH"}`',
    "--xacro-arg": '`xacro_args={"NAME": "VALUE"}`',
    "--max-faces": "`max_faces=N`",
    "--mass": '`mass="keep"` or `"density"`',
    "--density": "`density=KG_PER_M3` (a constant density: no mass prior)",
    "--spec": '`spec="robot.inertia.toml"` (a path, or a spec from `load_spec`)',
    # which links fix recomputes
    "--all": '`recompute="all"`',
    "--links": '`links=["NAME", ...]` (implies `recompute="links"`)',
    "--no-slips": "`slips=False`",
    "--keep-auto": "`keep_auto=True`",
    "--strict": "`strict=True` (`fix` raises instead of leaving a link as it was)",
    "--total-mass": "`total_mass=KG`",
    "--scale-kept": "`scale_kept=True`",
    "--repair-only": "`urdfinertia.plan.repair_only.repair_file(path)`",
    # what fix writes
    "--output": '`result.save("PATH")`',
    "--in-place": "`result.save(in_place=True)`",
    "--keep-mesh-paths": '`result.save("PATH", keep_mesh_paths=True)`',
    "--write-back": "`urdfinertia.write_back(result)`",
    "--write-back-report": '`urdfinertia.write_back(result, report="PATH")`',
    "--json": "the returned objects (`result.links`: one `LinkResult` per link)",
    "--quiet": "nothing is printed in Python",
    "--debug": "Python raises the exception itself",
    # check
    "check --strict": "`result.exit_code(strict=True)`",
    "--format": "the returned `CheckResult` (`findings`, `links`)",
    "--sarif": "command line only (`urdf-inertia check --sarif PATH`)",
    "--baseline": "command line only (`urdf-inertia check --baseline FILE`)",
    "--write-baseline": "command line only (`urdf-inertia check --write-baseline FILE`)",
    "--no-geometry": "`geometry=False` (`check` only)",
    "--show-info": "`result.findings` holds every finding, info included",
    "--skip-unknown-formats": "command line only (pre-commit passes every file)",
    "--includers": "command line only (a hook mode: an included xacro checked through the "
                   "robots that include it)",
    "--no-statics": "`statics=False`",
    "--effort-margin": "`effort_margin=FRACTION`",
    "--realizable": '`realizable="ellipsoid"` or `"hull"`',
    "--mass-tolerance": "`mass_tolerance=FRACTION`",
    "--engines": "command line only (`urdfinertia.engines.run.EngineCheck` in the library)",
    "--engine-seconds": "command line only, with `--engines`",
    "--engine-timeout": "command line only, with `--engines`",
    # compare
    "--against": '`against="OTHER.urdf"` (the second argument)',
    "--csv": "the returned list of `LinkComparison`",
    "--plot": "command line only (a PNG)",
    "--tol-com": "`tol_com=FRACTION`",
    "--tol-inertia": "`tol_inertia=FRACTION`",
    "--tol-mass": "`tol_mass=FRACTION`",
    "--fail-above": "compare the returned `LinkComparison` values yourself",
    "compare --all": "the returned list holds every link",
    # explain
    "--link": '`link="NAME"` (the second argument)',
    "explain --json": "the returned `Breakdown`",
    # report
    "--view": '`view="visual"` or `"collision"`',
    "--view-faces": "`face_budget=N`",
    "report --output": '`report.save("PATH")`',
    # many files at once: the batch runner of the command line
    "--jobs": "command line only: one file per call in Python, in this process",
    "--mesh-seconds": "command line only",
    "--no-cache": "command line only: Python calls use no cache",
    "--cache-dir": "command line only",
    "--cache-max-mb": "command line only",
    "--dask": "command line only",
    "--timings": "command line only",
}


def python_equivalent(command: str, option: str) -> str | None:
    """How ``option`` of ``command`` is said in Python (:data:`PYTHON_EQUIVALENTS`).

    Parameters
    ----------
    command : str
        The subcommand, as typed ("fix", "check", ...).
    option : str
        The option's long name ("--all") or a positional argument's name ("urdf").

    Returns
    -------
    str or None
        The Python keyword and value, or what takes the option's place; None when the
        table has no entry for it.
    """
    return PYTHON_EQUIVALENTS.get(f"{command} {option}", PYTHON_EQUIVALENTS.get(option))
