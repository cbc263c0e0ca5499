"""``urdf-inertia`` command line: parses arguments and dispatches to a subcommand module.

Each subcommand lives in ``cli/<name>.py`` with ``add_arguments(parser)`` and
``run(args) -> int``.

Exit codes: 0 success; 1 a command's findings (``check`` found problems); 2 a user-facing
failure: any :class:`UrdfInertiaError`, a bad command line, running out of memory, an
output pipe closed early, one line on stderr; 3 an internal error (a bug: any other
exception), also one line, naming the exception type and pointing at ``--debug``;
130 interrupted. ``--debug`` adds the traceback before the line.
"""

from __future__ import annotations

import argparse
import importlib
import importlib.util
import sys
import traceback
import warnings
from collections.abc import Sequence
from typing import Any, NoReturn

from urdfinertia import __version__
from urdfinertia.errors import EXTRA_OF, MissingExtraError, UrdfInertiaError

#: name -> one-line help; each is implemented in ``urdfinertia.cli.<name>``.
COMMANDS = {
    "fix": "recompute <inertial> tags from the links' geometry",
    "check": "lint the inertials as written (exit 1 when problems are found)",
    "compare": "compare inertials with the geometry or with another URDF",
    "explain": "per-element and per-part breakdown of one link (paper section 5)",
    "report": "self-contained HTML report with a 3-D view",
}


def _available(load: Sequence[str] | None = None) -> dict[str, object | None]:
    """Subcommand modules that exist, by name; only those in ``load`` (default: all) are
    imported, the others are None (each pulls in what its command computes with)."""
    mods: dict[str, object | None] = {}
    for name in COMMANDS:
        module = f"urdfinertia.cli.{name}"
        if load is not None and name not in load:
            if importlib.util.find_spec(module) is not None:
                mods[name] = None
            continue
        try:
            mods[name] = importlib.import_module(module)
        except ModuleNotFoundError as exc:
            if exc.name != module:
                raise
    return mods


def _command_in(argv: Sequence[str]) -> str | None:
    """The subcommand ``argv`` names: its first word that is not an option (the main
    parser's own options take no value)."""
    for arg in argv:
        if arg == "--":
            return None
        if not arg.startswith("-"):
            return arg if arg in COMMANDS else None
    return None


def build_parser(argv: Sequence[str] | None = None,
                 ) -> tuple[argparse.ArgumentParser, dict[str, object | None]]:
    """The parser; given ``argv``, only the subcommand it names gets its full arguments
    (the others keep their one-line help), so one command does not import all."""
    parser = OneLineArgumentParser(
        prog=PROG,
        description="Make the <inertial> tags of URDF robot descriptions right.",
    )
    parser.add_argument("--version", action="version", version=f"urdf-inertia {__version__}")
    parser.add_argument("--debug", action="store_true", help="show tracebacks on errors")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    if argv is None:
        mods = _available()
    else:
        command = _command_in(argv)
        mods = _available([command] if command is not None else [])
    for name, mod in mods.items():
        p = sub.add_parser(name, help=COMMANDS[name], description=COMMANDS[name])
        if mod is None:
            continue
        p.add_argument("--debug", action="store_true", default=argparse.SUPPRESS,
                       help="show tracebacks on errors")
        mod.add_arguments(p)  # type: ignore[attr-defined]
    return parser, mods


#: Exit code of a user-facing failure (bad input, options or environment).
EXIT_ERROR = 2
#: Exit code of an internal error: an exception this package did not expect (a bug).
EXIT_INTERNAL = 3


PROG = "urdf-inertia"


class OneLineArgumentParser(argparse.ArgumentParser):
    """argparse, but a usage error is one line (``--help`` still shows the usage), names
    the subcommand once, and suggests the nearest option for a misspelled one."""

    def error(self, message: str) -> NoReturn:
        command = self.prog.removeprefix(PROG).strip()
        where = f"{command}: " if command else ""
        self.exit(EXIT_ERROR, f"{PROG}: error: {where}{message} (see --help)\n")

    def parse_args(self, args=None, namespace=None):  # noqa: ANN001, ANN201 - argparse's
        parsed, extras = self.parse_known_args(args, namespace)
        if extras:
            parser = self._chosen(parsed)
            hints = [hint for hint in map(parser.suggestion, extras) if hint]
            more = f" ({'; '.join(hints)})" if hints else ""
            parser.error(f"unrecognized arguments: {' '.join(extras)}{more}")
        return parsed

    def _chosen(self, parsed: argparse.Namespace) -> OneLineArgumentParser:
        """The subcommand's parser (where a misplaced option belongs), else this one."""
        for action in self._actions:
            if isinstance(action, argparse._SubParsersAction):
                found = action.choices.get(getattr(parsed, action.dest, None) or "")
                if isinstance(found, OneLineArgumentParser):
                    return found
        return self

    def suggestion(self, arg: str) -> str | None:
        """"did you mean --output?" for an unknown option close to a known one."""
        import difflib

        if not arg.startswith("-"):
            return None
        known = [o for a in self._actions for o in a.option_strings if o.startswith("--")]
        close = difflib.get_close_matches(arg.split("=", 1)[0], known, n=1, cutoff=0.6)
        return f"did you mean {close[0]}?" if close else None


