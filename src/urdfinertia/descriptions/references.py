"""Relative references of a document written to another folder: one rule for every format.

A description names other files (meshes, textures, included files, asset folders) by paths
that are relative to its own folder. When `fix` writes the document somewhere else, each
such path must still name the same file: `relocated` gives the new text, and
`splice_edits` puts new attribute or element text in place of the old, every other
byte unchanged. Each format's `relocate` (`.urdf.mesh_refs`, `.mjcf.relocate`,
`.sdf.relocate`) finds its own references and calls these.
"""

from __future__ import annotations

import os
import re
from pathlib import Path, PurePosixPath

from urdfinertia.descriptions.splice import splice_edits  # noqa: F401  (re-exported)

_SCHEME = re.compile(r"[A-Za-z][A-Za-z0-9+.-]*:")


def is_relative_ref(uri: str) -> bool:
    """A plain relative path (what depends on the document's own folder).

    `package://`, `model://`, `file://` and other schemes, absolute paths, and values
    holding an unexpanded `$(...)` or an XML reference are not.
    """
    if not uri or _SCHEME.match(uri) or "$(" in uri or "&" in uri:
        return False
    return not (uri.startswith(("/", "\\")) or Path(uri).is_absolute())


def relocated(uri: str, source_dir: Path, output_dir: Path) -> str:
    """`uri` (relative to `source_dir`) as a path naming the same file from
    `output_dir`: relative with `/` separators, or absolute where no relative path
    exists (another drive on Windows)."""
    target = os.path.normpath(Path(os.path.abspath(source_dir)) / uri)
    try:
        rel = os.path.relpath(target, os.path.abspath(output_dir))
    except ValueError:
        return Path(target).as_posix()
    return PurePosixPath(*Path(rel).parts).as_posix()


def same_folder(source_dir: Path, output_dir: Path) -> bool:
    """Whether two folders are the same path (no reference needs rewriting).

    Parameters
    ----------
    source_dir, output_dir : Path
        The input's and the output's folders.

    Returns
    -------
    bool
        True when they are the same absolute path.
    """
    return os.path.abspath(source_dir) == os.path.abspath(output_dir)
