"""The inputs of a batch run: description files and folders, and where each result goes."""

from __future__ import annotations

import os
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

from urdfinertia.descriptions.paths import RealPaths
from urdfinertia.errors import OutputError, UrdfError


@dataclass(frozen=True)
class FileJob:
    """One URDF to fix and where its result goes (None: kept in memory)."""

    source: Path
    output: Path | None = None


FOLDER_SUFFIXES = (".urdf", ".sdf", ".world")
"""Suffixes a folder is searched for (any case). `.xml` files count only when their root element
is a registered format's (MJCF's `<mujoco>`): a folder holds `package.xml` and launch files
too. xacro sources are taken only when named: a package's many macro files are not robots.
"""


def collect_jobs(inputs: Sequence[Path], output_dir: Path | None) -> list[FileJob]:
    """The descriptions named by `inputs` (files, and folders searched recursively for
    `*.urdf`, `*.sdf`, `*.world` and MJCF `*.xml`).

    A file goes to `output_dir/<name>`, a folder's files to ``output_dir/<path relative
    to the folder>``. Raises when an input does not exist, nothing is found, two inputs
    would be written to the same place or an output would overwrite its input.
    """
    found: list[tuple[Path, Path]] = []  # (source, path relative to output_dir)
    for item in inputs:
        item = Path(item)
        if item.is_dir():
            files = sorted(description_files(item))
            found.extend((p, p.relative_to(item)) for p in files)
        elif item.is_file():
            found.append((item, Path(item.name)))
        else:
            raise UrdfError("no such file or folder", file=item)
    if not found:
        raise UrdfError("no .urdf, .sdf, .world or MJCF .xml files found in "
                        + ", ".join(map(str, inputs)))
    jobs: list[FileJob] = []
    seen: set[Path] = set()
    targets: dict[Path, Path] = {}
    real_path = RealPaths()  # Path.resolve, with the folders of the tree resolved once
    for source, rel in found:
        key = Path(real_path(source))
        if key in seen:
            continue
        seen.add(key)
        output = output_dir / rel if output_dir is not None else None
        if output is not None:
            target = Path(real_path(output))
            if target == key:
                raise OutputError("output is the input file: use --in-place", file=output)
            if target in targets:
                raise OutputError(f"two inputs would be written here: {targets[target]} and "
                                  f"{source}", file=output)
            targets[target] = source
        jobs.append(FileJob(source, output))
    return jobs


def description_files(folder: Path) -> list[Path]:
    """Description files under `folder` (`FOLDER_SUFFIXES`, MJCF `.xml`),
    unordered.

    What `folder.rglob("*")` filtered on `suffix` and `is_file()` finds (symbolic
    links to folders are not followed, links to files are kept), with `os.walk`: pathlib
    built a path object for every file of the tree, meshes included.
    """
    out = []
    for root, _, names in os.walk(folder):
        for name in names:
            dot = name.rfind(".")
            suffix = name[dot:].lower() if 0 < dot < len(name) - 1 else ""
            if suffix in FOLDER_SUFFIXES or (suffix == ".xml" and _is_mjcf(Path(root, name))):
                path = Path(root, name)
                if path.is_file():
                    out.append(path)
    return out


def _is_mjcf(path: Path) -> bool:
    """An `.xml` file whose root element is `<mujoco>` (first 64 KiB read)."""
    from urdfinertia.descriptions.formats import root_name

    try:
        with path.open("rb") as fh:
            head = fh.read(1 << 16)
    except OSError:
        return False
    return root_name(head) == "mujoco"
