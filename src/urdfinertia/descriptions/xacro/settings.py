"""The arguments and package folders every xacro expansion uses, set for a whole run.

Kept apart from `.expand` (which imports the `xacro` package, `xml.dom` and lxml)
so that a command can set them without loading xacro support: a run whose every file
comes from the cache, or that has no xacro input, never expands anything.
"""

from __future__ import annotations

import contextlib
from collections.abc import Iterator, Mapping
from dataclasses import dataclass
from pathlib import Path


@dataclass(frozen=True)
class XacroSettings:
    """`--xacro-arg NAME:=VALUE` and `--package-dir NAME=PATH` for every expansion."""

    args: tuple[tuple[str, str], ...] = ()
    package_dirs: tuple[tuple[str, str], ...] = ()


_settings = XacroSettings()


def configure(args: Mapping[str, str] | None = None,
              package_dirs: Mapping[str, str | Path] | None = None) -> None:
    """Set the arguments and package folders used by every later expansion (the CLI).

    A relative package folder is made absolute here, from the working directory: xacro
    joins a relative ``$(find PKG)`` to the including file's folder.
    """
    global _settings
    _settings = XacroSettings(
        tuple(sorted((args or {}).items())),
        tuple(sorted((k, absolute_folder(v)) for k, v in (package_dirs or {}).items())))


def absolute_folder(path: str | Path) -> str:
    """``path`` absolute from the working directory (``~`` expanded), not normalised:
    ``..`` after a symbolic link keeps its meaning."""
    return str(Path(path).expanduser().absolute())


def current_settings() -> XacroSettings:
    """The xacro arguments and package folders expansions use now.

    Returns
    -------
    XacroSettings
        Set by `configure` or, for one call, `settings_for`.
    """
    return _settings


@contextlib.contextmanager
def settings_for(args: Mapping[str, str] | None = None,
                 package_dirs: Mapping[str, str | Path] | None = None,
                 ) -> Iterator[XacroSettings]:
    """Expansions inside the `with` block use `args` and `package_dirs`; the settings
    before it are restored after (the library's per-call xacro options)."""
    global _settings
    before = _settings
    configure(args, package_dirs)
    try:
        yield _settings
    finally:
        _settings = before
