"""The report's display copies made by worker processes before the page is built."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

from urdfinertia.batch.executors import open_executor, submit
from urdfinertia.render.scene import display_paths, display_task, load_display_modules

if TYPE_CHECKING:
    from urdfinertia.batch.run import BatchSettings
    from urdfinertia.cache.library import MeshLibrary

DISPLAY_WORKERS_FROM_BYTES = 4 << 20
"""Bytes of mesh files whose display copies are missing from the cache from which they are made by
worker processes (with -j): reading and decimating costs about 0.15 s per MB of COLLADA (baxter's
visuals), a forked worker a few tenths of a second.
"""


def prepare_display(urdf: Path, meshes: MeshLibrary, view: str, view_faces: int,
                    settings: BatchSettings) -> None:
    """Make the display copies the 3-D view of `urdf` needs that the cache lacks in
    worker processes (`settings`: -j, --dask), into the cache, so that building the
    scene only reads them."""
    from urdfinertia.descriptions.formats import read_description
    from urdfinertia.errors import UrdfInertiaError

    if meshes.cache is None or (settings.jobs <= 1 and not settings.dask):
        return
    try:
        robot, _ = read_description(urdf)
    except UrdfInertiaError:
        return  # build_report says why
    paths, cap = display_paths(robot, meshes, view, view_faces)
    missing = [p for p in paths if not meshes.display_cached(p, cap)]
    size = sum(p.stat().st_size for p in missing if p.is_file())
    if len(missing) < 2 or (size < DISPLAY_WORKERS_FROM_BYTES and not settings.dask):
        return
    load_display_modules()  # once here, not in every forked worker
    # largest first: the long tasks start early and the end stays busy
    missing.sort(key=lambda p: -p.stat().st_size if p.is_file() else 0)
    with open_executor(min(settings.jobs, len(missing)), settings.dask) as pool:
        assert pool is not None
        futures = {p: submit(pool, display_task, str(p), meshes.max_faces, cap)
                   for p in missing}
        for p, fut in futures.items():
            try:
                made = fut.result()
            except Exception:  # noqa: BLE001 - a dead worker: build_scene makes it here
                continue
            if made is not None:
                meshes.seed_display(p, cap, *made)
