"""Resolve, read and integrate each mesh file once per run (and once ever, with a cache)."""

from __future__ import annotations

import copy
import math
import weakref
from collections.abc import Callable, Mapping
from pathlib import Path

import numpy as np

from urdfinertia.cache.store import DEFAULT_MAX_BYTES, SolidsCache, cacheable
from urdfinertia.descriptions.paths import RealPaths, resolve_mesh_path
from urdfinertia.errors import MeshError
from urdfinertia.inertia.polyhedron import used_vertices
from urdfinertia.mesh.limits import DEFAULT_MAX_FACES
from urdfinertia.mesh.read.load import TriangleMesh, load_mesh
from urdfinertia.mesh.repair.graph import first_occurrences
from urdfinertia.mesh.repair.pipeline import repair_mesh
from urdfinertia.mesh.solids import MeshSolids, integrate_repaired
from urdfinertia.rules import Rule
from urdfinertia.timing import StageTimes


def integrate_mesh(mesh: TriangleMesh, timer: StageTimes | None = None) -> MeshSolids:
    """Repair and integrate `mesh`, timing repair, boolean unions and integration apart."""
    timer = timer if timer is not None else StageTimes()
    unions = StageTimes()
    with timer.stage("repair"):
        repaired = repair_mesh(mesh, unions)
    timer.add("repair", -unions.get("union"))  # counted on its own below
    timer.merge(unions)
    with timer.stage("integration"):
        return integrate_repaired(repaired)


def mesh_file_solids(path: Path, max_faces: int = DEFAULT_MAX_FACES,
                     cache: SolidsCache | None = None,
                     timer: StageTimes | None = None,
                     read: Callable[[Path, int], TriangleMesh] | None = None) -> MeshSolids:
    """Unscaled solids of one mesh file, from `cache` when it holds them (`read`
    reads the file otherwise).

    Raises
    ------
    MeshError
        The file cannot be read, parsed or integrated, or has more than `max_faces`
        faces (also on a cache hit: the cache never changes what is accepted).
    """
    timer = timer if timer is not None else StageTimes()
    key = None
    if cache is not None:
        with timer.stage("cache"):
            key, hit = cache.lookup_mesh(path, max_faces)
        if isinstance(hit, MeshError):
            raise MeshError(hit.cause, rule=hit.rule)
        if hit is not None:
            return hit
    try:
        with timer.stage("mesh read"):
            mesh = (read or load_mesh)(path, max_faces)
    except MemoryError:
        raise _out_of_memory(path, "reading") from None
    try:
        found: MeshSolids | MeshError = integrate_mesh(mesh, timer)
    except MeshError as exc:
        found = exc
    except MemoryError:  # this mesh's error, the rest of the run goes on (never cached)
        found = _out_of_memory(path, f"repairing its {len(mesh.faces)} faces")
    if cache is not None:
        with timer.stage("cache"):
            cache.store_mesh(key, path, found, len(mesh.faces))
    if isinstance(found, MeshError):
        raise found
    return found


def _out_of_memory(path: Path, doing: str) -> MeshError:
    """A mesh that ran the process out of memory, as that mesh's error (with its path:
    a run out of memory named no file). Not a property of its bytes alone."""
    return MeshError(f"mesh {path}: out of memory {doing} (a smaller --max-faces refuses "
                     "large meshes before reading them)", rule=Rule.MESH_TOO_LARGE)


#: ``reduce(vertices, faces, max_faces) -> (vertices, faces, how)`` of
#: :meth:`MeshLibrary.display`.
Reducer = Callable[[np.ndarray, np.ndarray, int], tuple[np.ndarray, np.ndarray, str]]
"""`reduce(vertices, faces, max_faces) -> (vertices, faces, how)` of `MeshLibrary.display`.
"""


STASH_FACES = 300_000
"""A mesh read for one entry (its hull points, say) is kept for the next (its solids) while the
meshes kept hold at most this many faces in all (about 40 bytes a face).
"""


