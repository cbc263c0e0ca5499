"""Fix many URDFs in one run: inputs, worker processes or a Dask cluster, one outcome each.

The unit of work is one file (:func:`fix_file_task`, which calls :func:`fix.fix_robot`).
With workers, each distinct mesh file is first read and integrated exactly once (largest
first, results from the persistent cache when it has them), then every URDF is fixed by a
worker with its meshes' results handed over. The parent process alone reads and writes the
cache and writes the outputs, so results do not depend on the number of workers, on the
cache or on the engine. One file's failure is recorded and the run goes on.
"""

from __future__ import annotations

import concurrent.futures as cf
import dataclasses
import hashlib
import time
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING

from urdfinertia.atomic import atomic_write_bytes, write_in_place
from urdfinertia.batch.executors import open_executor, submit
from urdfinertia.batch.file_cache import CachedResult, FileResults
from urdfinertia.batch.inputs import FileJob
from urdfinertia.cache.store import DEFAULT_MAX_BYTES, SolidsCache, file_entry_key
from urdfinertia.errors import MeshError, OutputError, UrdfInertiaError
from urdfinertia.link.options import FixOptions
from urdfinertia.mesh.limits import max_mesh_bytes
from urdfinertia.timing import StageTimes

if TYPE_CHECKING:
    from urdfinertia.cache.library import MeshLibrary
    from urdfinertia.mesh.solids import MeshSolids

# What reads, repairs and integrates (numpy, lxml, the mesh readers) is imported by the
# functions that compute: a warm run, whose every file comes from the cache, needs none of it.

#: Threads writing the outputs of a run whose every file came from the cache: each write
#: waits for its fsyncs, which overlap in threads.
WRITER_THREADS = 8


def _load_compute_modules() -> None:
    """Import what computes (numpy, lxml, the mesh readers) before any stage is timed, so
    that stage times do not include imports."""
    import urdfinertia.cache.library
    import urdfinertia.descriptions.urdf.read
    import urdfinertia.descriptions.urdf.write
    import urdfinertia.link.assemble
    import urdfinertia.link.parts  # noqa: F401


#: progress(kind, done, total) with kind "meshes" or "files".
ProgressHook = Callable[[str, int, int], None]


@dataclass(frozen=True)
class BatchSettings:
    """How to run: workers, cache and engine.

    jobs : worker processes (1: everything in this process).
    cache_dir : None for :func:`cache.default_cache_dir`.
    cache_max_bytes : size bound of the cache folder.
    dask : address of a Dask scheduler; overrides ``jobs``.
    in_place : write results over the sources (with ``.bak``) instead of ``FileJob.output``.
    details : keep per-link JSON-ready results (``--json``).
    """

    jobs: int = 1
    use_cache: bool = True
    cache_dir: Path | None = None
    cache_max_bytes: int = DEFAULT_MAX_BYTES
    dask: str | None = None
    in_place: bool = False
    details: bool = False
    #: keep relative mesh references as written when the output is in another folder
    keep_mesh_paths: bool = False

    def __post_init__(self) -> None:
        if self.jobs < 1:
            raise ValueError("jobs must be at least 1")

    def open_cache(self) -> SolidsCache | None:
        if not self.use_cache:
            return None
        return SolidsCache(self.cache_dir, self.cache_max_bytes)


@dataclass(frozen=True, eq=False)
class FileOutcome:
    """What happened to one file. ``error`` is one line; ``document`` is the fixed URDF."""

    source: Path
    output: Path | None = None
    robot: str = ""
    links: int = 0
    recomputed: int = 0
    changed: bool = False
    warnings: tuple[str, ...] = ()
    document: bytes | None = None
    details: dict | None = None
    error: str | None = None
    times: StageTimes = field(default_factory=StageTimes)
    #: (uri, urdf folder, resolved path) of every mesh used, and a digest of the source
    #: bytes the result was computed from: what a whole-file cache entry depends on.
    trace: tuple[tuple[str, str, str], ...] = ()
    source_digest: str = ""
    #: The error, or the links left as they were, depend on the source bytes and the
    #: traced meshes alone (its XML, a URI that does not resolve, a mesh rejected for its
    #: bytes, not a permission): the outcome may be cached.
    reusable_error: bool = False
    #: one line per link left as it was, and per problem read past
    left: tuple[str, ...] = ()
    problems: tuple[str, ...] = ()
    #: relative mesh references rewritten for the output's folder
    rewritten: int = 0


