"""Persistent cache of per-mesh results (`MeshSolids`) keyed by file content.

An entry's key is a hash of the mesh file's bytes, its format (suffix) and the version of
everything that turns bytes into solids (the repair algorithm's version string and a digest
of this package's source), so an edited file or a new algorithm never meets a stale entry.
Scale is not part of the key: `MeshSolids.scaled` applies `<mesh scale>` exactly
afterwards. `max_faces` only refuses meshes, so the face count is stored and checked on a
hit instead.

An entry file holds a magic line, a JSON header (format, key, face count, field names, the
solids' text fields) and raw little-endian float64 numbers, sealed by a BLAKE2b digest of
its file name (which holds the key) and bytes; nothing is ever unpickled or evaluated.
Anything that does not validate (a seal that does not match, wrong magic, header or key,
wrong length, non-finite values, volume not positive, asymmetric second moments) or is
not a regular file within `MAX_ENTRY_BYTES` (a FIFO, a symbolic link, a device) is
ignored, removed and recomputed, never trusted; opening never blocks or follows a link.
A mesh the repair rejects (a `MeshError` it raises for the bytes themselves) is stored
too, as its message, so a warm run repeats the error without redoing the work. The folder
is kept under a size bound by deleting the least recently used entries (by modification
time; a hit touches it).
"""

from __future__ import annotations

import dataclasses
import hashlib
import hmac
import json
import os
import stat
import time
from collections.abc import Callable
from pathlib import Path
from typing import TYPE_CHECKING, Any, TypeVar

from urdfinertia.atomic import replace_file
from urdfinertia.cache.digests import FileDigests, content_digest, file_digest
from urdfinertia.cache.version import code_digest
from urdfinertia.errors import MeshError
from urdfinertia.mesh.limits import OVER_BUDGET_NOTE, max_mesh_bytes
from urdfinertia.rules import Rule

#: the codes an error entry may carry (an entry with another is not this version's)
_RULE_CODES = frozenset(r.value for r in Rule)

if TYPE_CHECKING:
    import numpy as np

    from urdfinertia.mesh.solids import MeshSolids

# numpy and the solids types are imported where entries are encoded or decoded: a warm run
# that reuses whole-file results computes keys only.

CACHE_FORMAT = "urdfinertia-solids-cache/3"
"""Layout of one entry file; a different layout is a foreign entry."""
MAGIC = b"URDFINERTIA-SOLIDS\n"
SUBDIR = "solids-v2"
"""Sub-folder of the cache directory holding the entries (nothing outside it is touched)."""
FILES_SUBDIR = "files-v1"
"""Sub-folder of whole-file results (`urdfinertia.batch.file_cache`)."""
DIGESTS_FILE = "digests-v1.json"
SIZE_FILE = "size-v1.json"
"""Bytes of entries counted by the last `SolidsCache.prune` (lets a run that wrote nothing
skip the scan of every entry).
"""
SIZE_FORMAT = "urdfinertia-cache-size/1"
ENV_VAR = "URDFINERTIA_CACHE_DIR"
DEFAULT_MAX_BYTES = 512 * 1024 * 1024
"""Default size bound of the cache folder, bytes."""
MAX_ENTRY_BYTES = 16 * 1024 * 1024
"""Largest entry file read (a real entry is a few kB)."""
SEAL_BYTES = 32
"""Length of the BLAKE2b digest that ends every entry file."""
_ARRAYS = ("volume", "first", "second")
T = TypeVar("T")
_ERROR_KEYS = {"format", "key", "faces", "solid_fields", "mesh_fields", "error", "code"}


def too_many_faces(path: Path, faces: int, max_faces: int) -> MeshError:
    """The error `load_mesh` raises, for a cache hit over the limit."""
    return MeshError(f"mesh {path} has {faces} faces, more than the limit "
                     f"{max_faces} (raise it with --max-faces, in Python max_faces=)",
                     rule=Rule.MESH_TOO_LARGE)


