"""Whole-file results in the cache: a warm batch run skips the URDFs nothing changed in.

An entry is keyed by the URDF's bytes and location, every
[`FixOptions`][urdfinertia.body.options.FixOptions] field, the package search path variables and a
digest of this package's whole source. It records the fixed document, the summary of the run, and
each mesh the result depends on as `(uri, urdf folder, resolved path, content key)`. It is used only
when every mesh URI still resolves to the same file and every such file still has the same content
key (`cache.file_entry_key`, a hash of its bytes), so an edited mesh, a new package folder or
different options never meet an old result. The stored document carries its own digest: a truncated
or altered entry is ignored. Runs with a decomposition spec are not cached at this level (the spec's
files are further inputs).

A file that fails for a reason fixed by its inputs alone (its XML, a mesh URI that does
not resolve, a mesh the repair rejects for its bytes, masses that do not add up) is stored
too, as its one-line error: a mesh URI that did not resolve is recorded with the reason,
and the entry is used only while it still fails for that same reason. Errors that may
depend on anything else (a file that cannot be read, an internal error) are never stored.
An error message quotes paths as the user spelled them, so it is reused only for the same
spelling of the URDF's path.
"""

from __future__ import annotations

import dataclasses
import hashlib
import itertools
import json
import os
from pathlib import Path
from typing import TypeGuard

from urdfinertia.body.options import FixOptions
from urdfinertia.cache.store import SolidsCache, key_from_digest
from urdfinertia.cache.version import code_digest
from urdfinertia.descriptions.paths import RealPaths, resolve_mesh_path
from urdfinertia.errors import MeshError
from urdfinertia.mesh.limits import max_mesh_bytes

FILES_FORMAT = "urdfinertia-file-result/3"
MAGIC = b"URDFINERTIA-FILE\n"
_ENV = ("ROS_PACKAGE_PATH", "AMENT_PREFIX_PATH")


def result_key(data: bytes, source: Path, options: FixOptions,
               real_path: RealPaths | None = None,
               fields: list[tuple[str, str]] | None = None) -> str | None:
    """Key of the result of fixing `source` (bytes `data`); None when not cacheable.

    `fields`: `option_fields` of `options`, when the caller has them.
    """
    if options.spec is not None:
        return None
    resolved = real_path(source) if real_path is not None else str(source.resolve())
    head = json.dumps([FILES_FORMAT, code_digest(), resolved,
                       option_fields(options) if fields is None else fields,
                       [os.environ.get(v, "") for v in _ENV]])
    h = hashlib.blake2b(digest_size=20)
    h.update(head.encode() + b"\0")
    h.update(data)
    return h.hexdigest()


def option_fields(options: FixOptions) -> list[tuple[str, str]]:
    """(name, repr) of every [`FixOptions`][urdfinertia.body.options.FixOptions] field: part of
    every key."""
    return [(f.name, repr(getattr(options, f.name))) for f in dataclasses.fields(options)]


@dataclasses.dataclass(frozen=True)
class CachedResult:
    """A file's fixed document and summary, or (`error` set) its one-line error."""

    robot: str
    links: int
    recomputed: int
    warnings: tuple[str, ...]
    document: bytes
    error: str | None = None
    left: tuple[str, ...] = ()
    problems: tuple[str, ...] = ()


def encode(key: str, deps: list[list[str]], result: CachedResult, source: str = "") -> bytes:
    """Entry bytes; `source` is the URDF's path as spelled (checked for errors only).

    The body is the fixed document, or for an error its message (UTF-8), under the digest.
    """
    body = result.document if result.error is None else result.error.encode("utf-8")
    header = {"format": FILES_FORMAT, "key": key, "deps": deps, "robot": result.robot,
              "links": result.links, "recomputed": result.recomputed,
              "warnings": list(result.warnings), "error": result.error is not None,
              "left": list(result.left), "problems": list(result.problems),
              "source": source,
              "document_digest": hashlib.blake2b(body, digest_size=20).hexdigest()}
    head = json.dumps(header).encode()
    return MAGIC + len(head).to_bytes(4, "little") + head + body


def decode(data: bytes, key: str, source: str = "",
           ) -> tuple[list[list[str]], CachedResult] | None:
    """Validate an entry; an error entry must also name the same spelling of the source."""
    if not data.startswith(MAGIC):
        return None
    pos = len(MAGIC)
    size = int.from_bytes(data[pos:pos + 4], "little")
    head = data[pos + 4:pos + 4 + size]
    if len(head) != size:
        return None
    header = json.loads(head.decode("utf-8"))
    if not isinstance(header, dict) or header.get("format") != FILES_FORMAT:
        return None
    if header.get("key") != key:
        return None
    deps = header.get("deps")
    if not _string_rows(deps, 4):
        return None
    robot, links, recomputed = header.get("robot"), header.get("links"), header.get("recomputed")
    warnings = header.get("warnings")
    if not (isinstance(robot, str) and isinstance(links, int) and isinstance(recomputed, int)
            and _strings(warnings)):
        return None
    failed = header.get("error")
    if not isinstance(failed, bool):
        return None
    left, problems = header.get("left"), header.get("problems")
    if not (_strings(left) and _strings(problems)):
        return None
    if failed and header.get("source") != source:
        return None  # an error quoting the source as spelled otherwise
    body = data[pos + 4 + size:]
    if header.get("document_digest") != hashlib.blake2b(body, digest_size=20).hexdigest():
        return None  # truncated or altered
    if not failed:
        return deps, CachedResult(robot, links, recomputed, tuple(warnings), body, None,
                                  tuple(left), tuple(problems))
    try:
        error = body.decode("utf-8")
    except UnicodeDecodeError:
        return None
    if not error:
        return None
    return deps, CachedResult(robot, links, recomputed, tuple(warnings), b"", error)


