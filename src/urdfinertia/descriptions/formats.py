"""Description formats as siblings behind one robot model (meshio's `register_format`).

Each format (URDF, xacro, SDFormat, MJCF, USD) lives in its own subpackage of
`urdfinertia.descriptions` and registers a `DescriptionFormat`: how to read a document's bytes
into the shared [`Robot`][urdfinertia.descriptions.model.Robot] (once, leniently: every value as
written, with findings for what was read past) and how to splice new inertials into the same
bytes. Everything above this layer calls
[`read_description`][urdfinertia.descriptions.formats.read_description] and `format_of`, and never
imports a format by name. A format converts its own conventions (SDF poses, MJCF half sizes and
quaternions) to the model's at the edge: SI units, inertia about the CoM along the inertial origin's
axes, URDF's sign convention for products of inertia.
"""

from __future__ import annotations

import importlib
import re
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

from urdfinertia.errors import UrdfError

if TYPE_CHECKING:
    from urdfinertia.descriptions.model import Robot
    from urdfinertia.inertia.massprops import MassProperties

VALUES = frozenset({"mass", "com", "tensor"})
"""The values of an inertial: what a writer is told was derived (the others were kept)."""


@dataclass(frozen=True)
class NewInertial:
    """A link's inertial as `DescriptionFormat.patch` is to write it.

    Attributes
    ----------
    props : MassProperties
        The mass properties in the link frame.
    size : float
        The link's length scale, m, below which round-off is written as 0.
    derived : frozenset of str
        Which of "mass", "com" and "tensor" were derived; the others were kept as written,
        and a writer leaves their text byte for byte where the document allows.
    """

    props: MassProperties
    size: float
    derived: frozenset[str] = VALUES

    @property
    def partial(self) -> bool:
        """Some value was kept: only the derived ones are to be written."""
        return self.derived != VALUES


NewInertials = Mapping[str, "NewInertial | tuple[MassProperties, float]"]
"""New inertials for `DescriptionFormat.patch`: link name -> a `NewInertial`, or (mass
properties, size) for one whose every value was derived.
"""


def new_inertial(value: NewInertial | tuple[MassProperties, float]) -> NewInertial:
    """`value` as a `NewInertial`.

    Parameters
    ----------
    value : NewInertial or (MassProperties, float)
        A new inertial, or a pair (mass properties, size): every value derived.

    Returns
    -------
    NewInertial
        The new inertial.
    """
    if isinstance(value, NewInertial):
        return value
    props, size = value
    return NewInertial(props, size)


@dataclass(frozen=True)
class DescriptionFormat:
    """One description format: how to read it and how to write inertials back into it.

    Attributes
    ----------
    name : str
        A short name, also `Robot.format` of what it reads ("urdf", "sdf", ...).
    roots : tuple of str
        The root element names that identify the format (`robot`, `sdf`, `mujoco`).
    suffixes : tuple of str
        File suffixes, lower case, used when the root element does not decide.
    read : callable (bytes, path) -> Robot
        Reads once, leniently: every value as written, with the reader's findings (what it
        read past) in `Robot.findings`.
    patch : callable (bytes, new inertials) -> bytes
        Changes nothing but the inertial elements, and of an inertial with kept values only
        the derived values' text (`NewInertial`).
    claims : callable (bytes, path) -> bool, optional
        Decides a file whose root element is shared with another format (xacro's `<robot>`).
    expand : callable (bytes, path) -> bytes, optional
        For a file that generates another format's document (xacro -> URDF): the document
        that `read` reads and `patch` edits.
    relocate : callable (bytes, source folder, output folder) -> (bytes, int), optional
        Relative references (meshes, textures, included files, asset folders) made to
        resolve from the output's folder, and how many were rewritten; None: nothing to do.
    default_output : callable (path) -> path, optional
        Where `fix` writes when given neither `-o` nor `--in-place` (USD: the override layer
        `robot.inertia.usda` beside the asset); None: standard output.
    """

    name: str
    roots: tuple[str, ...]
    suffixes: tuple[str, ...]
    read: Callable[[bytes, Path], Robot]
    patch: Callable[[bytes, NewInertials], bytes]
    claims: Callable[[bytes, Path], bool] | None = None
    expand: Callable[[bytes, Path], bytes] | None = None
    relocate: Callable[[bytes, Path, Path], tuple[bytes, int]] | None = None
    default_output: Callable[[Path], Path] | None = None
    write_in_place: Callable[[Path, bytes], None] | None = None
    """(path, output bytes) -> None: `--in-place` for a format whose output is not the input's new
    bytes (USD: the override's opinions authored into the root layer)
    """


_FORMATS: dict[str, DescriptionFormat] = {}
_BUILTIN = ("urdfinertia.descriptions.urdf", "urdfinertia.descriptions.xacro",
            "urdfinertia.descriptions.mjcf", "urdfinertia.descriptions.sdf",
            "urdfinertia.descriptions.usd")
"""Modules that register the built-in formats when first imported."""
_SNIFF_BYTES = 1 << 16
"""Bytes searched for the root element (comments and a DOCTYPE may come first)."""
_PROLOG = re.compile(rb"\A(?:\xef\xbb\xbf)?(?:\s+|<\?.*?\?>|<!--.*?-->|<![^>]*>)*", re.S)
_ROOT = re.compile(rb"<([A-Za-z_][\w.\-]*:)?([A-Za-z_][\w.\-]*)")


def register_format(fmt: DescriptionFormat) -> None:
    """Add `fmt`; a later registration of the same name replaces the earlier one.

    Parameters
    ----------
    fmt : DescriptionFormat
        The format.
    """
    _FORMATS[fmt.name] = fmt


