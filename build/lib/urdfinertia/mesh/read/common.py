"""What the native mesh readers (:mod:`stl_read`, :mod:`obj_read`, :mod:`dae_read`) return.

The readers reproduce, array for array, what ``trimesh.load(..., process=False)`` gives
for the files they accept, without importing trimesh. A file that uses something a
reader does not reproduce exactly raises :class:`NeedsTrimesh`, and
:func:`urdfinertia.mesh.read.load.load_mesh` reads it with trimesh instead.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

#: The transform of a piece that is not placed by a scene graph (trimesh's identity).
IDENTITY = np.eye(4)
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

    ``transform`` places it in the file's root frame, as trimesh's scene graph would.
    Pieces of several instances of one geometry share their arrays.
    """

    vertices: np.ndarray  # (n, 3) float64
    faces: np.ndarray  # (m, 3) int64
    transform: np.ndarray = field(default_factory=lambda: IDENTITY)  # (4, 4) float64


def parse_ints(text: str | bytes) -> np.ndarray:
    """Whitespace-separated integers as int64, as ``np.fromstring(text, sep=" ")``.

    ``np.fromstring`` returns an uninitialised value for a blank non-empty string;
    such text raises :class:`NeedsTrimesh` instead, so callers never see that value.
    """
    if text and not text.strip():
        raise NeedsTrimesh("blank number list")
    return np.fromstring(text, dtype=np.int64, sep=" ")


def parse_floats(text: str | bytes, dtype: type = np.float64) -> np.ndarray:
    """Whitespace-separated numbers, as ``np.fromstring(text, dtype, sep=" ")``.

    Same guard as :func:`parse_ints` for blank text.
    """
    if text and not text.strip():
        raise NeedsTrimesh("blank number list")
    return np.fromstring(text, dtype=dtype, sep=" ")


def hashable_rows(data: np.ndarray) -> np.ndarray:
    """One sortable key per row of an int64 (n, k) array (trimesh's ``hashable_rows``).

    Rows of up to four small values are packed into one uint64, others viewed as bytes;
    equal keys mean equal rows either way, and the key order is trimesh's.
    """
    if len(data) == 0:
        return np.array([], dtype=np.uint64)
    if data.shape[1] <= 4:
        precision = int(np.floor(64 / data.shape[1]))
        threshold = (2 ** (precision - 1)) - 1
        if data.max() < threshold and data.min() > -threshold:
            hashable = np.zeros(len(data), dtype=np.uint64)
            bitbang = (data.T + (threshold + 1)).astype(np.uint64)
            for offset, column in enumerate(bitbang):
                np.bitwise_xor(hashable, column << (offset * precision), out=hashable)
            return hashable
    dtype = np.dtype((np.void, data.dtype.itemsize * data.shape[1]))
    return np.ascontiguousarray(data).view(dtype).reshape(-1)
