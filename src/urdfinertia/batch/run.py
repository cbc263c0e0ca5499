"""Fix many URDFs in one run: inputs, worker processes or a Dask cluster, one outcome each.

The unit of work is one file (`.tasks.fix_file_task`, which calls
[`urdfinertia.plan.fix.fix_robot`][urdfinertia.plan.fix.fix_robot]).
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
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

from urdfinertia.atomic import OutputWriter, write_in_place
from urdfinertia.batch.executors import open_executor, submit
from urdfinertia.batch.file_cache import CachedResult, FileResults
from urdfinertia.batch.inputs import FileJob
from urdfinertia.batch.tasks import (
    FileOutcome,
    fix_file_task,
    fix_with_library,
    load_compute_modules,
    mesh_needs,
    mesh_task,
)
from urdfinertia.body.options import FixOptions
from urdfinertia.cache.store import DEFAULT_MAX_BYTES, SolidsCache
from urdfinertia.errors import MeshError, OutputError, UrdfInertiaError
from urdfinertia.timing import StageTimes

if TYPE_CHECKING:
    import numpy as np

    from urdfinertia.cache.library import MeshLibrary
    from urdfinertia.mesh.solids import MeshSolids

# What reads, repairs and integrates (numpy, lxml, the mesh readers) is imported by the
# functions that compute: a warm run, whose every file comes from the cache, needs none of it.

WRITER_THREADS = 8
"""Threads writing the outputs of the files that came from the cache, before any worker process
starts: each write waits for its fsync, which overlap in threads.
"""
WORKERS_FROM_BYTES = 6 << 20
"""Bytes of mesh files still to compute below which a run stays in one process: each worker first
imports numpy, scipy, trimesh and manifold3d (about 1.5 CPU seconds), and the repair takes about
half a second per megabyte of mesh file (example-robot-data: 355 MB in 165 s), so two workers pay
for themselves from a few megabytes on.
"""


ProgressHook = Callable[[str, int, int], None]
"""Progress(kind, done, total) with kind "meshes" or "files"."""


@dataclass(frozen=True)
class BatchSettings:
    """How to run: workers, cache and engine.

    Attributes
    ----------
    jobs : int
        Worker processes (1: everything in this process).
    use_cache : bool
        Read and store mesh solids in the cache.
    cache_dir : Path or None
        The cache folder; None for the default (`URDFINERTIA_CACHE_DIR`, else the user's
        cache folder).
    cache_max_bytes : int
        The size bound of the cache folder.
    dask : str or None
        The address of a Dask scheduler; overrides `jobs`.
    in_place : bool
        Write results over the sources (with `.bak`) instead of `FileJob.output`.
    details : bool
        Keep per-link JSON-ready results (`--json`).
    keep_mesh_paths : bool
        Keep relative mesh references as written when the output is in another folder.
    """

    jobs: int = 1
    use_cache: bool = True
    cache_dir: Path | None = None
    cache_max_bytes: int = DEFAULT_MAX_BYTES
    dask: str | None = None
    in_place: bool = False
    details: bool = False
    keep_mesh_paths: bool = False

    def __post_init__(self) -> None:
        if self.jobs < 1:
            raise ValueError("jobs must be at least 1")

    def open_cache(self) -> SolidsCache | None:
        """The mesh cache these settings ask for.

        Returns
        -------
        SolidsCache or None
            None with `use_cache=False`.
        """
        if not self.use_cache:
            return None
        return SolidsCache(self.cache_dir, self.cache_max_bytes)


@dataclass(frozen=True, eq=False)
class BatchReport:
    outcomes: tuple[FileOutcome, ...]
    times: StageTimes
    meshes: int  # distinct mesh files read or found in the cache
    cache_hits: int = 0  # mesh entries
    cache_misses: int = 0
    warnings: tuple[str, ...] = ()
    file_hits: int = 0  # files whose whole result came from the cache
    up_to_date: tuple[bool, ...] = ()
    """Per outcome: its output file already held exactly these bytes and was left untouched (same
    inode and modification time)
    """

    @property
    def failed(self) -> tuple[FileOutcome, ...]:
        """The files that failed, in input order."""
        return tuple(o for o in self.outcomes if o.error is not None)

    @property
    def untouched(self) -> int:
        """Outputs that already held these bytes and were left untouched."""
        return sum(self.up_to_date)


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
        #: hull points of the meshes the geometry checks read (:meth:`MeshLibrary.points`)
        self.points: dict[Path, np.ndarray] = {}
        #: the header of each "points" entry (with the hull's volume), for the library
        self.point_headers: dict[Path, dict] = {}
        self.keys: dict[Path, str] = {}
        self.futures: dict[cf.Future, tuple[str, object]] = {}
        #: per file, what it waits for: ("solids" or "points", mesh path)
        self.pending: list[set[tuple[str, Path]]] = []
        self.waiting: dict[tuple[str, Path], list[int]] = {}
        self.on_ready: Callable[[int], None] = lambda i: None
        self.total_meshes = 0
        self.done_meshes = 0

    def workers(self, needs: Sequence[Sequence[Path]],
                point_needs: Sequence[Sequence[Path]]) -> int:
        """How many worker processes the meshes of `needs` (solids) and `point_needs`
        (hull points) are worth: `settings.jobs`, or 1 (this process) when what is
        not in the cache is under `WORKERS_FROM_BYTES` of mesh files (a file that
        cannot be opened needs no work: its file's task says why)."""
        jobs = self.settings.jobs
        if jobs <= 1 or self.settings.dask:
            return jobs
        work = 0
        solids = dict.fromkeys(p for paths in needs for p in paths)
        for p in solids:
            if p not in self.meshes and not self.lookup_cache(p):
                work += _size(p)
        for p in dict.fromkeys(p for paths in point_needs for p in paths):
            if p not in solids and p not in self.points and not self.lookup_points(p):
                work += _size(p) // 5  # reading and a hull: a fifth of a repair
        return jobs if work >= WORKERS_FROM_BYTES else 1

    def lookup_cache(self, path: Path) -> bool:
        """Fill `self.meshes[path]` from the cache; False when it must be computed."""
        if self.cache is None:
            return False
        with self.times.stage("cache"):
            key, found = self.cache.lookup_mesh(path, self.options.max_faces)
        if key is not None:
            self.keys[path] = key
        if found is None:
            return False
        self.meshes[path] = found
        return True

    def lookup_points(self, path: Path) -> bool:
        """Fill `self.points[path]` from the cache; False when it must be computed."""
        if self.cache is None:
            return False
        with self.times.stage("cache"):
            key, found = self.cache.lookup_arrays(path, self.options.max_faces, "points")
        if key is not None:
            self.keys[path] = key
        if found is None or isinstance(found, MeshError) or len(found[1]) % 3:
            return False  # a refusal is the reader's to repeat, in context
        self.points[path] = found[1].reshape(-1, 3)
        self.point_headers[path] = found[0]
        return True

    def store(self, path: Path, outcome: MeshSolids | Exception | None, faces: int,
              points: np.ndarray | None, header: dict | None = None) -> None:
        """Keep a worker's results for `path` (and put them in the cache). `header`
        is the points' cache header the worker computed
        (`points_header`): this process runs no Qhull.
        Without one (the worker failed after reading the points) the entry holds no
        volume, and whoever needs it computes it."""
        if outcome is not None:
            self.meshes[path] = outcome
        if points is not None and path not in self.points:
            self.points[path] = points
            if header is not None:
                self.point_headers[path] = header
            if self.cache is not None:
                with self.times.stage("cache"):
                    self.cache.store_arrays(self.keys.get(path), "points",
                                            {**(header or {}), "faces": faces}, points)
        if outcome is not None and self.cache is not None:
            with self.times.stage("cache"):
                self.cache.store_mesh(self.keys.get(path), path, outcome, faces)

    def prepare(self, pool: cf.Executor, needs: Sequence[Sequence[Path]],
                on_ready: Callable[[int], None],
                point_needs: Sequence[Sequence[Path]] = ()) -> None:
        """Compute every mesh of `needs` once, and the hull points of every mesh of
        `point_needs` (from the same reading where both are needed); call
        `on_ready(i)` when file i's solids are known.

        `on_ready` may submit more work to `pool`; `drain` collects it.
        """
        distinct = list(dict.fromkeys(p for paths in needs for p in paths))
        todo = [p for p in distinct if p not in self.meshes and not self.lookup_cache(p)]
        wanted = dict.fromkeys(p for paths in point_needs for p in paths)
        missing_points = {p for p in wanted
                          if p not in self.points and not self.lookup_points(p)}
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
            missing = {("solids", p) for p in paths if p not in self.meshes}
            if i < len(point_needs):
                missing.update(("points", p) for p in point_needs[i] if p in missing_points)
            self.pending.append(missing)
            for item in missing:
                self.waiting.setdefault(item, []).append(i)
        self.on_ready = on_ready
        # largest first: the long tasks start early and the end of the run stays busy
        groups.sort(key=lambda g: (-_size(g[0]), str(g[0])))
        for group in groups:
            fut = submit(pool, mesh_task, str(group[0]), self.options.max_faces)
            self.futures[fut] = ("mesh", group)
        only_points = sorted(missing_points.difference(todo), key=lambda p: (-_size(p), str(p)))
        for p in only_points:
            fut = submit(pool, mesh_task, str(p), self.options.max_faces, False)
            self.futures[fut] = ("points", [p])
        for i, missing in enumerate(self.pending):
            if not missing:
                on_ready(i)

    def mesh_done(self, group: list[Path], fut: cf.Future) -> None:
        points = None
        try:
            outcome, faces, times, points, header = fut.result()
            self.times.merge(times)
        except Exception as exc:  # noqa: BLE001 - a dead worker fails its meshes only
            outcome, faces = MeshError(f"worker failed: {type(exc).__name__}: {exc}",
                                       file=group[0]), 0
            header = None
        for p in group:
            self.store(p, outcome, faces, points, header)
            self.done_meshes += 1
            self._arrived(("solids", p))
            self._arrived(("points", p))  # or not: the file's task reads it and says why
        self.progress("meshes", self.done_meshes, self.total_meshes)

    def points_done(self, paths: list[Path], fut: cf.Future) -> None:
        points, faces, header = None, 0, None
        try:
            _, faces, times, points, header = fut.result()
            self.times.merge(times)
        except Exception:  # noqa: BLE001 - the file's own task reads it and says why
            pass
        for p in paths:
            self.store(p, None, faces, points, header)
            self._arrived(("points", p))

    def _arrived(self, item: tuple[str, Path]) -> None:
        for i in self.waiting.pop(item, []):
            self.pending[i].discard(item)
            if not self.pending[i]:
                self.on_ready(i)

    def point_seeds(self, paths: Sequence[Path]) -> dict[str, np.ndarray]:
        return {str(p): self.points[p] for p in paths if p in self.points}

    def header_seeds(self, paths: Sequence[Path]) -> dict[str, dict]:
        return {str(p): self.point_headers[p] for p in paths if p in self.point_headers}

    def drain(self, on_file: Callable[[object, cf.Future], None]) -> None:
        """Wait for all submitted work, dispatching results as they arrive."""
        while self.futures:
            done, _ = cf.wait(list(self.futures), return_when=cf.FIRST_COMPLETED)
            for fut in done:
                kind, payload = self.futures.pop(fut)
                if kind == "mesh":
                    self.mesh_done(payload, fut)  # type: ignore[arg-type]
                elif kind == "points":
                    self.points_done(payload, fut)  # type: ignore[arg-type]
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
    """A `MeshLibrary` holding the results of every mesh `urdfs` reference.

    With `settings.jobs > 1` or `settings.dask` the meshes are computed in parallel;
    otherwise they are computed lazily by the library itself.
    """
    from urdfinertia.cache.library import MeshLibrary

    library = MeshLibrary(options.package_dirs, options.max_faces, cache)
    if settings.jobs <= 1 and not settings.dask:
        return library
    run = _Run(options, settings, cache, progress)
    with run.times.stage("xml"):
        needs, point_needs = zip(*(mesh_needs(Path(u), options) for u in urdfs),
                                 strict=True) if urdfs else ((), ())
    with open_executor(run.workers(needs, point_needs), settings.dask) as pool:
        if pool is not None:
            run.prepare(pool, needs, lambda i: None, point_needs)
            run.drain(lambda payload, fut: None)
    for path, outcome in run.meshes.items():
        library.seed(path, outcome)
    for path, points in run.points.items():
        library.seed_points(path, points, run.point_headers.get(path))
    library.timer.merge(run.times)
    return library


def run_batch(jobs: Sequence[FileJob], options: FixOptions,
              settings: BatchSettings = BatchSettings(),
              progress: ProgressHook | None = None) -> BatchReport:
    """Fix every job's file, write its output, and report each file's outcome."""
    with OutputWriter() as writer:
        return _run_batch(jobs, options, settings, progress, writer)


def _run_batch(jobs: Sequence[FileJob], options: FixOptions, settings: BatchSettings,
               progress: ProgressHook | None, writer: OutputWriter) -> BatchReport:
    cache = settings.open_cache()
    outcomes: list[FileOutcome | None] = [None] * len(jobs)
    up_to_date = [False] * len(jobs)
    total = len(jobs)
    done = 0
    times = StageTimes()
    meshes = 0

    def finish(i: int, outcome: FileOutcome) -> None:
        nonlocal done
        if outcome.error is None and outcome.document is not None:
            with times.stage("write"):
                outcome, up_to_date[i] = _write(jobs[i], outcome, settings, writer)
        outcomes[i] = outcome
        done += 1
        hook("files", done, total)

    hook = progress or (lambda kind, d, t: None)
    hook("files", 0, total)
    results = (FileResults(cache, options) if cache is not None and not settings.details
               else None)
    todo = list(range(total))
    if results is not None:
        todo = []
        # a file from the cache is written while the next ones are looked up, a few at
        # once (each write waits for its fsync); the threads are gone before any worker
        # process is forked, and a run without hits starts none
        with cf.ThreadPoolExecutor(WRITER_THREADS,
                                   thread_name_prefix="urdfinertia-write") as pool:
            writes: list[tuple[int, cf.Future[tuple[FileOutcome, bool]]]] = []
            for i, job in enumerate(jobs):
                with times.stage("cache"):
                    hit = results.lookup(job.source)
                if hit is None:
                    todo.append(i)
                else:
                    writes.append((i, pool.submit(_write, job, _from_cache(job.source, *hit),
                                                  settings, writer)))
            with times.stage("write"):
                for i, fut in writes:
                    outcomes[i], up_to_date[i] = fut.result()
                    done += 1
                    hook("files", done, total)
    if todo:

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
    for o in outcomes:
        assert o is not None
        times.merge(o.times)
    warnings: tuple[str, ...] = ()
    if cache is not None:
        with times.stage("cache"):
            cache.prune()
        warnings = tuple(cache.warnings)
    with times.stage("write"):
        writer.close()  # each folder's renames made durable once, after all its files
    return BatchReport(tuple(o for o in outcomes if o is not None), times, meshes,
                       cache.hits if cache else 0, cache.misses if cache else 0, warnings,
                       results.hits if results is not None else 0,
                       tuple(u for o, u in zip(outcomes, up_to_date, strict=True)
                             if o is not None))


def _fix_all(jobs: Sequence[FileJob], todo: list[int], options: FixOptions,
             settings: BatchSettings, cache: SolidsCache | None,
             progress: ProgressHook | None, times: StageTimes,
             finish: Callable[[int, FileOutcome], None]) -> int:
    """Compute the files `todo` (indices into `jobs`), passing each outcome to
    `finish`; returns the number of distinct meshes used."""
    from urdfinertia.cache.library import MeshLibrary

    load_compute_modules()
    total = len(jobs)
    run = _Run(options, settings, cache, progress)
    pending = set(todo)
    needs: list[list[Path]] = []
    point_needs: list[list[Path]] = []

    def read_needs() -> None:
        with run.times.stage("xml"):
            for i in range(total):
                solids, points = mesh_needs(jobs[i].source, options) if i in pending else \
                    ([], [])
                needs.append(solids)
                point_needs.append(points)

    jobs_now = settings.jobs
    if jobs_now > 1 and not settings.dask:
        read_needs()
        # little to compute: starting worker processes would cost more than they save
        jobs_now = run.workers(needs, point_needs)
    with open_executor(jobs_now, settings.dask) as pool:
        if pool is None:
            library = MeshLibrary(options.package_dirs, options.max_faces, cache)
            for path, outcome in run.meshes.items():
                library.seed(path, outcome)
            for path, points in run.points.items():
                library.seed_points(path, points, run.point_headers.get(path))
            times.merge(run.times)  # the look-ups above; each file brings its own times
            for i in todo:
                finish(i, fix_with_library(jobs[i].source, options, library,
                                           settings.details))
            return len(library._memo)
        if not needs:
            read_needs()

        def ready(i: int) -> None:
            if i not in pending:
                return  # taken from the whole-file cache
            seeds = {str(p): run.meshes[p] for p in needs[i]}
            fut = submit(pool, fix_file_task, str(jobs[i].source), options, seeds,
                         settings.details, run.point_seeds(point_needs[i]),
                         run.header_seeds(point_needs[i]))
            run.futures[fut] = ("file", i)

        def file_done(i: object, fut: cf.Future) -> None:
            assert isinstance(i, int)
            try:
                outcome = fut.result()
            except Exception as exc:  # noqa: BLE001 - e.g. a worker killed by the OS
                outcome = FileOutcome(jobs[i].source, error=f"{jobs[i].source}: worker "
                                      f"failed: {type(exc).__name__}: {exc}")
            finish(i, outcome)

        run.prepare(pool, needs, ready, point_needs)
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


def _write(job: FileJob, outcome: FileOutcome, settings: BatchSettings,
           writer: OutputWriter) -> tuple[FileOutcome, bool]:
    """Write `outcome`'s document where `job` says; drop it from memory once written.
    Also returns whether the output already held these bytes (and was left untouched)."""
    if outcome.error is not None or outcome.document is None:
        return outcome, False
    in_place = settings.in_place
    if not in_place and job.output is not None and not settings.keep_mesh_paths:
        from urdfinertia.descriptions.formats import relocate_references

        moved, rewritten = relocate_references(outcome.document, job.source, job.output)
        outcome = dataclasses.replace(outcome, document=moved, rewritten=rewritten)
    document = outcome.document
    if document is None:  # (checked above; relocation keeps a document)
        return outcome, False
    try:
        if in_place:
            if outcome.changed:
                write_in_place(job.source, document)
            return dataclasses.replace(outcome, output=job.source, document=None), False
        if job.output is None:
            return outcome, False
        job.output.parent.mkdir(parents=True, exist_ok=True)
        untouched = writer.write(job.output, document).untouched
    except OSError as exc:
        err = OutputError(f"cannot write: {exc.strerror or exc}", file=job.output)
        return dataclasses.replace(outcome, error=str(err), document=None), False
    except UrdfInertiaError as exc:
        return dataclasses.replace(outcome, error=str(exc), document=None), False
    return dataclasses.replace(outcome, output=job.output, document=None), untouched