def registered_formats() -> tuple[DescriptionFormat, ...]:
    """Every registered format, the built-in ones loaded first.

    Returns
    -------
    tuple of DescriptionFormat
        In registration order.
    """
    _load_builtin()
    return tuple(_FORMATS.values())


def _load_builtin() -> None:
    for module in _BUILTIN:
        importlib.import_module(module)


def format_of(robot: Robot) -> DescriptionFormat:
    """The format that read `robot` (and so writes its inertials).

    Parameters
    ----------
    robot : Robot
        A robot model read by a registered format.

    Returns
    -------
    DescriptionFormat
        Its format.
    """
    _load_builtin()
    return _FORMATS[robot.format]


def root_name(data: bytes) -> str | None:
    """The local name of the document's root element, without parsing the document.

    Parameters
    ----------
    data : bytes
        The document (its first bytes are enough).

    Returns
    -------
    str or None
        "robot", "sdf", "mujoco" ...; None when no element starts the document.
    """
    head = data[:_SNIFF_BYTES]
    prolog = _PROLOG.match(head)
    found = _ROOT.match(head, prolog.end() if prolog else 0)
    return found.group(2).decode("ascii") if found else None


def detect_format(data: bytes, path: Path) -> DescriptionFormat:
    """The registered format of a document: by its root element, then its suffix.

    Parameters
    ----------
    data : bytes
        The document.
    path : Path
        Its file name (for the suffix).

    Returns
    -------
    DescriptionFormat
        The format; URDF when nothing decides (its reader names what is wrong).
    """
    _load_builtin()
    root = root_name(data)
    by_root = [f for f in _FORMATS.values() if root in f.roots]
    claimed = [f for f in by_root if f.claims is not None and f.claims(data, path)]
    if claimed:
        return claimed[0]
    unclaimed = [f for f in by_root if f.claims is None]
    if unclaimed:
        return unclaimed[0]
    suffix = path.suffix.lower()
    for fmt in _FORMATS.values():
        if suffix in fmt.suffixes:
            return fmt
    return _FORMATS["urdf"]  # its reader names what is wrong with the document


def relocate_references(data: bytes, path: Path, output: Path) -> tuple[bytes, int]:
    """`data` (a document read from `path`) made to work when written at `output`.

    Parameters
    ----------
    data : bytes
        The document.
    path : Path
        Where it was read from.
    output : Path
        Where it is to be written.

    Returns
    -------
    (bytes, int)
        The document with its format's relative references rewritten (URDF meshes; MJCF
        compiler folders and includes; SDFormat URIs), and how many were.
    """
    fmt = detect_format(data, path)
    if fmt.relocate is None:
        return data, 0
    return fmt.relocate(data, path.parent, output.parent)


def read_bytes(path: str | Path) -> bytes:
    """A description's bytes, at most one past the size limit.

    Parameters
    ----------
    path : str or Path
        The file.

    Returns
    -------
    bytes
        Its contents (one byte more than the limit tells that it is exceeded).

    Raises
    ------
    UrdfError
        When the file cannot be read.
    """
    from urdfinertia.descriptions import xml

    path = Path(path)
    try:
        with path.open("rb") as fh:  # one byte more than the limit tells it is exceeded
            return fh.read(xml.MAX_DOCUMENT_BYTES + 1)
    except OSError as exc:
        raise UrdfError(f"cannot read: {exc.strerror or exc}", file=path) from None


def robot_from_bytes(data: bytes, path: str | Path) -> Robot:
    """The robot model of a description's bytes, in whatever registered format it is.

    Parameters
    ----------
    data : bytes
        The document.
    path : str or Path
        Where it was read from (relative references resolve from its folder).

    Returns
    -------
    Robot
        The robot model.
    """
    path = Path(path)
    return detect_format(data, path).read(data, path)


def read_description(path: str | Path) -> tuple[Robot, bytes]:
    """Read a description file of any registered format: its robot model and its bytes.

    The format is told by the root element, then by the suffix (URDF, xacro, SDFormat,
    MJCF, USD). xacro input is expanded with the arguments and package folders of the
    current settings (`urdfinertia.fix(..., xacro_args=...)` sets them for a call).

    Parameters
    ----------
    path : str or Path
        The description file.

    Returns
    -------
    robot : Robot
        Links (inertials as written: NaN, negative and absurd values included, for the
        judgement), joints, and what was read past (`robot.findings`).
    data : bytes
        The document the robot was read from: for a generating format (xacro) the
        expansion, which `patch` edits.

    Raises
    ------
    UrdfError
        When the file cannot be read or is not a description at all (a problem inside
        one element is a finding in `robot.findings` instead).
    """
    data = read_bytes(path)
    fmt = detect_format(data, Path(path))
    robot = fmt.read(data, Path(path))
    return robot, (fmt.expand(data, Path(path)) if fmt.expand is not None else data)


def is_description(data: bytes, path: str | Path) -> bool:
    """Whether a registered format takes this file by both its suffix and its root element
    (by its suffix alone for a format without root elements: USD).

    For callers handed every `*.xml` (or `*.xacro`, `*.sdf`) of a repository, such as
    the pre-commit hook: a ROS `package.xml` or a launch file is not a description, and a
    format that is not registered yet is not read as URDF.

    Parameters
    ----------
    data : bytes
        The file's contents.
    path : str or Path
        Its name.

    Returns
    -------
    bool
        Whether it is a description some format reads.
    """
    _load_builtin()
    suffix = Path(path).suffix.lower()
    root = root_name(data)
    for fmt in _FORMATS.values():
        # a format that is not XML (USD: no root element) is taken by its suffix alone
        if suffix in fmt.suffixes and (root in fmt.roots or not fmt.roots):
            if fmt.claims is None or fmt.claims(data, Path(path)):
                return True
    return False
