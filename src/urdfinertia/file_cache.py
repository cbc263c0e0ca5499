"""Whole-file results in the cache: a warm batch run skips the URDFs nothing changed in.

An entry is keyed by the URDF's bytes and location, every :class:`FixOptions` field, the
package search path variables and a digest of this package's whole source. It records the
fixed document, the summary of the run, and each mesh the result depends on as
``(uri, urdf folder, resolved path, content key)``. It is used only when every mesh URI
still resolves to the same file and every such file still has the same content key
(:func:`cache.file_entry_key`, a hash of its bytes), so an edited mesh, a new package
folder or different options never meet an old result. The stored document carries its own
digest: a truncated or altered entry is ignored. Runs with a decomposition spec are
not cached at this level (the spec's files are further inputs).
"""

from __future__ import annotations

import dataclasses
import functools
import hashlib
import json
import os
from pathlib import Path

from . import __version__
from .cache import SolidsCache, file_entry_key
from .errors import UrdfInertiaError
from .fix import FixOptions
from .mesh_io import max_mesh_bytes
from .meshlib import MeshLibrary

FILES_FORMAT = "urdfinertia-file-result/1"
MAGIC = b"URDFINERTIA-FILE\n"
_ENV = ("ROS_PACKAGE_PATH", "AMENT_PREFIX_PATH")


@functools.lru_cache(maxsize=1)
def package_digest() -> str:
    """Digest of every module of this package: any code change invalidates file results."""
    h = hashlib.blake2b(digest_size=16)
    for path in sorted(Path(__file__).parent.glob("*.py")):
        h.update(path.name.encode() + b"\0" + path.read_bytes() + b"\0")
    return h.hexdigest()


def result_key(data: bytes, source: Path, options: FixOptions) -> str | None:
    """Key of the result of fixing ``source`` (bytes ``data``); None when not cacheable."""
    if options.spec is not None:
        return None
    fields = [(f.name, repr(getattr(options, f.name))) for f in dataclasses.fields(options)]
    head = json.dumps([FILES_FORMAT, __version__, package_digest(), str(source.resolve()),
                       fields, [os.environ.get(v, "") for v in _ENV]])
    h = hashlib.blake2b(digest_size=20)
    h.update(head.encode() + b"\0")
    h.update(data)
    return h.hexdigest()


@dataclasses.dataclass(frozen=True)
class CachedResult:
    robot: str
    links: int
    recomputed: int
    warnings: tuple[str, ...]
    document: bytes


def encode(key: str, deps: list[list[str]], result: CachedResult) -> bytes:
    header = {"format": FILES_FORMAT, "key": key, "deps": deps, "robot": result.robot,
              "links": result.links, "recomputed": result.recomputed,
              "warnings": list(result.warnings),
              "document_digest": hashlib.blake2b(result.document, digest_size=20).hexdigest()}
    head = json.dumps(header).encode()
    return MAGIC + len(head).to_bytes(4, "little") + head + result.document


def decode(data: bytes, key: str) -> tuple[list[list[str]], CachedResult] | None:
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
    if not (isinstance(deps, list) and all(
            isinstance(d, list) and len(d) == 4 and all(isinstance(x, str) for x in d)
            for d in deps)):
        return None
    robot, links, recomputed = header.get("robot"), header.get("links"), header.get("recomputed")
    warnings = header.get("warnings")
    if not (isinstance(robot, str) and isinstance(links, int) and isinstance(recomputed, int)
            and isinstance(warnings, list) and all(isinstance(w, str) for w in warnings)):
        return None
    document = data[pos + 4 + size:]
    if header.get("document_digest") != hashlib.blake2b(document, digest_size=20).hexdigest():
        return None  # truncated or altered
    return deps, CachedResult(robot, links, recomputed, tuple(warnings), document)


class FileResults:
    """Look up and store whole-file results for one run (memoising mesh keys)."""

    def __init__(self, cache: SolidsCache, options: FixOptions) -> None:
        self.cache = cache
        self.options = options
        self.meshes = MeshLibrary(options.package_dirs, options.max_faces)
        self._mesh_keys: dict[str, str | None] = {}
        self._real: dict[tuple[str, str], str] = {}
        self.keys: dict[Path, tuple[str, bytes]] = {}
        self.hits = 0

    def path(self, key: str) -> Path:
        return self.cache.files_folder / key[:2] / f"{key}.entry"

    def mesh_key(self, path: str) -> str | None:
        if path not in self._mesh_keys:
            limit = max_mesh_bytes(self.options.max_faces)
            self._mesh_keys[path] = file_entry_key(Path(path), limit, self.cache.digests)
        return self._mesh_keys[path]

    def lookup(self, source: Path) -> tuple[CachedResult, bytes] | None:
        """(cached result, original bytes) for ``source``, if still valid."""
        try:
            data = source.read_bytes()
        except OSError:
            return None
        key = result_key(data, source, self.options)
        if key is None:
            return None
        self.keys[source] = (key, data)
        found = self.cache.read(self.path(key), lambda raw: decode(raw, key), count=False)
        if found is None or not self._still_valid(found[0]):
            return None
        self.hits += 1
        return found[1], data

    def _real_path(self, uri: str, folder: str) -> str:
        """The resolved file ``uri`` names, memoised per run (realpath walks the tree)."""
        key = (uri, folder)
        if key not in self._real:
            self._real[key] = str(self.meshes.resolve(uri, Path(folder)).resolve())
        return self._real[key]

    def _still_valid(self, deps: list[list[str]]) -> bool:
        for uri, folder, path, mesh_key in deps:
            try:
                if self._real_path(uri, folder) != path:
                    return False
            except UrdfInertiaError:
                return False
            if self.mesh_key(path) != mesh_key:
                return False
        return True

    def store(self, source: Path, trace: tuple[tuple[str, str, str], ...],
              result: CachedResult) -> None:
        """Remember a fresh result; ``trace`` lists the meshes it was computed from."""
        known = self.keys.get(source)
        if known is None:
            return
        key, data = known
        deps = []
        for uri, folder, path in dict.fromkeys(trace):
            mesh_key = self.mesh_key(path)
            if mesh_key is None:
                return
            deps.append([uri, folder, path, mesh_key])
        self.cache.write(self.path(key), encode(key, deps, result))