@dataclass(frozen=True, eq=False)
class BatchReport:
    outcomes: tuple[FileOutcome, ...]
    times: StageTimes
    meshes: int  # distinct mesh files read or found in the cache
    cache_hits: int = 0  # mesh entries
    cache_misses: int = 0
    warnings: tuple[str, ...] = ()
    file_hits: int = 0  # files whose whole result came from the cache

    @property
    def failed(self) -> tuple[FileOutcome, ...]:
        return tuple(o for o in self.outcomes if o.error is not None)


def referenced_meshes(source: Path, options: FixOptions) -> list[Path]:
    """Resolved mesh files the geometry policy will read for ``source`` (best effort).

    Problems are ignored here: the file's own task reports them in context.
    """
    from urdfinertia.descriptions.formats import read_description
    from urdfinertia.descriptions.model import Mesh
    from urdfinertia.descriptions.paths import resolve_mesh_path
    from urdfinertia.link.options import select_geometry

    try:
        robot, _ = read_description(source)
    except UrdfInertiaError:
        return []
    out: dict[Path, None] = {}
    for link in robot.links:
        _, refs = select_geometry(link, options.geometry)
        for ref in refs:
            if isinstance(ref.shape, Mesh):
                try:
                    path = resolve_mesh_path(ref.shape.filename, source.parent,
                                             options.package_dirs)
                except UrdfInertiaError:
                    continue
                out[path.resolve()] = None
    return list(out)


# ---------------------------------------------------------------------------- work units

def mesh_task(path: str, max_faces: int) -> tuple[MeshSolids | Exception, int, StageTimes]:
    """Read and integrate one mesh file: (solids or the error, face count, stage times).

    The error is returned, not raised, so that each file using the mesh repeats it exactly
    as a single-process run would.
    """
    from urdfinertia.cache import library as meshlib

    _load_compute_modules()
    times = StageTimes()
    faces = 0
    try:
        with times.stage("mesh read"):
            mesh = meshlib.load_mesh(path, max_faces)
        faces = len(mesh.faces)
        return meshlib.integrate_mesh(mesh, times), faces, times
    except Exception as exc:  # noqa: BLE001 - reported per file by fix_with_library
        return exc, faces, times


def fix_with_library(source: Path, options: FixOptions, meshes: MeshLibrary,
                     details: bool = False) -> FileOutcome:
    """Fix one file with ``meshes``; any failure becomes the outcome's one-line error."""
    from urdfinertia.descriptions.formats import read_bytes, robot_from_bytes
    from urdfinertia.link.fix import fix_robot

    times = StageTimes()
    before = dict(meshes.timer.seconds)
    start = time.perf_counter()
    meshes.trace = []
    digest = ""
    step = "read"
    try:
        with times.stage("xml"):
            data = read_bytes(source)
            digest = hashlib.blake2b(data, digest_size=20).hexdigest()
            step = "parse"
            robot = robot_from_bytes(data, source)
        step = "fix"
        result = fix_robot(robot, data, options, meshes)
        step = "report"
        info = None
        if details:
            from urdfinertia.render.results_json import fix_result_dict

            info = fix_result_dict(result)
        warnings = tuple(f"{r.name}: {w}" for r in result.links for w in r.warnings)
        done = {"dropped": "element dropped", "ignored": "value ignored",
                "lenient": "read leniently"}
        outcome = FileOutcome(
            source, robot=robot.name, links=len(result.links),
            recomputed=sum(r.status == "recomputed" for r in result.links),
            changed=result.changed, warnings=warnings, document=result.output,
            details=info, times=times, trace=tuple(meshes.trace), source_digest=digest,
            left=tuple(str(result.left_error(r)) for r in result.left),
            problems=tuple(f"{p.describe(result.path)} ({done[p.kind]})"
                           for p in result.problems),
            reusable_error=meshes.failed_for_bytes_only(meshes.trace))
    except UrdfInertiaError as exc:
        # reading can fail for the environment (permissions); parsing and fixing for the
        # inputs, unless a mesh failed for more than its bytes (a read error, say)
        reusable = step in ("parse", "fix") and meshes.failed_for_bytes_only(meshes.trace)
        outcome = FileOutcome(source, error=str(exc), times=times, trace=tuple(meshes.trace),
                              source_digest=digest, reusable_error=reusable)
    except Exception as exc:  # noqa: BLE001 - a bug on one file must not end a batch
        outcome = FileOutcome(source, error=f"{source}: internal error: "
                                            f"{type(exc).__name__}: {exc}", times=times)
    meshes.trace = None
    mesh_time = 0.0
    for name, seconds in meshes.timer.seconds.items():
        delta = seconds - before.get(name, 0.0)
        if delta > 0:
            times.add(name, delta)
            mesh_time += delta
    times.add("assemble", time.perf_counter() - start - times.get("xml") - mesh_time)
    return outcome


