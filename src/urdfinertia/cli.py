"""``urdf-inertia`` command line: parses arguments and dispatches to a subcommand module.

Each subcommand lives in ``cli_<name>.py`` with ``add_arguments(parser)`` and
``run(args) -> int``. Any :class:`UrdfInertiaError` becomes one line on stderr and exit
code 2 (``--debug`` shows the traceback).
"""

from __future__ import annotations

import argparse
import importlib
import sys
import traceback
from collections.abc import Sequence

from . import __version__
from .errors import UrdfInertiaError

#: name -> one-line help; each is implemented in ``urdfinertia.cli_<name>``.
COMMANDS = {
    "fix": "recompute <inertial> tags from the links' geometry",
    "check": "lint the inertials as written (exit 1 when problems are found)",
    "compare": "compare inertials with the geometry or with another URDF",
    "explain": "per-element and per-part breakdown of one link (paper section 5)",
    "report": "self-contained HTML report with a 3-D view",
}


def _available() -> dict[str, object]:
    mods = {}
    for name in COMMANDS:
        try:
            mods[name] = importlib.import_module(f"urdfinertia.cli_{name}")
        except ModuleNotFoundError as exc:
            if exc.name != f"urdfinertia.cli_{name}":
                raise
    return mods


def build_parser() -> tuple[argparse.ArgumentParser, dict[str, object]]:
    parser = argparse.ArgumentParser(
        prog="urdf-inertia",
        description="Make the <inertial> tags of URDF robot descriptions right.",
    )
    parser.add_argument("--version", action="version", version=f"urdf-inertia {__version__}")
    parser.add_argument("--debug", action="store_true", help="show tracebacks on errors")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    mods = _available()
    for name, mod in mods.items():
        p = sub.add_parser(name, help=COMMANDS[name], description=COMMANDS[name])
        p.add_argument("--debug", action="store_true", default=argparse.SUPPRESS,
                       help="show tracebacks on errors")
        mod.add_arguments(p)  # type: ignore[attr-defined]
    return parser, mods


def main(argv: Sequence[str] | None = None) -> int:
    parser, mods = build_parser()
    args = parser.parse_args(argv)
    if not args.command:
        parser.print_help(sys.stderr)
        return 2
    try:
        return int(mods[args.command].run(args))  # type: ignore[attr-defined]
    except UrdfInertiaError as exc:
        if args.debug:
            traceback.print_exc()
        print(f"urdf-inertia: error: {exc}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("urdf-inertia: interrupted", file=sys.stderr)
        return 130


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
