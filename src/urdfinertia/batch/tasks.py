"""What one unit of a batch run does, in the parent or in a worker process.

`mesh_task` reads, repairs and integrates one mesh file; `fix_file_task` fixes
one URDF with its meshes' results handed over; `FileOutcome` is what is reported of
one file. These functions are pickled to worker processes and Dask workers, so they take
and return plain values.
"""

from __future__ import annotations

import hashlib
import time
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING

from urdfinertia.body.options import FixOptions
from urdfinertia.errors import UrdfInertiaError
from urdfinertia.timing import StageTimes

if TYPE_CHECKING:
    import numpy as np

    from urdfinertia.cache.library import MeshLibrary
    from urdfinertia.mesh.solids import MeshSolids


def load_compute_modules() -> None:
    """Import what computes (numpy, lxml, the mesh readers) before any stage is timed, so
    that stage times do not include imports."""
    import urdfinertia.body.assemble
    import urdfinertia.body.parts  # noqa: F401




@dataclass(frozen=True, eq=False)
class FileOutcome:
    """What happened to one file. `error` is one line; `document` is the fixed URDF."""

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
    trace: tuple[tuple[str, str, str], ...] = ()
    """(uri, urdf folder, resolved path) of every mesh used, and a digest of the source bytes the
    result was computed from: what a whole-file cache entry depends on.
    """
    source_digest: str = ""
    reusable_error: bool = False
    """The error, or the links left as they were, depend on the source bytes and the traced meshes
    alone (its XML, a URI that does not resolve, a mesh rejected for its bytes, not a
    permission): the outcome may be cached.
    """
    left: tuple[str, ...] = ()
    """One line per link left as it was, and per problem read past."""
    problems: tuple[str, ...] = ()
    rewritten: int = 0
    """Relative mesh references rewritten for the output's folder."""




def referenced_meshes(source: Path, options: FixOptions) -> list[Path]:
    """Resolved mesh files the geometry policy will read for `source` (best effort).

    Problems are ignored here: the file's own task reports them in context.
    """
    return mesh_needs(source, options)[0]


def mesh_needs(source: Path, options: FixOptions) -> tuple[list[Path], list[Path]]:
    """`(solids, points)`: the resolved mesh files whose solids the geometry policy
    integrates for `source`, and those whose hull points the geometry checks read
    (every mesh of a link that has an inertial, collision and visual; and every mesh whose
    solids are integrated: a candidate's box and kind come from its points), best effort.

    Problems are ignored here: the file's own task reports them in context.
    """
    from urdfinertia.body.options import select_geometry
    from urdfinertia.descriptions.formats import read_description
    from urdfinertia.descriptions.model import Mesh
    from urdfinertia.descriptions.paths import resolve_mesh_path

    try:
        robot, _ = read_description(source)
    except UrdfInertiaError:
        return [], []
    solids: dict[Path, None] = {}
    points: dict[Path, None] = {}

    def add(refs: tuple, into: dict[Path, None]) -> None:
        for ref in refs:
            if isinstance(ref.shape, Mesh):
                try:
                    path = resolve_mesh_path(ref.shape.filename, source.parent,
                                             options.package_dirs)
                except UrdfInertiaError:
                    continue
                into[path.resolve()] = None

    for link in robot.links:
        refs = select_geometry(link, options.geometry)[1]
        if options.geometry == "auto" and options.recompute != "needed":
            # every link asked for is derived: --geometry auto weighs all its geometries
            refs = refs + link.collisions + link.visuals
        add(refs, solids)
        add(refs, points)
        if link.inertial is not None:
            add(link.collisions + link.visuals, points)
    return list(solids), list(points)


# ---------------------------------------------------------------------------- work units

def mesh_task(path: str, max_faces: int, solids: bool = True,
              ) -> tuple[MeshSolids | Exception | None, int, StageTimes, np.ndarray | None,
                         dict | None]:
    """Read one mesh file and integrate it (unless `solids` is False): (solids or the
    error, face count, stage times, its hull points or None when it cannot be read, and
    their cache header with the hull's volume,
    `points_header`).

    The points (`MeshLibrary.points`) come from the same reading, so no process
    reads the file again for the geometry checks; the hull's volume is computed here,
    in the worker, not by the process that gathers the results (which then needs no
    Qhull, nor scipy) nor again by each file's task. The error is returned, not raised,
    so that each file using the mesh repeats it exactly as a single-process run would.
    """
    from urdfinertia.batch.heap import release_free_memory
    from urdfinertia.cache import library as meshlib

    load_compute_modules()
    # what the previous mesh freed goes back to the system before this one is read, so
    # that a worker's peak is its largest mesh's, not the sum of what its heap kept
    release_free_memory()
    times = StageTimes()
    faces = 0
    points = header = None
    try:
        with times.stage("mesh read"):
            mesh = meshlib.load_mesh(path, max_faces)
        faces = len(mesh.faces)
        with times.stage("assemble"):
            header, points = meshlib.points_entry(mesh)
        if not solids:
            return None, faces, times, points, header
        return meshlib.integrate_mesh(mesh, times), faces, times, points, header
    except Exception as exc:  # noqa: BLE001 - reported per file by fix_with_library
        return exc, faces, times, points, header


def fix_with_library(source: Path, options: FixOptions, meshes: MeshLibrary,
                     details: bool = False) -> FileOutcome:
    """Fix one file with `meshes`; any failure becomes the outcome's one-line error."""
    from urdfinertia.descriptions.formats import read_bytes, robot_from_bytes
    from urdfinertia.plan.fix import fix_robot

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
        from urdfinertia.render.decisions import problem_lines, verdict_note_lines

        outcome = FileOutcome(
            source, robot=robot.name, links=len(result.links),
            recomputed=sum(r.status == "recomputed" for r in result.links),
            changed=result.changed, warnings=verdict_note_lines(result),
            document=result.output,
            details=info, times=times, trace=tuple(meshes.trace), source_digest=digest,
            left=tuple(str(result.left_error(r)) for r in result.left),
            problems=tuple(problem_lines(result)),
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
                  details: bool = False,
                  points: Mapping[str, np.ndarray] | None = None,
                  headers: Mapping[str, dict] | None = None) -> FileOutcome:
    """The per-file unit of work run by a worker: `seeds` are its meshes' results,
    `points` their hull points, `headers` those points' cache headers (the hull's
    volume, so that no Qhull runs again here)."""
    from urdfinertia.cache.library import MeshLibrary

    load_compute_modules()
    meshes = MeshLibrary(options.package_dirs, options.max_faces)
    for path, outcome in seeds.items():
        meshes.seed(Path(path), outcome)
    headers = headers or {}
    for path, found in (points or {}).items():
        meshes.seed_points(Path(path), found, headers.get(path))
    return fix_with_library(Path(source), options, meshes, details)