def fix_file_task(source: str, options: FixOptions,
                  seeds: Mapping[str, MeshSolids | Exception],
                  details: bool = False) -> FileOutcome:
    """The per-file unit of work run by a worker: ``seeds`` are its meshes' results."""
    from urdfinertia.cache.library import MeshLibrary

    _load_compute_modules()
    meshes = MeshLibrary(options.package_dirs, options.max_faces)
    for path, outcome in seeds.items():
        meshes.seed(Path(path), outcome)
    return fix_with_library(Path(source), options, meshes, details)


class _Run:
    """State of one batch: which meshes are known, which files wait for which meshes."""

    def __init__(self, options: FixOptions, settings: BatchSettings,
                 cache: SolidsCache | None, progress: ProgressHook | None) -> None:
        self.options = options
        self.settings = settings
        self.cache = cache
        self.progress = progress or (lambda kind, done, total: None)
        self.times = StageTimes()
        self.meshes: dict[Path, MeshSolids | Exception] = {}
        self.keys: dict[Path, str] = {}
        self.futures: dict[cf.Future, tuple[str, object]] = {}
        self.pending: list[set[Path]] = []
        self.waiting: dict[Path, list[int]] = {}
        self.on_ready: Callable[[int], None] = lambda i: None
        self.total_meshes = 0
        self.done_meshes = 0

    def lookup_cache(self, path: Path) -> bool:
        """Fill ``self.meshes[path]`` from the cache; False when it must be computed."""
        if self.cache is None or not self.cache.enabled:
            return False
        with self.times.stage("cache"):
            key = file_entry_key(path, max_mesh_bytes(self.options.max_faces),
                                 self.cache.digests)
            if key is None:
                return False  # not a readable regular file within limits: the worker says so
            self.keys[path] = key
            hit = self.cache.get(key)
        if hit is None:
            return False
        found, faces = hit
        max_faces = self.options.max_faces
        if faces > max_faces:
            from urdfinertia.cache.library import too_many_faces

            found = too_many_faces(path, faces, max_faces)
        self.meshes[path] = found
        return True

    def store(self, path: Path, outcome: MeshSolids | Exception, faces: int) -> None:
        from urdfinertia.cache.library import cacheable

        self.meshes[path] = outcome
        key = self.keys.get(path)
        # faces > 0: the mesh was read, so an error came from the repair of its bytes
        if (self.cache is not None and key is not None and faces > 0
                and cacheable(outcome, path)):
            with self.times.stage("cache"):
                self.cache.put(key, outcome, faces)

    def prepare(self, pool: cf.Executor, needs: Sequence[Sequence[Path]],
                on_ready: Callable[[int], None]) -> None:
        """Compute every mesh of ``needs`` once; call ``on_ready(i)`` when file i's are known.

        ``on_ready`` may submit more work to ``pool``; :meth:`drain` collects it.
        """
        distinct = list(dict.fromkeys(p for paths in needs for p in paths))
        todo = [p for p in distinct if not self.lookup_cache(p)]
        # identical bytes under two names (copied packages) are integrated once
        by_key: dict[str, list[Path]] = {}
        groups: list[list[Path]] = []
        for p in todo:
            key = self.keys.get(p)
            if key is None:
                groups.append([p])
            elif key in by_key:
                by_key[key].append(p)
            else:
                by_key[key] = [p]
                groups.append(by_key[key])
        self.total_meshes = len(distinct)
        self.done_meshes = len(distinct) - len(todo)
        self.progress("meshes", self.done_meshes, self.total_meshes)
        for i, paths in enumerate(needs):
            missing = {p for p in paths if p not in self.meshes}
            self.pending.append(missing)
            for p in missing:
                self.waiting.setdefault(p, []).append(i)
        self.on_ready = on_ready
        # largest first: the long tasks start early and the end of the run stays busy
        groups.sort(key=lambda g: (-_size(g[0]), str(g[0])))
        for group in groups:
            fut = submit(pool, mesh_task, str(group[0]), self.options.max_faces)
            self.futures[fut] = ("mesh", group)
        for i, missing in enumerate(self.pending):
            if not missing:
                on_ready(i)

    def mesh_done(self, group: list[Path], fut: cf.Future) -> None:
        try:
            outcome, faces, times = fut.result()
            self.times.merge(times)
        except Exception as exc:  # noqa: BLE001 - a dead worker fails its meshes only
            outcome, faces = MeshError(f"worker failed: {type(exc).__name__}: {exc}",
                                       file=group[0]), 0
        for p in group:
            self.store(p, outcome, faces)
            self.done_meshes += 1
            for i in self.waiting.pop(p, []):
                self.pending[i].discard(p)
                if not self.pending[i]:
                    self.on_ready(i)
        self.progress("meshes", self.done_meshes, self.total_meshes)

    def drain(self, on_file: Callable[[object, cf.Future], None]) -> None:
        """Wait for all submitted work, dispatching results as they arrive."""
        while self.futures:
            done, _ = cf.wait(list(self.futures), return_when=cf.FIRST_COMPLETED)
            for fut in done:
                kind, payload = self.futures.pop(fut)
                if kind == "mesh":
                    self.mesh_done(payload, fut)  # type: ignore[arg-type]
                else:
                    on_file(payload, fut)


