"""Size limits of mesh files, importable without numpy (command line, cache keys).

:mod:`urdfinertia.mesh.read.load` enforces them when reading; the values are defined here so that
the command line and a warm run (which only hashes files) need not import the readers.
"""

from __future__ import annotations

#: Largest mesh accepted by default (faces); ``--max-faces`` raises it. 18 times the
#: largest mesh of the example-robot-data collection (56k faces).
DEFAULT_MAX_FACES = 1_000_000
#: File size allowed per face of the limit: an ASCII STL takes about 300 bytes a face,
#: every other supported format less. Files above ``max_mesh_bytes`` are not opened.
BYTES_PER_FACE = 400
#: Size allowed whatever the face limit (headers, materials, small meshes).
BASE_MESH_BYTES = 1 << 20


def max_mesh_bytes(max_faces: int) -> int:
    """Largest mesh file read under a face limit of ``max_faces``, bytes."""
    return BASE_MESH_BYTES + BYTES_PER_FACE * max(int(max_faces), 0)
