"""``urdf-inertia report``: write the self-contained HTML report of one URDF."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from urdfinertia.atomic import atomic_write_bytes
from urdfinertia.batch.display import prepare_display
from urdfinertia.cli.batch import (
    add_batch_arguments,
    finish_single,
    settings_from_args,
    single_file_library,
)
from urdfinertia.cli.options import add_common_geometry_arguments, options_from_args, positive_int
from urdfinertia.render.report import build_report
from urdfinertia.render.scene import DEFAULT_VIEW_FACES, VIEW_MODES


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


def run(args: argparse.Namespace) -> int:
    from urdfinertia.plan.policy import every_link
    from urdfinertia.render.report import require_report_extra

    require_report_extra()  # before any work: one line naming the extra to install
    options = options_from_args(args)
    # the meshes in parallel with -j: every link's, since the report's compare derives
    # every link with geometry (fix's own are among them)
    meshes = single_file_library(args, every_link(options))
    prepare_display(args.urdf, meshes, args.view, args.view_faces, settings_from_args(args))
    page = build_report(args.urdf, options, view=args.view, face_budget=args.view_faces,
                        meshes=meshes)
    finish_single(args, meshes)
    data = page.encode("utf-8")
    atomic_write_bytes(args.output, data)
    print(f"wrote {args.output} ({len(data) / 1e6:.1f} MB)", file=sys.stderr)
    return 0
