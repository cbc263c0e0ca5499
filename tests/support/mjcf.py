"""MuJoCo as the reference for MJCF tests: compiled body inertias, and byte comparisons."""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np

from urdfinertia.descriptions.mjcf.orientation import quat_matrix
from urdfinertia.descriptions.mjcf.write import scan_bodies


def compiled(path: Path, *, exact_meshes: bool = False):
    """MuJoCo's compiled model of ``path`` (meshes with ``inertia="exact"`` if asked)."""
    import mujoco

    if not exact_meshes:
        return mujoco.MjModel.from_xml_path(str(path))
    spec = mujoco.MjSpec.from_file(str(path))
    for mesh in spec.meshes:
        mesh.inertia = mujoco.mjtMeshInertia.mjMESH_INERTIA_EXACT
    return spec.compile()


def body_inertia(model, name: str) -> tuple[float, np.ndarray, np.ndarray]:
    """(mass, CoM, tensor about the CoM along the body frame's axes) MuJoCo compiled."""
    # an unnamed body "body#K" is the K-th body in document order: MuJoCo's body id K
    body = model.body(int(name[5:]) if name.startswith("body#") else name)
    r = quat_matrix(tuple(body.iquat))
    return float(body.mass[0]), np.array(body.ipos), r @ np.diag(body.inertia) @ r.T


_SPACE_BEFORE = re.compile(rb"[ \t]*\r?\n?[ \t]*\Z")


def strip_inertials(data: bytes) -> bytes:
    """``data`` without any body's ``<inertial>`` (nor the white space before it)."""
    spans = sorted(s.inertial for s in scan_bodies(data).values() if s.inertial is not None)
    out = bytearray()
    pos = 0
    for start, end in spans:
        head = data[pos:start]
        out += head[: _SPACE_BEFORE.search(head).start()]
        pos = end
    out += data[pos:]
    return bytes(out)