def _size(path: Path) -> int:
    try:
        return path.stat().st_size
    except OSError:
        return 0


def prepared_library(urdfs: Sequence[Path], options: FixOptions, settings: BatchSettings,
                     cache: SolidsCache | None = None,
                     progress: ProgressHook | None = None) -> MeshLibrary:
    """A :class:`MeshLibrary` holding the results of every mesh ``urdfs`` reference.

    With ``settings.jobs > 1`` or ``settings.dask`` the meshes are computed in parallel;
    otherwise they are computed lazily by the library itself.
    """
    from urdfinertia.cache.library import MeshLibrary

    library = MeshLibrary(options.package_dirs, options.max_faces, cache)
    with open_executor(settings.jobs, settings.dask) as pool:
        if pool is None:
            return library
        run = _Run(options, settings, cache, progress)
        with run.times.stage("xml"):
            needs = [referenced_meshes(Path(u), options) for u in urdfs]
        run.prepare(pool, needs, lambda i: None)
        run.drain(lambda payload, fut: None)
    for path, outcome in run.meshes.items():
        library.seed(path, outcome)
    library.timer.merge(run.times)
    return library


def run_batch(jobs: Sequence[FileJob], options: FixOptions,
              settings: BatchSettings = BatchSettings(),
              progress: ProgressHook | None = None) -> BatchReport:
    """Fix every job's file, write its output, and report each file's outcome."""
    cache = settings.open_cache()
    outcomes: list[FileOutcome | None] = [None] * len(jobs)
    total = len(jobs)
    done = 0
    times = StageTimes()
    meshes = 0

    def finish(i: int, outcome: FileOutcome) -> None:
        nonlocal done
        if outcome.error is None and outcome.document is not None:
            with times.stage("write"):
                outcome = _write(jobs[i], outcome, settings)
        outcomes[i] = outcome
        done += 1
        hook("files", done, total)

    hook = progress or (lambda kind, d, t: None)
    hook("files", 0, total)
    results = (FileResults(cache, options) if cache is not None and not settings.details
               else None)
    todo = list(range(total))
    hits: list[tuple[int, FileOutcome]] = []
    if results is not None:
        todo = []
        for i, job in enumerate(jobs):
            with times.stage("cache"):
                hit = results.lookup(job.source)
            if hit is None:
                todo.append(i)
            else:
                hits.append((i, _from_cache(job.source, *hit)))
    if todo:
        for i, outcome in hits:
            finish(i, outcome)

        def finish_fresh(i: int, outcome: FileOutcome) -> None:
            reusable = outcome.reusable_error and (outcome.document is not None
                                                   or outcome.error is not None)
            if results is not None and reusable and outcome.source_digest:
                known = results.keys.get(jobs[i].source)
                if known and hashlib.blake2b(known[1], digest_size=20).hexdigest() == \
                        outcome.source_digest:
                    with times.stage("cache"):
                        results.store(jobs[i].source, outcome.trace, CachedResult(
                            outcome.robot, outcome.links, outcome.recomputed,
                            outcome.warnings, outcome.document or b"", outcome.error,
                            outcome.left, outcome.problems))
            finish(i, outcome)

        meshes = _fix_all(jobs, todo, options, settings, cache, progress, times,
                          finish_fresh)
    elif hits:
        # everything came from the cache: only writing is left, and each write waits for
        # its fsyncs, so a few threads write at once (no process pool runs that a thread
        # could disturb)
        with times.stage("write"), cf.ThreadPoolExecutor(
                WRITER_THREADS, thread_name_prefix="urdfinertia-write") as writer:
            written = writer.map(lambda hit: _write(jobs[hit[0]], hit[1], settings), hits)
            for (i, _), outcome in zip(hits, written, strict=True):
                outcomes[i] = outcome
                done += 1
                hook("files", done, total)
    for o in outcomes:
        assert o is not None
        times.merge(o.times)
    warnings: tuple[str, ...] = ()
    if cache is not None:
        with times.stage("cache"):
            cache.prune()
        warnings = tuple(cache.warnings)
    return BatchReport(tuple(o for o in outcomes if o is not None), times, meshes,
                       cache.hits if cache else 0, cache.misses if cache else 0, warnings,
                       results.hits if results is not None else 0)


