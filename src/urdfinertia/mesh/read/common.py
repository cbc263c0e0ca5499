"""What every mesh reader of the registry (`.load`) returns: `Piece` lists.

A reader that meets something it does not reproduce raises `NeedsTrimesh`, and
`urdfinertia.mesh.read.load.load_mesh` reads the file with `trimesh.load` instead.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

IDENTITY = np.eye(4)
"""The transform of a piece that is not placed by a scene graph (trimesh's identity)."""
IDENTITY.flags.writeable = False


class NeedsTrimesh(Exception):
    """The file uses a feature, or a malformation, that only trimesh handles exactly."""


class TooManyFaces(Exception):
    """The scene instances more triangles than allowed (found before building arrays)."""

    def __init__(self, faces: int) -> None:
        super().__init__(faces)
        self.faces = faces


@dataclass(frozen=True, eq=False)
class Piece:
    """One scene instance of one triangle set, in its node's frame.

    `transform` places it in the file's root frame, as trimesh's scene graph would.
    Pieces of several instances of one geometry share their arrays.
    """

    vertices: np.ndarray  # (n, 3) float64
    faces: np.ndarray  # (m, 3) int64
    transform: np.ndarray = field(default_factory=lambda: IDENTITY)  # (4, 4) float64


def parse_floats(text: str | bytes, dtype: type = np.float64) -> np.ndarray:
    """Whitespace-separated numbers, as `np.fromstring(text, dtype, sep=" ")`.

    `np.fromstring` returns an uninitialised value for a blank non-empty string; such
    text raises `NeedsTrimesh` instead, so callers never see that value.
    """
    if text and not text.strip():
        raise NeedsTrimesh("blank number list")
    return np.fromstring(text, dtype=dtype, sep=" ")