def cacheable(outcome: object, path: Path) -> bool:
    """Solids, or a repair error that depends on the bytes only (names no path).

    Solids repaired past the time budget (fans only) are not: another run may have the
    time for the refined caps.
    """
    if isinstance(outcome, MeshError):
        return (outcome.file is None and str(path) not in outcome.cause
                and path.name not in outcome.cause)
    notes = getattr(outcome, "notes", ())
    return (not isinstance(outcome, Exception)
            and not any(n.startswith(OVER_BUDGET_NOTE) for n in notes))


def default_cache_dir() -> Path:
    """`$URDFINERTIA_CACHE_DIR` if set, else the platform's user cache folder."""
    env = os.environ.get(ENV_VAR)
    if env:
        return Path(env).expanduser()
    import platformdirs

    return Path(platformdirs.user_cache_dir("urdfinertia"))


def entry_key(data: bytes, suffix: str) -> str:
    """Cache key of a mesh file with content `data` and file suffix `suffix`."""
    return key_from_digest(content_digest(data), suffix)


def key_from_digest(digest: str, suffix: str) -> str:
    """The cache key of a mesh file with content digest `digest`.

    Parameters
    ----------
    digest : str
        `content_digest` of the file.
    suffix : str
        Its suffix (the reader depends on it).

    Returns
    -------
    str
        A key that changes with the cache format and the code that computes.
    """
    head = "\0".join((CACHE_FORMAT, code_digest(),
                      suffix.lower(), digest))
    return hashlib.blake2b(head.encode(), digest_size=20).hexdigest()


def file_entry_key(path: Path, max_bytes: int, digests: FileDigests | None = None,
                   ) -> str | None:
    """`entry_key` of the file at `path` (its digest from `digests` if known).

    None (do not use the cache; the reader reports the problem) for anything but a regular
    file of at most `max_bytes` bytes: a FIFO or a huge file is never read here.
    """
    digest = (digests.digest(path, max_bytes) if digests is not None
              else file_digest(path, max_bytes))
    return None if digest is None else key_from_digest(digest, path.suffix)