def _fix_all(jobs: Sequence[FileJob], todo: list[int], options: FixOptions,
             settings: BatchSettings, cache: SolidsCache | None,
             progress: ProgressHook | None, times: StageTimes,
             finish: Callable[[int, FileOutcome], None]) -> int:
    """Compute the files ``todo`` (indices into ``jobs``), passing each outcome to
    ``finish``; returns the number of distinct meshes used."""
    from urdfinertia.cache.library import MeshLibrary

    _load_compute_modules()
    total = len(jobs)
    with open_executor(settings.jobs, settings.dask) as pool:
        if pool is None:
            library = MeshLibrary(options.package_dirs, options.max_faces, cache)
            for i in todo:
                finish(i, fix_with_library(jobs[i].source, options, library,
                                           settings.details))
            return len(library._memo)
        run = _Run(options, settings, cache, progress)
        pending = set(todo)
        with run.times.stage("xml"):
            needs = [referenced_meshes(jobs[i].source, options) if i in pending else []
                     for i in range(total)]

        def ready(i: int) -> None:
            if i not in pending:
                return  # taken from the whole-file cache
            seeds = {str(p): run.meshes[p] for p in needs[i]}
            fut = submit(pool, fix_file_task, str(jobs[i].source), options, seeds,
                         settings.details)
            run.futures[fut] = ("file", i)

        def file_done(i: object, fut: cf.Future) -> None:
            assert isinstance(i, int)
            try:
                outcome = fut.result()
            except Exception as exc:  # noqa: BLE001 - e.g. a worker killed by the OS
                outcome = FileOutcome(jobs[i].source, error=f"{jobs[i].source}: worker "
                                      f"failed: {type(exc).__name__}: {exc}")
            finish(i, outcome)

        run.prepare(pool, needs, ready)
        run.drain(file_done)
        times.merge(run.times)
        return run.total_meshes


def _from_cache(source: Path, result: CachedResult, original: bytes) -> FileOutcome:
    if result.error is not None:
        return FileOutcome(source, error=result.error)
    return FileOutcome(source, robot=result.robot, links=result.links,
                       recomputed=result.recomputed, changed=result.document != original,
                       warnings=result.warnings, document=result.document,
                       left=result.left, problems=result.problems)


def _write(job: FileJob, outcome: FileOutcome, settings: BatchSettings) -> FileOutcome:
    """Write ``outcome``'s document where ``job`` says; drop it from memory once written."""
    if outcome.error is not None or outcome.document is None:
        return outcome
    in_place = settings.in_place
    if not in_place and job.output is not None and not settings.keep_mesh_paths:
        from urdfinertia.descriptions.formats import relocate_references

        document, rewritten = relocate_references(outcome.document, job.source, job.output)
        outcome = dataclasses.replace(outcome, document=document, rewritten=rewritten)
    try:
        if in_place:
            if outcome.changed:
                write_in_place(job.source, outcome.document)
            return dataclasses.replace(outcome, output=job.source, document=None)
        if job.output is None:
            return outcome
        job.output.parent.mkdir(parents=True, exist_ok=True)
        atomic_write_bytes(job.output, outcome.document)
    except OSError as exc:
        err = OutputError(f"cannot write: {exc.strerror or exc}", file=job.output)
        return dataclasses.replace(outcome, error=str(err), document=None)
    except UrdfInertiaError as exc:
        return dataclasses.replace(outcome, error=str(exc), document=None)
    return dataclasses.replace(outcome, output=job.output, document=None)