class FileResults:
    """Look up and store whole-file results for one run (memoising mesh keys and paths)."""

    def __init__(self, cache: SolidsCache, options: FixOptions) -> None:
        self.cache = cache
        self.options = options
        self.package_dirs = dict(options.package_dirs)
        self.real_path = RealPaths()
        self._fields = option_fields(options)
        self._mesh_keys: dict[str, str | None] = {}
        self._real: dict[tuple[str, str], str | MeshError] = {}
        self._folders: dict[str, Path] = {}
        self._limit = max_mesh_bytes(options.max_faces)
        self.keys: dict[Path, tuple[str, bytes]] = {}
        self.hits = 0

    def path(self, key: str) -> Path:
        """The entry file of `key`.

        Parameters
        ----------
        key : str
            A file entry's key.

        Returns
        -------
        Path
            Where it is stored.
        """
        return self.cache.files_folder / key[:2] / f"{key}.entry"

    def mesh_key(self, path: str) -> str | None:
        """`cache.file_entry_key` of the file at `path` (a string: no Path object
        is built per mesh)."""
        if path not in self._mesh_keys:
            digest = self.cache.digests.digest(path, self._limit)
            self._mesh_keys[path] = (None if digest is None
                                     else key_from_digest(digest, _suffix(path)))
        return self._mesh_keys[path]

    def lookup(self, source: Path) -> tuple[CachedResult, bytes] | None:
        """(cached result, original bytes) for `source`, if still valid."""
        try:
            data = source.read_bytes()
        except OSError:
            return None
        try:
            key = result_key(data, source, self.options, self.real_path, self._fields)
        except (OSError, RuntimeError):  # e.g. a symbolic link loop: the fix says so
            return None
        if key is None:
            return None
        self.keys[source] = (key, data)
        spelled = str(source)
        found = self.cache.read(self.path(key), lambda raw: decode(raw, key, spelled),
                                count=False)
        if found is None or not self._still_valid(found[0]):
            return None
        self.hits += 1
        return found[1], data

    def _real_path(self, uri: str, folder: str) -> str | MeshError:
        """The resolved file `uri` names from `folder` or why there is none, memoised
        per run (resolving walks the tree)."""
        key = (uri, folder)
        found = self._real.get(key)
        if found is None:
            urdf_dir = self._folders.get(folder)
            if urdf_dir is None:
                urdf_dir = self._folders[folder] = Path(folder)
            try:
                found = self.real_path(resolve_mesh_path(uri, urdf_dir, self.package_dirs))
            except MeshError as exc:
                found = exc
            self._real[key] = found
        return found

    def _still_valid(self, deps: list[list[str]]) -> bool:
        for uri, folder, path, mesh_key in deps:
            try:
                found = self._real_path(uri, folder)
            except (OSError, RuntimeError, ValueError):
                return False
            if not path:  # the URI did not resolve: it must still fail the same way
                if not (isinstance(found, MeshError) and found.cause == mesh_key):
                    return False
                continue
            if found != path or self.mesh_key(path) != mesh_key:
                return False
        return True

    def store(self, source: Path, trace: tuple[tuple[str, str, str], ...],
              result: CachedResult) -> None:
        """Remember a fresh result; `trace` lists the meshes it was computed from (a
        path of `""`: the URI did not resolve)."""
        known = self.keys.get(source)
        if known is None:
            return
        key, data = known
        deps = []
        for uri, folder, path in dict.fromkeys(trace):
            if not path:
                try:
                    found = self._real_path(uri, folder)
                except (OSError, RuntimeError, ValueError):
                    return
                if not isinstance(found, MeshError):
                    return  # resolves now: nothing stable to record
                deps.append([uri, folder, "", found.cause])
                continue
            mesh_key = self.mesh_key(path)
            if mesh_key is None:
                return
            deps.append([uri, folder, path, mesh_key])
        self.cache.write(self.path(key), encode(key, deps, result, str(source)))


def _strings(items: object) -> TypeGuard[list[str]]:
    """`items` is a list of strings (a JSON value: see `_string_rows`)."""
    return type(items) is list and set(map(type, items)) <= {str}


def _string_rows(rows: object, width: int) -> TypeGuard[list[list[str]]]:
    """`rows` is a list of lists of `width` strings each (a JSON value: its types are
    exactly `list` and `str`, so `type(...) is` suffices). One pass over the strings
    by `map`, not a generator per row: a warm run checks some 20,000 of them."""
    if type(rows) is not list:
        return False
    if not all(type(r) is list and len(r) == width for r in rows):
        return False
    return set(map(type, itertools.chain.from_iterable(rows))) <= {str}


def _suffix(path: str) -> str:
    """`Path(path).suffix` without building the Path."""
    name = os.path.basename(path)
    dot = name.rfind(".")
    return name[dot:] if 0 < dot < len(name) - 1 else ""