class SolidsCache:
    """A folder of cache entries with a size bound.

    Problems with the folder itself (not writable, full disk) never fail a run: the cache
    turns itself off and says why in `warnings`.
    """

    def __init__(self, root: str | Path | None = None,
                 max_bytes: int = DEFAULT_MAX_BYTES) -> None:
        self.root = Path(root) if root is not None else default_cache_dir()
        self.folder = self.root / SUBDIR
        self.files_folder = self.root / FILES_SUBDIR
        #: content digests of mesh files by stat signature (:mod:`urdfinertia.cache.digests`)
        self.digests = FileDigests(self.root / DIGESTS_FILE)
        self.max_bytes = int(max_bytes)
        self.enabled = True
        self.warnings: list[str] = []
        self.hits = 0
        self.misses = 0
        self.written = 0

    def path(self, key: str) -> Path:
        """The entry file of `key`.

        Parameters
        ----------
        key : str
            A cache key.

        Returns
        -------
        Path
            Where its entry is stored.
        """
        return self.folder / key[:2] / f"{key}.entry"

    def get(self, key: str) -> tuple[MeshSolids | MeshError, int] | None:
        """The solids (or the repair's error) and face count under `key`, or None.

        None means absent or invalid: the caller recomputes.
        """
        return self.read(self.path(key), lambda data: decode_entry(data, key))

    def put(self, key: str, outcome: MeshSolids | MeshError, faces: int) -> None:
        """Store an entry atomically (temporary file + rename); skipped when not encodable."""
        try:
            data = encode_entry(outcome, faces, key)
        except (TypeError, ValueError):
            return  # a field this format cannot hold: simply not cached
        self.write(self.path(key), data)

    # --- the one lookup protocol of mesh solids (MeshLibrary and batch runs both use it) --
    def lookup_mesh(self, path: Path, max_faces: int,
                    ) -> tuple[str | None, MeshSolids | MeshError | None]:
        """`(key, outcome)` of the mesh file at `path`; outcome None on a miss.

        The key is None when the file is not a readable regular file within the size
        limit (the reader then says why). A hit over `max_faces` is the reader's own
        refusal: the cache never changes what is accepted.
        """
        if not self.enabled:
            return None, None
        key = file_entry_key(path, max_mesh_bytes(max_faces), self.digests)
        if key is None:
            return None, None
        hit = self.get(key)
        if hit is None:
            return key, None
        found, faces = hit
        if faces > max_faces:
            return key, too_many_faces(path, faces, max_faces)
        return key, found

    def lookup_arrays(self, path: Path, max_faces: int, kind: str,
                      ) -> tuple[str | None, tuple[dict, np.ndarray] | MeshError | None]:
        """`(key, (header, numbers))` of an entry derived from the mesh at `path`
        other than its solids (`kind`: "points", "view-N", see `MeshLibrary`);
        None on a miss (key None: the file is not cacheable), a refusal over
        `max_faces`."""
        if not self.enabled:
            return None, None
        key = file_entry_key(path, max_mesh_bytes(max_faces), self.digests)
        if key is None:
            return None, None
        hit = self.read(self.arrays_path(key, kind),
                        lambda data: decode_arrays(data, key, kind))
        if hit is None:
            return key, None
        if hit[0]["faces"] > max_faces:
            return key, too_many_faces(path, hit[0]["faces"], max_faces)
        return key, hit

    def store_arrays(self, key: str | None, kind: str, header: dict,
                     numbers: np.ndarray) -> None:
        """Keep `numbers` with `header` (which holds the file's face count,
        `"faces"`) under `key` and `kind`."""
        if key is not None:
            self.write(self.arrays_path(key, kind), pack(
                {**header, "format": CACHE_FORMAT, "kind": kind, "key": key},
                numbers.reshape(-1)))

    def arrays_path(self, key: str, kind: str) -> Path:
        """The file of an entry's arrays of one `kind` (hull points, display copies).

        Parameters
        ----------
        key : str
            A cache key.
        kind : str
            What the arrays are.

        Returns
        -------
        Path
            Where they are stored.
        """
        return self.folder / key[:2] / f"{key}.{kind}.entry"  # pruned like the others

    def store_mesh(self, key: str | None, path: Path, outcome: MeshSolids | Exception,
                   faces: int) -> None:
        """Keep `outcome` under `key` when it depends on the file's bytes alone.

        `faces` > 0 says the mesh was read, so an error came from the repair of its bytes.
        """
        if key is not None and faces > 0 and cacheable(outcome, path):
            self.put(key, outcome, faces)  # type: ignore[arg-type]  # cacheable narrows

    def read(self, path: Path, decode: Callable[[bytes], T | None],
             count: bool = True) -> T | None:
        """`decode` of the entry file at `path`; None when absent, corrupt or foreign.

        `count`: add the lookup to `hits` / `misses` (mesh entries).
        """
        if not self.enabled:
            return None
        try:
            raw = read_entry_file(path)
            found = None if raw is None else decode(raw)
        except Exception:  # noqa: BLE001 - a corrupt entry (bad header, JSON, ...) is a miss
            found = None
        if found is None:
            self.misses += count
            _remove_entry(path)
            return None
        self.hits += count
        try:
            os.utime(path)  # least recently *used* goes first
        except OSError:
            pass
        return found

    def write(self, path: Path, data: bytes, count: bool = True) -> None:
        """Write an entry file atomically, sealed (`seal`); a folder that cannot be
        written turns caching off.

        `count`: add the bytes to `written` (entries; not bookkeeping files).
        """
        data = seal(path.name, data)
        if not self.enabled or len(data) > MAX_ENTRY_BYTES:
            return
        try:
            path.parent.mkdir(parents=True, exist_ok=True)
            replace_file(path, data, durable=False)
        except OSError as exc:
            self.enabled = False
            self.warnings.append(f"cache disabled: cannot write {self.root}: "
                                 f"{exc.strerror or exc}")
            return
        if count:
            self.written += len(data)

    def entries(self) -> list[tuple[Path, int, float]]:
        """(path, size in bytes, mtime) of every entry file."""
        return self._scan()[0]

    def _scan(self) -> tuple[list[tuple[Path, int, float]], list[str]]:
        """Entry files (`??/*.entry`) with size and mtime, and temporary files
        (`??/.*.tmp`) of both entry folders (`os.scandir`: pathlib's glob cost a warm
        run more than reading the entries)."""
        entries: list[tuple[Path, int, float]] = []
        temporary: list[str] = []
        for folder in (self.folder, self.files_folder):
            for sub in _scandir(folder):
                if len(sub.name) != 2 or not _is_dir(sub):
                    continue
                for item in _scandir(sub.path):
                    name = item.name
                    if name.endswith(".entry"):
                        try:
                            st = item.stat()
                        except OSError:
                            continue
                        entries.append((Path(item.path), st.st_size, st.st_mtime))
                    elif name.startswith(".") and name.endswith(".tmp") and len(name) >= 5:
                        temporary.append(item.path)
        return entries, temporary

    def size(self) -> int:
        """The bytes the cache's entries take.

        Returns
        -------
        int
            Their total size.
        """
        return sum(size for _, size, _ in self.entries())

    def prune(self, max_bytes: int | None = None) -> int:
        """Delete least recently used entries until the folder holds at most `max_bytes`.

        Also removes temporary files left by killed runs. Returns the bytes freed.

        A run that wrote no entry skips the scan when the size the last prune counted
        (`SIZE_FILE`, written by every scan) is within the bound: hits do not grow
        the folder. Missing or unreadable, the count is taken again.
        """
        limit = self.max_bytes if max_bytes is None else int(max_bytes)
        if self.enabled:
            self.digests.save()
        if self.written == 0:
            known = self._counted_size()
            if known is not None and known <= limit:
                return 0
        freed = 0
        now = time.time()
        found, temporary = self._scan()
        for tmp in temporary:
            try:
                if now - os.stat(tmp).st_mtime > 3600:
                    os.unlink(tmp)
            except OSError:
                pass
        entries = sorted(found, key=lambda e: (e[2], e[0].name))
        total = sum(size for _, size, _ in entries)
        for path, size, _ in entries:
            if total <= limit:
                break
            try:
                path.unlink()
            except OSError:
                continue
            total -= size
            freed += size
        self._save_counted_size(total)
        return freed

    def _counted_size(self) -> int | None:
        try:
            raw = read_entry_file(self.root / SIZE_FILE)
            doc = json.loads(raw.decode("utf-8")) if raw is not None else None
        except (OSError, ValueError):
            return None
        if not (isinstance(doc, dict) and doc.get("format") == SIZE_FORMAT):
            return None
        size = doc.get("bytes")
        return size if isinstance(size, int) and not isinstance(size, bool) else None

    def _save_counted_size(self, total: int) -> None:
        if not self.enabled or not self.folder.parent.is_dir():
            return
        self.write(self.root / SIZE_FILE,
                   json.dumps({"format": SIZE_FORMAT, "bytes": int(total)}).encode(),
                   count=False)


