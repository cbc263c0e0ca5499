"""Resolve mesh URIs of a URDF (relative, `file://` and `package://`) or of an SDFormat
model (also `model://`) to files.

Only local regular files are ever returned: other URL schemes, `file://` URIs naming a
remote host, FIFOs and devices are refused, so nothing is fetched and no read can block.
"""

from __future__ import annotations

import functools
import os
import re
import stat
from collections.abc import Mapping
from pathlib import Path
from urllib.parse import unquote, urlparse

from urdfinertia.errors import MeshError
from urdfinertia.rules import Rule

_PACKAGE_NAME = re.compile(r"<name>\s*([^<\s]+)\s*</name>")
_PACKAGE_NAME_OK = re.compile(r"[A-Za-z0-9_][A-Za-z0-9_.-]*\Z")
"""ROS package names (REP 144 is stricter; this only keeps out '', '.', '..' and separators)."""


def find_package(name: str, urdf_dir: Path, package_dirs: Mapping[str, Path]) -> Path | None:
    """Folder of ROS package `name`.

    Order: `package_dirs` (`--package-dir NAME=PATH`; a relative folder is the working
    directory's), then `ROS_PACKAGE_PATH` and
    `AMENT_PREFIX_PATH` (`share/NAME`), then the URDF's folder and its ancestors: a folder
    named `name`, or one whose `package.xml` declares `name`.
    """
    if name in package_dirs:  # a relative folder is the working directory's
        return Path(package_dirs[name]).expanduser().absolute()
    for root in os.environ.get("ROS_PACKAGE_PATH", "").split(os.pathsep):
        if root:
            for cand in (Path(root) / name, Path(root)):
                if cand.is_dir() and _is_package(cand, name):
                    return cand
    for prefix in os.environ.get("AMENT_PREFIX_PATH", "").split(os.pathsep):
        if prefix and (Path(prefix) / "share" / name).is_dir():
            return Path(prefix) / "share" / name
    folder = urdf_dir.resolve()
    for cand in (folder, *folder.parents):
        if cand.name == name or _is_package(cand, name):
            return cand
        if (cand / name).is_dir():
            return cand / name
    return None


@functools.lru_cache(maxsize=4096)
def _find_package_memo(name: str, urdf_dir: Path, package_dirs: tuple[tuple[str, Path], ...],
                       ros_package_path: str, ament_prefix_path: str) -> Path | None:
    """`find_package`, memoised: one lookup per package and folder, not per mesh.

    The environment variables are part of the key so that a changed search path is seen.
    """
    del ros_package_path, ament_prefix_path  # read again inside; here only for the key
    return find_package(name, urdf_dir, dict(package_dirs))


MODEL_PATH_VARIABLES = ("GZ_SIM_RESOURCE_PATH", "IGN_GAZEBO_RESOURCE_PATH", "SDF_PATH",
                        "GAZEBO_MODEL_PATH")
"""Search paths of Gazebo (old and new names) and libsdformat for `model://NAME`."""


def find_model(name: str, sdf_dir: Path, package_dirs: Mapping[str, Path]) -> Path | None:
    """Folder of SDFormat model `name` (what `model://NAME/...` refers to).

    Order: `package_dirs` (`--package-dir NAME=PATH`), then the folders listed in
    `MODEL_PATH_VARIABLES` (`ROOT/NAME`), then the file's folder and its ancestors:
    a folder named `name` holding a `model.config`, or one that has such a subfolder.
    """
    if name in package_dirs:  # a relative folder is the working directory's
        return Path(package_dirs[name]).expanduser().absolute()
    for variable in MODEL_PATH_VARIABLES:
        for root in os.environ.get(variable, "").split(os.pathsep):
            if root and (Path(root) / name).is_dir():
                return Path(root) / name
    folder = sdf_dir.resolve()
    for cand in (folder, *folder.parents):
        if cand.name == name and (cand / "model.config").is_file():
            return cand
        if (cand / name / "model.config").is_file():
            return cand / name
    for cand in (folder, *folder.parents):  # a model folder without its model.config
        if cand.name == name:
            return cand
    return None


def package_hint(name: str) -> str:
    """How to say where package ``name`` is, in both forms: these messages reach command
    line and library callers alike (and the mesh cache keeps them for either)."""
    return f"pass --package-dir {name}=PATH (Python: package_dirs={{{name!r}: PATH}})"


def _is_package(folder: Path, name: str) -> bool:
    if folder.name == name:
        return True
    manifest = folder / "package.xml"
    if not manifest.is_file():
        return False
    try:
        match = _PACKAGE_NAME.search(manifest.read_text(encoding="utf-8", errors="replace"))
    except OSError:
        return False
    return bool(match and match.group(1) == name)


