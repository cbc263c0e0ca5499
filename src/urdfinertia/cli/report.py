"""``urdf-inertia report``: write the self-contained HTML report of one URDF."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path
from typing import TYPE_CHECKING

from urdfinertia.atomic import atomic_write_bytes
from urdfinertia.cli.batch import add_batch_arguments, finish_single, single_file_library
from urdfinertia.cli.options import add_common_geometry_arguments, options_from_args, positive_int
from urdfinertia.render.report import build_report
from urdfinertia.render.scene import (
    DEFAULT_VIEW_FACES,
    VIEW_MODES,
    display_paths,
    display_task,
    load_display_modules,
)

if TYPE_CHECKING:
    from urdfinertia.cache.library import MeshLibrary


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("urdf", type=Path, help="the URDF to report on")
    p.add_argument("-o", "--output", type=Path, required=True, metavar="HTML",
                   help="write the report here (one self-contained file, works offline)")
    add_common_geometry_arguments(p)
    p.add_argument("--view", choices=VIEW_MODES, default="visual",
                   help="geometry drawn in the 3-D view (a link without it shows the other; "
                        "default visual)")
    p.add_argument("--view-faces", type=positive_int, default=DEFAULT_VIEW_FACES, metavar="N",
                   help="face budget of the 3-D view; meshes are decimated to share it "
                        f"(display only, default {DEFAULT_VIEW_FACES})")
    add_batch_arguments(p)


#: Bytes of mesh files whose display copies are missing from the cache from which they are
#: made by worker processes (with -j): reading and decimating costs about 0.15 s per MB
#: of COLLADA (baxter's visuals), a forked worker a few tenths of a second.
DISPLAY_WORKERS_FROM_BYTES = 4 << 20


def prepare_display(args: argparse.Namespace, meshes: MeshLibrary) -> None:
    """Make the display copies the 3-D view needs that the cache lacks in worker processes
    (-j, --dask), into the cache, so that building the scene only reads them."""
    from urdfinertia.batch.executors import open_executor, submit
    from urdfinertia.cli.batch import settings_from_args
    from urdfinertia.descriptions.formats import read_description
    from urdfinertia.errors import UrdfInertiaError

    settings = settings_from_args(args)
    if meshes.cache is None or (settings.jobs <= 1 and not settings.dask):
        return
    try:
        robot, _ = read_description(args.urdf, lenient=True)
    except UrdfInertiaError:
        return  # build_report says why
    paths, cap = display_paths(robot, meshes, args.view, args.view_faces)
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


def run(args: argparse.Namespace) -> int:
    from urdfinertia.link.policy import every_link

    options = options_from_args(args)
    # the meshes in parallel with -j: every link's, since the report's compare derives
    # every link with geometry (fix's own are among them)
    meshes = single_file_library(args, every_link(options))
    prepare_display(args, meshes)
    page = build_report(args.urdf, options, view=args.view, face_budget=args.view_faces,
                        meshes=meshes)
    finish_single(args, meshes)
    data = page.encode("utf-8")
    atomic_write_bytes(args.output, data)
    print(f"wrote {args.output} ({len(data) / 1e6:.1f} MB)", file=sys.stderr)
    return 0