def seal(name: str, data: bytes) -> bytes:
    """`data` followed by its seal: a BLAKE2b digest of the entry's file `name` and `data`.

    The name holds the key, so an entry copied under another key, a flipped bit or
    rescaled numbers all break the seal.
    """
    h = hashlib.blake2b(name.encode("utf-8") + b"\0", digest_size=SEAL_BYTES)
    h.update(data)
    return data + h.digest()


def unseal(name: str, data: bytes) -> bytes | None:
    """The bytes `seal` wrapped, or None when the seal does not match."""
    body = data[:-SEAL_BYTES]
    if len(data) < SEAL_BYTES or not hmac.compare_digest(seal(name, body), data):
        return None
    return body


def read_entry_file(path: Path) -> bytes | None:
    """The unsealed bytes of the entry file at `path`; None when it is absent, not a
    regular file (opened without following a link or blocking on a FIFO), larger than
    `MAX_ENTRY_BYTES` or not sealed for its name."""
    try:
        fd = os.open(path, os.O_RDONLY | os.O_NOFOLLOW | os.O_NONBLOCK
                     | getattr(os, "O_BINARY", 0))
    except OSError:
        return None
    with os.fdopen(fd, "rb") as fh:
        info = os.fstat(fd)
        if not stat.S_ISREG(info.st_mode) or info.st_size > MAX_ENTRY_BYTES:
            return None
        data = fh.read(MAX_ENTRY_BYTES + 1)
    if len(data) > MAX_ENTRY_BYTES:
        return None
    return unseal(path.name, data)