def main(argv: Sequence[str] | None = None) -> int:
    argv = sys.argv[1:] if argv is None else list(argv)
    parser, mods = build_parser(argv)
    args = parser.parse_args(argv)
    if not args.command:
        parser.print_help(sys.stderr)
        return EXIT_ERROR
    if mods.get(args.command) is None:  # named where _command_in does not look: all of them
        parser, mods = build_parser()
        args = parser.parse_args(argv)
    if args.debug:  # what libraries printed while reading (urdfinertia.quiet), and more
        _debug_log()
    try:
        from urdfinertia.cli.options import configure_descriptions

        configure_descriptions(args)
        with warnings.catch_warnings():
            if not args.debug:
                # numpy's overflow/invalid-value warnings would add lines to stderr; the
                # results they concern are checked (finite, physical) where they are made
                warnings.simplefilter("ignore", RuntimeWarning)
            command: Any = mods[args.command]
            return int(command.run(args))
    except UrdfInertiaError as exc:
        return _fail(args, f"error: {_one_line(str(exc))}", EXIT_ERROR)
    except MemoryError:
        # meshes' own exhaustion is their error (named); this is anything else's
        return _fail(args, "error: out of memory (nothing was written; --debug shows where)",
                     EXIT_ERROR)
    except BrokenPipeError:
        _silence_stdout()
        return _fail(args, "error: output pipe closed before the output was written",
                     EXIT_ERROR)
    except KeyboardInterrupt:
        print("urdf-inertia: interrupted", file=sys.stderr)
        return 130
    except ImportError as exc:
        extra = missing_extra(args, exc)
        if extra is not None:  # an optional dependency the command reached for
            return _fail(args, f"error: {extra}", EXIT_ERROR)
        return _fail(args, f"internal error: {type(exc).__name__}: {_one_line(str(exc))} "
                     "(this is a bug; rerun with --debug for the traceback)", EXIT_INTERNAL)
    except Exception as exc:  # any other exception is a bug: say so in one line
        return _fail(args, f"internal error: {type(exc).__name__}: {_one_line(str(exc))} "
                     "(this is a bug; rerun with --debug for the traceback)", EXIT_INTERNAL)


def missing_extra(args: argparse.Namespace, exc: ImportError) -> MissingExtraError | None:
    """``exc`` as the one line naming the extra to install, when the module it misses is
    an optional dependency (``EXTRA_OF``), else None. The features that need an extra
    check for it up front (``report``); this catches the others (``--plot``)."""
    module = (getattr(exc, "name", None) or "").partition(".")[0]
    if module not in EXTRA_OF:
        return None
    what = args.command + (" --plot" if getattr(args, "plot", None) else "")
    return MissingExtraError(what, EXTRA_OF[module], module)
def _debug_log() -> None:
    import logging

    handler = logging.StreamHandler(sys.stderr)
    handler.setFormatter(logging.Formatter(f"{PROG}: debug: %(message)s"))
    logger = logging.getLogger("urdfinertia")
    logger.addHandler(handler)
    logger.setLevel(logging.DEBUG)


def _fail(args: argparse.Namespace, message: str, code: int) -> int:
    if getattr(args, "debug", False):
        traceback.print_exc()
    print(f"urdf-inertia: {message}", file=sys.stderr)
    return code


def _one_line(text: str) -> str:
    """Messages may quote user data: newlines would break the one-line contract."""
    return " ".join(text.split()) if ("\n" in text or "\r" in text) else text


def _silence_stdout() -> None:
    """After EPIPE, point stdout at /dev/null so the interpreter's final flush is quiet."""
    import os

    try:
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
    except (OSError, ValueError):
        pass
