"""Size limits of mesh files, importable without numpy (command line, cache keys).

`urdfinertia.mesh.read.load` enforces them when reading; the values are defined here so that
the command line and a warm run (which only hashes files) need not import the readers.
"""

from __future__ import annotations

DEFAULT_MAX_FACES = 1_000_000
"""Largest mesh accepted by default (faces); `--max-faces` raises it. 18 times the largest mesh of
the example-robot-data collection (56k faces).
"""
BYTES_PER_FACE = 400
"""File size allowed per face of the limit: an ASCII STL takes about 300 bytes a face, every other
supported format less. Files above `max_mesh_bytes` are not opened.
"""
BASE_MESH_BYTES = 1 << 20
"""Size allowed whatever the face limit (headers, materials, small meshes)."""


def max_mesh_bytes(max_faces: int) -> int:
    """Largest mesh file read under a face limit of `max_faces`, bytes."""
    return BASE_MESH_BYTES + BYTES_PER_FACE * max(int(max_faces), 0)


BUDGET_ENV_VAR = "URDFINERTIA_MESH_SECONDS"
"""Environment variable holding the repair time budget per mesh, CPU seconds (set by
`--mesh-seconds`; worker processes inherit it).
"""
DEFAULT_MESH_SECONDS = 10.0
"""Default CPU time a mesh's repair may spend on refined hole caps (triangulations, winding-number
votes and level caps) before it caps its holes with fans. The slowest mesh of the
example-robot-data collection takes about 4 CPU seconds in all: the margin keeps a slower machine
from repairing ordinary meshes differently.
"""
OVER_BUDGET_NOTE = "repair over its time budget"
"""Start of the note of a repair that ran out of time and capped its holes with fans (results with
it are not cached: another run may have the time).
"""


def mesh_seconds() -> float | None:
    """The repair time budget per mesh (seconds; None when set to 0 or less: no limit)."""
    import os

    raw = os.environ.get(BUDGET_ENV_VAR, "")
    try:
        seconds = float(raw) if raw.strip() else DEFAULT_MESH_SECONDS
    except ValueError:
        seconds = DEFAULT_MESH_SECONDS
    return seconds if seconds > 0 else None