def _remove_entry(path: Path) -> None:
    """Remove a bad entry (a link or FIFO itself, never what it points to); absent or
    a folder is left alone."""
    try:
        os.unlink(path)
    except OSError:
        pass


def _scandir(folder: str | Path) -> list[os.DirEntry]:
    try:
        with os.scandir(folder) as it:
            return list(it)
    except OSError:
        return []


def _is_dir(entry: os.DirEntry) -> bool:
    try:
        return entry.is_dir()
    except OSError:
        return False


def _plain(value: Any) -> Any:
    """A JSON-ready copy of a text/number field, or TypeError."""
    import numpy as np

    if value is None or isinstance(value, (str, bool, int, float)):
        return value
    if isinstance(value, (np.floating, np.integer)):
        return value.item()
    if isinstance(value, (tuple, list)):
        return [_plain(v) for v in value]
    raise TypeError(f"cannot store {type(value).__name__} in a cache header")


def _tuples(value: Any) -> Any:
    """JSON lists back to the tuples the dataclasses hold."""
    if isinstance(value, list):
        return tuple(_tuples(v) for v in value)
    return value


def _field_names(cls: type) -> list[str]:
    return [f.name for f in dataclasses.fields(cls)]


def pack(header: dict, numbers: np.ndarray) -> bytes:
    """Entry bytes: magic line, header length (uint32 LE), JSON header, float64 LE numbers."""
    import numpy as np

    head = json.dumps(header, allow_nan=False).encode()
    body = np.ascontiguousarray(numbers, dtype="<f8").tobytes()
    return MAGIC + len(head).to_bytes(4, "little") + head + body


def unpack(data: bytes) -> tuple[dict, np.ndarray]:
    """Header and numbers of an entry; ValueError when the bytes are not one."""
    import numpy as np

    if not data.startswith(MAGIC):
        raise ValueError("not a cache entry")
    pos = len(MAGIC)
    size = int.from_bytes(data[pos:pos + 4], "little")
    head = data[pos + 4:pos + 4 + size]
    body = data[pos + 4 + size:]
    if len(head) != size or len(body) % 8:
        raise ValueError("truncated cache entry")
    header = json.loads(head.decode("utf-8"))
    if not isinstance(header, dict):
        raise ValueError("cache header is not an object")
    return header, np.frombuffer(body, dtype="<f8").astype(np.float64)