def resolve_mesh_path(
    uri: str, urdf_dir: Path, package_dirs: Mapping[str, Path] | None = None
) -> Path:
    """The file a `<mesh filename="...">` refers to.

    Raises
    ------
    MeshError
        The URI uses a scheme other than `package://` or `file://` (no URLs are
        fetched), names a package that cannot be found, or the file does not exist.
    """
    package_dirs = package_dirs or {}
    if "\x00" in uri:
        raise MeshError(f"mesh URI {uri!r} contains a NUL character")
    parsed = urlparse(uri)
    scheme = parsed.scheme.lower()
    if scheme == "package":
        name, rel = parsed.netloc, unquote(parsed.path).lstrip("/")
        if not name:  # "package:///NAME/..." occurs in the wild (example-robot-data)
            name, _, rel = rel.partition("/")
        if not _PACKAGE_NAME_OK.match(name):
            raise MeshError(f"mesh URI {uri!r} does not name a valid ROS package",
                            rule=Rule.MESH_UNRESOLVED)
        root = _find_package_memo(name, urdf_dir, tuple(sorted(package_dirs.items())),
                                  os.environ.get("ROS_PACKAGE_PATH", ""),
                                  os.environ.get("AMENT_PREFIX_PATH", ""))
        if root is None:
            raise MeshError(f"cannot resolve package '{name}' in {uri!r}: "
                            f"{package_hint(name)} or set ROS_PACKAGE_PATH",
                            rule=Rule.MESH_UNRESOLVED)
        path = root / rel
    elif scheme == "model":
        name, rel = parsed.netloc, unquote(parsed.path).lstrip("/")
        if not _PACKAGE_NAME_OK.match(name):
            raise MeshError(f"mesh URI {uri!r} does not name a valid model",
                            rule=Rule.MESH_UNRESOLVED)
        root = find_model(name, urdf_dir, package_dirs)
        if root is None:
            raise MeshError(f"cannot resolve model '{name}' in {uri!r}: "
                            f"{package_hint(name)} or set GZ_SIM_RESOURCE_PATH",
                            rule=Rule.MESH_UNRESOLVED)
        path = root / rel
    elif scheme == "file":
        if parsed.netloc not in ("", "localhost"):
            raise MeshError(f"mesh URI {uri!r} names host '{parsed.netloc}': only local "
                            "files are read", rule=Rule.MESH_REFUSED)
        path = Path(unquote(parsed.path))
    elif scheme == "" or (len(scheme) == 1 and os.name == "nt"):
        path = Path(uri)
        if not path.is_absolute():
            path = urdf_dir / path
    else:
        raise MeshError(f"mesh URI {uri!r} uses scheme '{scheme}': only files are read",
                        rule=Rule.MESH_REFUSED)
    try:
        info = path.stat()  # follows symbolic links, like every later read
    except (OSError, ValueError):
        raise MeshError(f"mesh file not found: {uri!r} (looked at {path})",
                        rule=Rule.MESH_UNRESOLVED) from None
    if not stat.S_ISREG(info.st_mode):
        # a FIFO, device or folder: reading could block forever or never end
        raise MeshError(f"mesh {uri!r} is not a regular file (looked at {path})")
    return path


class RealPaths:
    """`str(Path(p).resolve())` for many paths, memoising resolved folders.

    `Path.resolve` checks every component of every path (one `lstat` each), while the
    files of a run share few folders. Here each component is appended to its resolved
    parent (one `lstat` per new file or folder; `..` takes the parent's folder), as
    `realpath` does; a path that meets a symbolic link is resolved by `Path.resolve`
    itself. The memo assumes that files and folders are not replaced by links (or links
    retargeted) during the life of the object (one run).
    """

    def __init__(self) -> None:
        self._known: dict[str, str | None] = {}  # None: a link on the way

    def __call__(self, path: str | os.PathLike[str]) -> str:
        text = os.fspath(path)
        if not os.path.isabs(text):  # the memo must not depend on the working folder
            text = os.path.join(os.getcwd(), text)
        found = self._resolve(text)
        return str(Path(text).resolve()) if found is None else found

    def _resolve(self, text: str) -> str | None:
        if text in self._known:
            return self._known[text]
        head, tail = os.path.split(text)
        found: str | None
        if head == text:  # the root
            found = str(Path(text).resolve())
        else:
            found = self._resolve(head)
            if found is None or tail in ("", "."):
                pass
            elif tail == "..":
                found = os.path.dirname(found)
            else:
                found = os.path.join(found, tail)
                if os.path.islink(found):
                    found = None
        self._known[text] = found
        return found
