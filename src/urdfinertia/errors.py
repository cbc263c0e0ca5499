"""The exception hierarchy. The CLI turns any of these into one line and exit code 2.

Every exception carries the [`Rule`][urdfinertia.rules.Rule] of its problem: the class
gives a default and the raiser may name a finer one (`MeshError(cause,
rule=Rule.MESH_NO_VOLUME)`). Where one bad element does not sink the robot, the error
becomes a [`Finding`][urdfinertia.findings.Finding] of that rule; reports read the rule,
never the message's words.
"""

from __future__ import annotations

from pathlib import Path

from urdfinertia.rules import Rule


class UrdfInertiaError(Exception):
    """A problem with the user's input or environment, reported without a traceback.

    The message names the file, and where known its line, the link and the cause.

    Attributes
    ----------
    cause : str
        What is wrong, without the location.
    rule : Rule
        The rule of the problem (the class's `default_rule` unless the raiser named
        another).
    file, line, link : str, int, str or None
        Where, as far as known.
    """

    default_rule = Rule.DESCRIPTION_UNREADABLE
    """The rule of the class's problems, when the raiser names none."""

    def __init__(
        self,
        cause: str,
        *,
        file: str | Path | None = None,
        line: int | None = None,
        link: str | None = None,
        rule: Rule | str | None = None,
    ) -> None:
        super().__init__(cause)
        self.cause = cause
        self.rule = Rule(rule) if rule is not None else self.default_rule
        self.file = str(file) if file is not None else None
        self.line = line
        self.link = link

    @property
    def code(self) -> str:
        """The rule's code ("mesh-no-volume")."""
        return self.rule.value

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

    default_rule = Rule.DESCRIPTION_UNREADABLE


class MeshError(UrdfInertiaError):
    """A referenced mesh is missing, unreadable, unsupported or unusable.

    Rules: `MESH_UNRESOLVED` (no such file, or a `package://` or
    `model://` that names no known folder), `MESH_REFUSED` (a remote or
    non-file URI), `MESH_TOO_LARGE` (over the size, face or time limit),
    `MESH_NO_VOLUME` (encloses no volume), `MESH_ABSURD` (a unit
    or coordinates no mesh has), `GEOMETRY_UNREADABLE` (anything else).
    """

    default_rule = Rule.GEOMETRY_UNREADABLE

    def __init__(self, cause: str, *, file: str | Path | None = None,
                 line: int | None = None, link: str | None = None,
                 rule: Rule | str | None = None, of_bytes: bool = False) -> None:
        super().__init__(cause, file=file, line=line, link=link, rule=rule)
        #: True when the file's bytes alone caused it (corrupt, empty, over a limit), not
        #: the machine (permissions, memory): a file's result may then be reused while the
        #: mesh at the same place has the same bytes, though the message names the path
        self.of_bytes = of_bytes


class SpecError(UrdfInertiaError):
    """The decomposition spec is invalid."""

    default_rule = Rule.SPEC_INVALID


class OutputError(UrdfInertiaError):
    """An output cannot be written."""

    default_rule = Rule.OUTPUT_FAILED


class MissingExtraError(UrdfInertiaError, ImportError):
    """A feature needs an optional dependency that is not installed.

    Also an `ImportError`, so `except ImportError` catches it. The message is one
    line with the install command: "the report needs the report extra: pip install
    'urdfinertia[report]'".

    Attributes
    ----------
    extra : str
        The extra that installs it (`pip install 'urdfinertia[EXTRA]'`).
    name : str
        The module that could not be imported (as `ImportError` names it).
    """

    default_rule = Rule.MISSING_EXTRA

    def __init__(self, what: str, extra: str, module: str) -> None:
        super().__init__(f"{what} needs the {extra} extra: "
                         f"pip install 'urdfinertia[{extra}]'")
        self.extra = extra
        self.name = module

    def __str__(self) -> str:
        return self.cause


#: Optional modules and the extra that installs each (pyproject.toml's
#: ``[project.optional-dependencies]``).
EXTRA_OF = {"plotly": "report", "matplotlib": "report", "fast_simplification": "report",
            "igl": "fast"}


def require_extra(modules: tuple[str, ...], what: str) -> None:
    """Raise [`MissingExtraError`][urdfinertia.errors.MissingExtraError] unless every module in
    `modules` is importable.

    Only looks the modules up (`importlib.util.find_spec`), so a present extra costs no
    import here; `what` names the feature ("the report", "compare --plot").
    """
    import importlib.util

    for module in modules:
        try:
            found = importlib.util.find_spec(module) is not None
        except (ImportError, ValueError):
            found = False
        if not found:
            raise MissingExtraError(what, EXTRA_OF.get(module, module), module)
