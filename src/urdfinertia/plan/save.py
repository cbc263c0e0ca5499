"""Save a fixed description: the one path from a
[`FixResult`][urdfinertia.plan.results.FixResult] to a file on disk.

`urdf-inertia fix -o` / `--in-place` and
[`FixResult.save`][urdfinertia.plan.results.FixResult.save] both come here, so the library
writes the same bytes as the command line: the patched document with its relative references
(meshes, textures, included files, asset folders) made to resolve from the output's folder,
written atomically (`urdfinertia.atomic`), with a backup of the input when it is replaced.
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

from urdfinertia.atomic import atomic_write_bytes, write_in_place
from urdfinertia.errors import OutputError

if TYPE_CHECKING:
    from collections.abc import Mapping

    from urdfinertia.descriptions.formats import DescriptionFormat
    from urdfinertia.descriptions.xacro.writeback import Plan
    from urdfinertia.plan.results import FixResult

#: Suffix of the copy kept when a file is replaced in place.
BACKUP_SUFFIX = ".bak"


@dataclass(frozen=True)
class SaveReport:
    """What [`save_result`][urdfinertia.plan.save.save_result] did.

    Attributes
    ----------
    path : Path
        The file written (a symbolic link's target), or that would have been.
    written : bool
        False when nothing needed writing (in place, and nothing changed).
    references_rewritten : int
        Relative references rewritten to resolve from the output's folder.
    backup : Path or None
        The copy of the replaced input (in place with `backup=True`).
    """

    path: Path
    written: bool
    references_rewritten: int = 0
    backup: Path | None = None


def output_bytes(result: FixResult, path: str | Path, *, keep_mesh_paths: bool = False,
                 ) -> tuple[bytes, int]:
    """The bytes :func:`save_result` writes at ``path``, and the references it rewrote.

    Parameters
    ----------
    result : FixResult
        A fixed description.
    path : str or Path
        Where the document is to be written.
    keep_mesh_paths : bool
        Keep relative references as written even when ``path`` is in another folder.

    Returns
    -------
    document : bytes
        ``result.output`` with its relative references relocated (see
        :func:`urdfinertia.descriptions.formats.relocate_references`).
    rewritten : int
        How many references were rewritten.
    """
    if keep_mesh_paths:
        return result.output, 0
    from urdfinertia.descriptions.formats import relocate_references

    return relocate_references(result.output, result.path, Path(path))


def save_result(result: FixResult, path: str | Path | None = None, *, in_place: bool = False,
                backup: bool = True, keep_mesh_paths: bool = False) -> SaveReport:
    """Write a fixed description to `path`, or over its input.

    Parameters
    ----------
    result : FixResult
        What [`urdfinertia.fix`][urdfinertia.api.fix] (or `fix_file`) returned.
    path : str or Path, optional
        The output file. Its folder must exist. A format with a default output (USD: the
        override layer `<asset>.inertia.usda` beside the asset) is saved there when
        `path` is omitted. Relative references of the document are
        rewritten to name the same files from there (unless `keep_mesh_paths`).
    in_place : bool
        Replace the input file (`result.path`) instead; `path` must then be omitted
        or name the input. Nothing is written when the document did not change.
    backup : bool
        With `in_place`: first keep a complete copy of the input as
        `<input>.bak` (written atomically, an older one replaced).
    keep_mesh_paths : bool
        Write relative references as they are, even in another folder.

    Returns
    -------
    SaveReport
        The file written, whether it was, the references rewritten and the backup.

    Raises
    ------
    OutputError
        The file cannot be written; `path` names the input without `in_place`; neither
        `path` nor `in_place` is given; or `in_place` is asked for a xacro input
        (its sources are edited by write-back, not replaced by the expansion).

    Notes
    -----
    The write is atomic: the new bytes go to a temporary file in the target's folder,
    which then replaces the target. A failure leaves the target as it was.

    Examples
    --------
    >>> result = urdfinertia.fix("robot.urdf")            # doctest: +SKIP
    >>> result.save("out/robot.urdf").references_rewritten  # doctest: +SKIP
    12
    """
    source = Path(result.path)
    if in_place:
        if path is not None and not _same_file(Path(path), source):
            raise OutputError("in_place writes the input file; pass no other path",
                              file=path)
        if result.robot.format == "xacro":
            raise OutputError("a xacro file is not replaced by its expansion: write the "
                              "fixed values back into its sources (write-back) or save "
                              "the URDF elsewhere", file=source)
        if not result.changed:
            return SaveReport(source, False)
        own = _format(result).write_in_place
        if own is not None:  # USD: the fixed opinions are authored into the root layer
            own(source, result.output)
            return SaveReport(source, True)
        if backup:
            written = write_in_place(source, result.output, BACKUP_SUFFIX)
            return SaveReport(written, True, 0, written.with_name(written.name
                                                                   + BACKUP_SUFFIX))
        return SaveReport(atomic_write_bytes(source, result.output), True)
    default_output = _format(result).default_output
    if path is None and default_output is not None:
        path = default_output(source)  # USD: an override layer beside the asset
    if path is None:
        raise OutputError("nothing to save to: pass a path or in_place=True", file=source)
    path = Path(path)
    if _same_file(path, source):
        raise OutputError("output is the input file: use in-place saving", file=path)
    document, rewritten = output_bytes(result, path, keep_mesh_paths=keep_mesh_paths)
    return SaveReport(atomic_write_bytes(path, document), True, rewritten)


def write_back(result: FixResult, *, xacro_args: Mapping[str, str] | None = None,
               package_dirs: Mapping[str, str | Path] | None = None,
               backup: bool = True, report: str | Path | None = None) -> Plan:
    """Write a fixed xacro robot's new values into its sources (`fix --write-back`).

    Each value is changed where it is written: a literal, a property, a macro call's
    attribute or a YAML scalar; values that are computed or shared by several links are
    reported in the plan, not changed. The edited sources are expanded again and must give
    `result.output` before anything is kept.

    Parameters
    ----------
    result : FixResult
        [`urdfinertia.fix`][urdfinertia.api.fix] of a xacro file.
    xacro_args, package_dirs : mapping, optional
        The xacro arguments and package folders the robot was fixed with.
    backup : bool
        Keep `<source>.bak` of every file changed.
    report : str or Path, optional
        Write the links not written back, with where each value comes from, to this YAML
        file (before the sources are edited, so it is there even when editing fails).

    Returns
    -------
    Plan
        Per link, where each value was written or why it was not.

    Raises
    ------
    UrdfInertiaError
        The input is not xacro, or its sources changed since `result` was computed, or
        the edited sources do not expand to the fixed document (nothing is then kept).
    """
    from urdfinertia.descriptions.formats import read_bytes
    from urdfinertia.descriptions.xacro import expansion
    from urdfinertia.descriptions.xacro.apply import apply_plan
    from urdfinertia.descriptions.xacro.expand import settings_for
    from urdfinertia.descriptions.xacro.writeback import plan_write_back, report_yaml
    from urdfinertia.errors import UrdfInertiaError

    source = Path(result.path)
    if result.robot.format != "xacro":
        raise UrdfInertiaError("write-back applies to xacro input (a URDF is saved in "
                               "place or elsewhere)", file=source)
    with settings_for(xacro_args, package_dirs) as settings:
        exp = expansion(read_bytes(source), source)
        if exp.document != result.original:
            raise UrdfInertiaError("the sources changed during the run; nothing written",
                                   file=source)
        plan = plan_write_back(source, exp, result.output, settings)
        if report is not None:
            atomic_write_bytes(Path(report), report_yaml(plan).encode())
        apply_plan(source, exp, result.output, plan, settings, backup=backup)
    return plan


def _format(result: FixResult) -> DescriptionFormat:
    from urdfinertia.descriptions.formats import format_of

    return format_of(result.robot)


def _same_file(a: Path, b: Path) -> bool:
    return os.path.realpath(a) == os.path.realpath(b)
