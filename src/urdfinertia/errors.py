"""The exception hierarchy. The CLI turns any of these into one line and exit code 2.

Every exception carries a short `code` naming its category ("mesh-missing",
"mesh-too-large", ...): the class gives a default and the raiser may name a finer one
(`MeshError(cause, code="no-volume")`). Reports and problem lists read the attribute,
never the message's words.
"""

from __future__ import annotations

from pathlib import Path


class UrdfInertiaError(Exception):
    """A problem with the user's input or environment, reported without a traceback.

    The message names the file, and where known its line, the link and the cause.

    Attributes
    ----------
    cause : str
        What is wrong, without the location.
    code : str
        The category of the problem (the class's `default_code` unless the raiser
        named another), as reports and the JSON output name it.
    file, line, link : str, int, str or None
        Where, as far as known.
    """

    default_code = "error"
    """Category of the class's problems, when the raiser names none."""

    def __init__(
        self,
        cause: str,
        *,
        file: str | Path | None = None,
        line: int | None = None,
        link: str | None = None,
        code: str | None = None,
    ) -> None:
        super().__init__(cause)
        self.cause = cause
        self.code = code if code is not None else self.default_code
        self.file = str(file) if file is not None else None
        self.line = line
        self.link = link

    def with_context(
        self, *, file: str | Path | None = None, line: int | None = None, link: str | None = None
    ) -> UrdfInertiaError:
        """Fill in context the raiser did not know (never overwrites what is set).

        Parameters
        ----------
        file : str or Path, optional
            The file the error is about.
        line : int, optional
            Its line.
        link : str, optional
            The link it is about.

        Returns
        -------
        UrdfInertiaError
            This error, for `raise exc.with_context(...)`.
        """
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
    """The description cannot be read or holds invalid values."""

    default_code = "bad-description"


class MeshError(UrdfInertiaError):
    """A referenced mesh is missing, unreadable, unsupported or unusable.

    Codes: "mesh-missing" (no such file), "mesh-unresolved" (a `package://` or
    `model://` that names no known folder), "mesh-url" (a remote or non-file URI),
    "mesh-format" (a format no reader takes), "mesh-too-large" (over the size or face
    limit), "no-volume" (encloses no volume), "mesh-unreadable" (anything else).
    """

    default_code = "mesh-unreadable"

    def __init__(self, cause: str, *, file: str | Path | None = None,
                 line: int | None = None, link: str | None = None,
                 code: str | None = None, of_bytes: bool = False) -> None:
        super().__init__(cause, file=file, line=line, link=link, code=code)
        #: True when the file's bytes alone caused it (corrupt, empty, over a limit), not
        #: the machine (permissions, memory): a file's result may then be reused while the
        #: mesh at the same place has the same bytes, though the message names the path
        self.of_bytes = of_bytes


class SpecError(UrdfInertiaError):
    """The decomposition spec is invalid."""

    default_code = "bad-spec"


class OutputError(UrdfInertiaError):
    """An output cannot be written."""

    default_code = "output"