def points_of(mesh: TriangleMesh) -> np.ndarray:
    """The `MeshLibrary.points` of `mesh`: its used vertices' hull vertices."""
    return hull_points(mesh.vertices[used_vertices(len(mesh.vertices), mesh.faces)])


def points_entry(mesh: TriangleMesh) -> tuple[dict, np.ndarray]:
    """The "points" cache entry of `mesh`: its header (`points_header`) and its
    `points_of`."""
    points = points_of(mesh)
    return points_header(points), points


def points_header(points: np.ndarray) -> dict:
    """What a "points" cache entry records besides the points: the volume of their convex
    hull (`unit_hull_volume`), so that a warm run needs no Qhull (nor scipy)."""
    return {"volume": unit_hull_volume(points)}


def unit_hull_volume(points: np.ndarray) -> float | None:
    """Volume of the convex hull of `points` (n, 3); None when they span no volume.

    A mesh scaled by `(sx, sy, sz)` has the hull of its points scaled likewise, whose
    volume is this one times `|sx sy sz|` (`MeshLibrary.hull_volume`): the hull is
    computed once per mesh, not per scale, and kept in the cache with the points.
    """
    from scipy.spatial import ConvexHull, QhullError

    try:
        return float(ConvexHull(np.asarray(points, dtype=np.float64).reshape(-1, 3)).volume)
    except (QhullError, ValueError):
        return None


def _stored_volume(header: dict) -> tuple[bool, float | None]:
    """(found, unit hull volume) of a "points" entry's header (entries written before
    the volume was kept have none: it is then computed from the points)."""
    if "volume" not in header:
        return False, None
    volume = header["volume"]
    if volume is None:
        return True, None
    if isinstance(volume, float) and volume >= 0:
        return True, volume
    return False, None


def hull_points(points: np.ndarray) -> np.ndarray:
    """The vertices of the convex hull of `points` (n, 3), in input order; all of
    `points` when they span no volume (flat, collinear) or are few."""
    points = np.asarray(points, dtype=np.float64)
    if len(points) <= 64:
        return points
    from scipy.spatial import ConvexHull, QhullError

    # a triangle soup (STL, many COLLADA exports) repeats each vertex several times:
    # Qhull is several times faster on the distinct points, and the hull is the same
    distinct = first_occurrences(points)
    try:
        # the extreme points of every direction are hull vertices: with no merging of
        # nearly coplanar facets ("Q" options off), none of them is dropped
        hull = ConvexHull(points[distinct], qhull_options="Qt")
        return points[np.sort(distinct[hull.vertices])]
    except (QhullError, ValueError):
        return points


def display_entry(mesh: TriangleMesh, max_faces: int, reduce: Reducer,
                  ) -> tuple[dict, np.ndarray]:
    """The cache entry of `MeshLibrary.display` made from `mesh`: a header (how it
    was reduced, its vertex count, the file's face count) and its numbers (vertices, then
    faces)."""
    v, f, how = reduce(mesh.vertices, mesh.faces, max_faces)
    v = np.asarray(v, dtype=np.float64)
    f = np.asarray(f, dtype=np.int64)
    return ({"method": how, "vertices": len(v), "faces": len(mesh.faces)},
            np.concatenate([v.ravel(), f.ravel()]))


def _display_kind(max_faces: int) -> str:
    return f"view-{int(max_faces)}"


def _display_valid(header: dict, numbers: np.ndarray) -> bool:
    n = header.get("vertices")
    return (isinstance(n, int) and 0 <= 3 * n <= len(numbers)
            and (len(numbers) - 3 * n) % 3 == 0
            and bool(np.all(numbers[3 * n:] < n)) and bool(np.all(numbers[3 * n:] >= 0)))


def fresh(exc: Exception) -> Exception:
    """A new exception equal to `exc` with its own attributes (context is added per use).

    `copy.copy` is not enough: libraries such as tblib (loaded by dask) change how
    exceptions reduce, and the copy may then share its `__dict__`.
    """
    new = copy.copy(exc)
    new.__dict__ = dict(exc.__dict__)
    return new