def encode_entry(outcome: MeshSolids | MeshError, faces: int, key: str) -> bytes:
    """The bytes of one entry: solids, or the repair's error message for a mesh it rejects."""
    import numpy as np

    from urdfinertia.mesh.solids import MeshSolids, Solid

    header: dict[str, Any] = {"format": CACHE_FORMAT, "key": key, "faces": int(faces),
                              "solid_fields": _field_names(Solid),
                              "mesh_fields": _field_names(MeshSolids)}
    if isinstance(outcome, MeshError):
        header["error"] = str(outcome.cause)
        header["code"] = str(outcome.code)
        return pack(header, np.zeros(0))
    solids = outcome.solids
    numbers = [np.array([float(s.volume) for s in solids], dtype=np.float64)]
    numbers += [np.asarray(s.first, dtype=np.float64).reshape(3) for s in solids]
    numbers += [np.asarray(s.second, dtype=np.float64).reshape(9) for s in solids]
    header["mesh"] = {n: _plain(getattr(outcome, n)) for n in _field_names(MeshSolids)
                      if n != "solids"}
    header["solids"] = [{n: _plain(getattr(s, n)) for n in _field_names(Solid)
                         if n not in _ARRAYS} for s in solids]
    return pack(header, np.concatenate(numbers))


def decode_entry(data: bytes, key: str) -> tuple[MeshSolids | MeshError, int] | None:
    """Validate and rebuild an entry; None for anything foreign, stale or corrupt."""
    import numpy as np

    from urdfinertia.mesh.solids import MeshSolids, Solid

    header, numbers = unpack(data)
    if header.get("format") != CACHE_FORMAT or header.get("key") != key:
        return None  # another layout, or copied/renamed from elsewhere
    if header.get("solid_fields") != _field_names(Solid):
        return None
    if header.get("mesh_fields") != _field_names(MeshSolids):
        return None
    faces = header.get("faces")
    if not (isinstance(faces, int) and not isinstance(faces, bool) and faces > 0):
        return None
    if "error" in header:
        cause, code = header["error"], header.get("code")
        if not isinstance(cause, str) or code not in _RULE_CODES or len(numbers) \
                or set(header) != _ERROR_KEYS:
            return None
        return MeshError(cause, rule=Rule(code)), faces
    extras, mesh_extra = header.get("solids"), header.get("mesh")
    if not (isinstance(extras, list) and isinstance(mesh_extra, dict)):
        return None
    k = len(extras)
    if not (k > 0 and all(isinstance(e, dict) for e in extras)) or len(numbers) != 13 * k:
        return None
    if not np.all(np.isfinite(numbers)):
        return None
    volume = numbers[:k]
    first = numbers[k:4 * k].reshape(k, 3)
    second = numbers[4 * k:].reshape(k, 3, 3)
    if not np.all(volume > 0):
        return None
    scale = np.abs(second).max(axis=(1, 2), initial=0.0)
    if np.any(np.abs(second - second.transpose(0, 2, 1)).max(axis=(1, 2)) > 1e-9 * scale):
        return None
    out = []
    for i, extra in enumerate(extras):
        fields = {n: _tuples(v) for n, v in extra.items()}
        if set(fields) | set(_ARRAYS) != set(_field_names(Solid)):
            return None
        out.append(Solid(volume=float(volume[i]), first=first[i].copy(),
                         second=second[i].copy(), **fields))
    mesh_fields = {n: _tuples(v) for n, v in mesh_extra.items()}
    if set(mesh_fields) | {"solids"} != set(_field_names(MeshSolids)):
        return None
    return MeshSolids(solids=tuple(out), **mesh_fields), faces


def decode_arrays(data: bytes, key: str, kind: str) -> tuple[dict, np.ndarray] | None:
    """Header and numbers of an entry of `kind` for `key`; None when it is not one
    (the caller checks the numbers' shapes)."""
    import numpy as np

    header, numbers = unpack(data)
    if (header.get("format") != CACHE_FORMAT or header.get("kind") != kind
            or header.get("key") != key or not isinstance(header.get("faces"), int)
            or not len(numbers) or not np.all(np.isfinite(numbers))):
        return None
    return header, numbers
