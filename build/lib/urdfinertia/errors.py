"""The exception hierarchy. The CLI turns any of these into one line and exit code 2."""

from __future__ import annotations

from pathlib import Path


class UrdfInertiaError(Exception):
    """A problem with the user's input or environment, reported without a traceback.

    The message names the file, and where known its line, the link and the cause.
    """

    def __init__(
        self,
        cause: str,
        *,
        file: str | Path | None = None,
        line: int | None = None,
        link: str | None = None,
    ) -> None:
        super().__init__(cause)
        self.cause = cause
        self.file = str(file) if file is not None else None
        self.line = line
        self.link = link

    def with_context(
        self, *, file: str | Path | None = None, line: int | None = None, link: str | None = None
    ) -> UrdfInertiaError:
        """Fill in context the raiser did not know (never overwrites what is set)."""
        if self.file is None and file is not None:
            self.file = str(file)
        if self.line is None and line is not None:
            self.line = line
        if self.link is None and link is not None:
            self.link = link
        return self

    def __str__(self) -> str:
        where = self.file or "<input>"
        if self.line is not None:
            where += f":{self.line}"
        link = f" link '{self.link}':" if self.link else ""
        return f"{where}:{link} {self.cause}"


class UrdfError(UrdfInertiaError):
    """The URDF cannot be read or holds invalid values."""


class MeshError(UrdfInertiaError):
    """A referenced mesh is missing, unreadable, unsupported or unusable."""


class SpecError(UrdfInertiaError):
    """The decomposition spec is invalid."""


class OutputError(UrdfInertiaError):
    """An output cannot be written."""