class MeshLibrary:
    """Mesh solids by URI, memoised by resolved file path for the life of the object.

    One library is shared by all links of a run, so a mesh referenced by several links
    (left and right legs, mirrored parts) is read and integrated once; a mesh that cannot
    be used fails once and its error is repeated (results and errors computed by other
    processes are handed in with `seed`). With a `SolidsCache`, results
    also persist between runs. `timer` collects the mesh stages' wall time.
    """

    def __init__(
        self,
        package_dirs: Mapping[str, Path] | None = None,
        max_faces: int = DEFAULT_MAX_FACES,
        cache: SolidsCache | None = None,
        timer: StageTimes | None = None,
    ) -> None:
        self.package_dirs = dict(package_dirs or {})
        self.max_faces = max_faces
        self.cache = cache
        self.timer = timer if timer is not None else StageTimes()
        self._memo: dict[Path, MeshSolids | Exception] = {}
        self._points: dict[Path, np.ndarray] = {}
        self._hulls: dict[tuple[Path, tuple[float, ...]], float] = {}
        #: per mesh, :func:`unit_hull_volume` of its points (None: they span no volume)
        self._volumes: dict[Path, float | None] = {}
        self._resolved: dict[tuple[str, Path], Path | MeshError] = {}
        self._records: dict[tuple[str, Path], tuple[str, str, str]] = {}
        self._real_path = RealPaths()
        self._keys: dict[Path, Path] = {}
        #: meshes read lately, by key (:data:`STASH_FACES`): the geometry checks ask for
        #: a mesh's points and then for its solids, which must not read the file twice
        self._stash: dict[Path, TriangleMesh] = {}
        #: When a list, every :meth:`resolve` appends (uri, urdf_dir, path), both resolved
        #: (path "" when the URI does not resolve): what a file's result depends on
        #: (:mod:`urdfinertia.batch.file_cache`).
        self.trace: list[tuple[str, str, str]] | None = None

    def resolve(self, uri: str, urdf_dir: Path) -> Path:
        """The file `uri` names, memoised: package lookups walk up folders and read files."""
        key = (uri, urdf_dir)
        found = self._resolved.get(key)
        if found is None:
            try:
                found = resolve_mesh_path(uri, urdf_dir, self.package_dirs)
            except MeshError as exc:
                found = exc
            self._resolved[key] = found
        if self.trace is not None:
            self.trace.append(self._record(key, found))
        if isinstance(found, MeshError):
            raise fresh(found)
        return found

    def _record(self, key: tuple[str, Path], found: Path | MeshError) -> tuple[str, str, str]:
        """The trace entry of a resolution, memoised (absolute: it must not depend on the
        working folder)."""
        record = self._records.get(key)
        if record is None:
            uri, urdf_dir = key
            record = (uri, self._real_path(urdf_dir),
                      "" if isinstance(found, MeshError) else self._real_path(found))
            self._records[key] = record
        return record

    def _key(self, path: Path) -> Path:
        """`path.resolve()`, memoised: the key of `_memo`."""
        key = self._keys.get(path)
        if key is None:
            key = self._keys[path] = Path(self._real_path(path))
        return key

    def seed(self, path: Path, outcome: MeshSolids | Exception) -> None:
        """Record a result computed elsewhere (another process) for the file at `path`."""
        self._memo[self._key(Path(path))] = outcome

    def seed_points(self, path: Path, points: np.ndarray, header: dict | None = None,
                    ) -> None:
        """Record the `points` of the file at `path` computed elsewhere, with the
        header of their cache entry (`points_header`) when there is one."""
        key = self._key(Path(path))
        self._points[key] = np.asarray(points, dtype=np.float64)
        known, volume = _stored_volume(header or {})
        if known:
            self._volumes[key] = volume

    def _read(self, key: Path, max_faces: int) -> TriangleMesh:
        """The mesh file `key`, read once while it is in the stash (kept for a later
        request: the geometry checks ask for points first, then for solids)."""
        mesh = self._stash.get(key)
        if mesh is None:
            mesh = load_mesh(key, max_faces)
            self._stash[key] = mesh
            total = sum(len(m.faces) for m in self._stash.values())
            while total > STASH_FACES and self._stash:
                total -= len(self._stash.pop(next(iter(self._stash))).faces)
        return mesh

    def _take(self, key: Path, max_faces: int) -> TriangleMesh:
        """The mesh file `key` for its solids, the last request: out of the stash, so
        no other mesh is held while it is repaired."""
        mesh = self._stash.pop(key, None)
        return mesh if mesh is not None else load_mesh(key, max_faces)

    def known(self, path: Path) -> bool:
        """Whether the solids of the mesh file at `path` are already computed.

        Parameters
        ----------
        path : Path
            A mesh file.

        Returns
        -------
        bool
            True when the library holds them.
        """
        return self._key(Path(path)) in self._memo

    def solids(self, path: Path) -> MeshSolids:
        """Unscaled solids of the mesh file at `path`."""
        key = self._key(path)
        found = self._memo.get(key)
        if found is None:
            try:
                found = mesh_file_solids(key, self.max_faces, self.cache, self.timer,
                                         self._take)
            except Exception as exc:  # noqa: BLE001 - bugs too are repeated like any failure
                found = exc
            self._memo[key] = found
        if isinstance(found, Exception):
            error = fresh(found)  # callers add context to the exception they get
            if isinstance(error, MeshError) and path.name not in error.cause:
                # the file/line context is the URDF's (added by the caller); name the mesh
                # in the cause instead
                error.cause = f"mesh {path}: {error.cause}"
                error.args = (error.cause,)
            raise error
        return found

    def points(self, path: Path) -> np.ndarray:
        """(n, 3) points of the mesh file at `path` whose bounding box, after any affine
        map (scale, rotation, shift), is that of its used vertices: the vertices of their
        convex hull (all of them when they span no volume). Kept in the persistent cache,
        so a warm `check` reads no mesh file.

        Raises
        ------
        MeshError
            As `load_mesh`.
        """
        key = self._key(path)
        found = self._points.get(key)
        if found is None:
            header, numbers, _ = self._derived(key, "points", points_entry,
                                               lambda h, x: len(x) % 3 == 0)
            found = self._points[key] = numbers.reshape(-1, 3)
            known, volume = _stored_volume(header)
            if known:
                self._volumes.setdefault(key, volume)
        return found

    def hull_volume(self, path: Path, scale: tuple[float, ...] = (1.0, 1.0, 1.0)) -> float:
        """Volume of the convex hull of the mesh at `path` scaled by `scale`, memoised
        (links and geometry candidates ask for the same mesh many times).

        Raises
        ------
        MeshError
            As `points`.
        ValueError
            When the points span no volume.
        """
        mesh = self._key(path)
        key = (mesh, tuple(float(v) for v in scale))
        found = self._hulls.get(key)
        if found is None:
            points = self.points(path)  # with the cache: the hull's volume too
            if mesh not in self._volumes:
                self._volumes[mesh] = unit_hull_volume(points)
            unit = self._volumes[mesh]
            if unit is None:
                raise ValueError(f"the points of {path} span no volume")
            found = self._hulls[key] = unit * abs(math.prod(key[1]))
        return found

    def display(self, path: Path, max_faces: int, reduce: Reducer,
                ) -> tuple[np.ndarray, np.ndarray, int, str]:
        """A display copy of the mesh file at `path`: ``reduce(vertices, faces,
        max_faces)`` (vertices, faces, how) and the file's face count, in the
        persistent cache per `max_faces`, so a warm report reads no mesh file.

        Raises
        ------
        MeshError
            As `load_mesh`.
        """
        header, numbers, faces = self._derived(
            self._key(path), _display_kind(max_faces),
            lambda mesh: display_entry(mesh, max_faces, reduce), _display_valid)
        n = header["vertices"]
        return (numbers[:3 * n].reshape(-1, 3), numbers[3 * n:].astype(np.int64).reshape(-1, 3),
                faces, str(header.get("method", "")))

    def derived(self, path: Path, kind: str,
                make: Callable[[TriangleMesh], tuple[dict, np.ndarray]],
                valid: Callable[[dict, np.ndarray], bool]) -> tuple[dict, np.ndarray]:
        """`(header, numbers)` that `make` derives from the mesh file at `path`
        (JSON-able header, float64 numbers), in the persistent cache under `kind` (a
        name safe in a file name, unique to what else `make` depends on): a warm run
        reads neither the file nor computes again. Entries `valid` rejects are remade.

        Raises
        ------
        MeshError
            As `load_mesh`, or as `make`.
        """
        header, numbers, _ = self._derived(self._key(path), kind, make, valid)
        return header, numbers

    def display_cached(self, path: Path, max_faces: int) -> bool:
        """Whether the persistent cache holds `display`'s copy of `path` for
        `max_faces` (False without a cache)."""
        if self.cache is None:
            return False
        _, hit = self.cache.lookup_arrays(self._key(path), self.max_faces,
                                          _display_kind(max_faces))
        return hit is not None and not isinstance(hit, MeshError) and _display_valid(*hit)

    def seed_display(self, path: Path, max_faces: int, header: dict,
                     numbers: np.ndarray) -> None:
        """Store in the persistent cache a `display_entry` made elsewhere (another
        process), for `display` to find; nothing without a cache."""
        if self.cache is None or not _display_valid(header, numbers):
            return
        kind = _display_kind(max_faces)
        with self.timer.stage("cache"):
            entry, _ = self.cache.lookup_arrays(self._key(path), self.max_faces, kind)
            self.cache.store_arrays(entry, kind, header, numbers)

    def _derived(self, key: Path, kind: str,
                 make: Callable[[TriangleMesh], tuple[dict, np.ndarray]],
                 valid: Callable[[dict, np.ndarray], bool],
                 ) -> tuple[dict, np.ndarray, int]:
        """`(header, numbers, file face count)` of the entry `kind` derived from the
        mesh file `key` by `make`: from the cache when `valid` accepts it (anything
        else is recomputed), or made and stored."""
        entry = None
        if self.cache is not None:
            with self.timer.stage("cache"):
                entry, hit = self.cache.lookup_arrays(key, self.max_faces, kind)
            if isinstance(hit, MeshError):
                raise MeshError(hit.cause)
            if hit is not None and valid(*hit):
                header, numbers = hit
                return header, numbers, int(header["faces"])
        with self.timer.stage("mesh read"):
            mesh = self._read(key, self.max_faces)
        header, numbers = make(mesh)
        header = {**header, "faces": len(mesh.faces)}
        if self.cache is not None:
            with self.timer.stage("cache"):
                self.cache.store_arrays(entry, kind, header, numbers)
        return header, numbers, len(mesh.faces)

    def failed_for_bytes_only(self, trace: list[tuple[str, str, str]]) -> bool:
        """True when every mesh of `trace` (see `trace`) has an outcome that
        depends on its bytes alone (`cacheable`: no failure for another reason, no
        repair cut short by the time budget): a file's result then depends on its inputs
        alone."""
        for _, _, path in trace:
            if path:
                found = self._memo.get(Path(path))
                if found is not None and not cacheable(found, Path(path)) and not (
                        isinstance(found, MeshError) and found.of_bytes):
                    return False
        return True


def mesh_library(package_dirs: Mapping[str, Path] | None = None,
                 max_faces: int = DEFAULT_MAX_FACES, *, use_cache: bool = True,
                 cache_dir: Path | None = None,
                 cache_max_bytes: int = DEFAULT_MAX_BYTES) -> MeshLibrary:
    """The mesh library of a command: every command builds its library here.

    It reads and fills the persistent mesh cache (`cache_dir`, default
    `default_cache_dir`) unless `use_cache` is False, so
    `check`, `compare`, `explain` and `report` reuse what `fix` (or an earlier
    run of any of them) computed. The cache is kept within `cache_max_bytes` when the
    library is discarded (least recently used entries go first).
    """
    cache = SolidsCache(cache_dir, cache_max_bytes) if use_cache else None
    library = MeshLibrary(package_dirs, max_faces, cache)
    if cache is not None:
        weakref.finalize(library, cache.prune)
    return library
