"""COLLADA as trimesh's own loader (`trimesh.exchange.dae.load_collada`) reads it.

First by the direct reader (`.collada`: the same arrays, bit for bit, without parsing
the sources a mesh does not need), else by that loader, called directly, without
`trimesh.load`'s scene machinery. pycollada's tolerance is kept (a geometry, node or
material it cannot load is left out); what it does not read (`<tristrips>`,
controllers) holds no triangles here either. Every `<triangles>` or `<polylist>`
instance is one piece: an unwelded triangle soup placed by its node's world matrix; the
repair's weld joins the corners (the mass properties are those of the welded surface,
checked against `trimesh.load` on every mesh of example-robot-data). The caller has
refused hostile XML (entities, external DTDs) and zipped files, checked the declared
face count, and applies `<unit meter>`.
"""

from __future__ import annotations

import io

import numpy as np

from urdfinertia.mesh.read.collada import read_collada
from urdfinertia.mesh.read.common import Piece


def read_dae(data: bytes, max_faces: int) -> list[Piece]:
    """Every triangle-set instance of a COLLADA document, in its world frame.

    The direct reader (`.collada.read_collada`) gives trimesh's arrays at less
    cost; what it does not reproduce is read by trimesh's loader (`read_dae_trimesh`).
    """
    try:
        return read_collada(data)
    except (MemoryError, RecursionError):
        raise
    except Exception:  # noqa: BLE001 - NeedsPycollada, or a document trimesh also fails on:
        # its loader gives the outcome (and the error message) of record
        return read_dae_trimesh(data, max_faces)


def read_dae_trimesh(data: bytes, max_faces: int) -> list[Piece]:
    """`read_dae` through `trimesh.exchange.dae.load_collada` (pycollada)."""
    from trimesh.exchange.dae import load_collada

    loaded = load_collada(io.BytesIO(data))
    geometry = loaded["geometry"]
    pieces = []
    for edge in loaded["graph"]:
        kwargs = geometry.get(edge.get("geometry"))
        if kwargs is None or len(kwargs["faces"]) == 0:
            continue
        pieces.append(Piece(np.asarray(kwargs["vertices"], dtype=np.float64),
                            np.asarray(kwargs["faces"], dtype=np.int64),
                            np.asarray(edge["matrix"], dtype=np.float64)))
    return pieces
