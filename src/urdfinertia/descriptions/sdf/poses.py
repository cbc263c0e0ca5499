"""SDFormat poses and frames: `<pose>` text, and `relative_to` resolved as libsdformat does.

A `<pose>` is `x y z roll pitch yaw` (radians, or degrees with `degrees="true"`), the
rotation `Rz(yaw) Ry(pitch) Rx(roll)` as in URDF, or `x y z qx qy qz qw` with
`rotation_format="quat_xyzw"` (SDFormat 1.9+). Pose frame semantics (SDFormat 1.7+,
http://sdformat.org/tutorials?tut=pose_frame_semantics): inside one `<model>` every link,
joint, `<frame>` and nested model is a frame; a pose is relative to the frame named by
its `relative_to` attribute, else to a default: the model frame for links, nested models
and frames without `attached_to`; a frame's `attached_to`; a joint's child link; the
parent link for collisions, visuals and the inertial. `a::b` names frame `b` of nested
model `a`. SDFormat 1.5/1.6 wrote the attribute `frame`; libsdformat's 1.6 -> 1.7
conversion renames it to `relative_to`, and so is it read here.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np
from lxml import etree

from urdfinertia.errors import UrdfError
from urdfinertia.inertia.rotation import rpy_matrix

MODEL_FRAME = "__model__"
"""The implicit frame of every model (libsdformat's reserved name)."""


def parse_pose(el: etree._Element | None,
               numbers: Callable[[etree._Element, str], tuple[float, ...]],
               ) -> tuple[np.ndarray, str | None]:
    """(4, 4) transform of a `<pose>` element and its `relative_to` (None: default).

    `numbers(el, text)` turns the element's text into floats (the reader's checks).
    """
    if el is None:
        return np.eye(4), None
    relative_to = el.get("relative_to") or el.get("frame") or None
    values = numbers(el, el.text or "")
    fmt = (el.get("rotation_format") or "euler_rpy").strip()
    t = np.eye(4)
    if fmt == "quat_xyzw":
        if len(values) != 7:
            raise ValueError(f"<pose rotation_format=\"quat_xyzw\"> needs 7 numbers, "
                             f"got {len(values)}")
        t[:3, :3] = quat_xyzw_matrix(values[3:])
    elif fmt == "euler_rpy":
        if len(values) == 0:
            values = (0.0,) * 6
        if len(values) != 6:
            raise ValueError(f"<pose> needs 6 numbers, got {len(values)}")
        rpy = np.asarray(values[3:], dtype=np.float64)
        if (el.get("degrees") or "false").strip().lower() in ("true", "1"):
            rpy = np.radians(rpy)
        t[:3, :3] = rpy_matrix(rpy)
    else:
        raise ValueError(f"<pose rotation_format=\"{fmt}\"> is not euler_rpy or quat_xyzw")
    t[:3, 3] = values[:3]
    return t, relative_to


def quat_xyzw_matrix(q: tuple[float, ...]) -> np.ndarray:
    """Rotation of a quaternion `(x, y, z, w)`, normalised as libsdformat does."""
    x, y, z, w = q
    n = math.sqrt(x * x + y * y + z * z + w * w)
    if not n > 0:
        raise ValueError("quaternion of zero length")
    x, y, z, w = x / n, y / n, z / n, w / n
    return np.array([
        [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
        [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
        [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
    ])


def matrix_rpy(r: np.ndarray) -> tuple[float, float, float]:
    """`(roll, pitch, yaw)` of a rotation matrix: the inverse of `rpy_matrix`."""
    cp = math.hypot(float(r[0, 0]), float(r[1, 0]))
    pitch = math.atan2(-float(r[2, 0]), cp)
    if cp < 1e-12:  # gimbal lock: roll takes the whole turn about the common axis
        return math.atan2(-float(r[1, 2]), float(r[1, 1])), pitch, 0.0
    return math.atan2(float(r[2, 1]), float(r[2, 2])), pitch, math.atan2(float(r[1, 0]),
                                                                         float(r[0, 0]))


@dataclass
class FrameDef:
    """One frame of a model scope: its pose relative to `relative_to`."""

    pose: np.ndarray
    relative_to: str
    line: int | None = None


@dataclass
class Scope:
    """The frames of one `<model>`, expressed in its model frame on demand.

    Attributes
    ----------
    name : str
        The model's name.
    frames : dict of str to FrameDef
        Name -> definition (links, joints, `<frame>`s, nested models).
    nested : dict of str to Scope
        A nested model's name -> its own scope (the frames `name::x`).
    """

    name: str
    frames: dict[str, FrameDef] = field(default_factory=dict)
    nested: dict[str, Scope] = field(default_factory=dict)
    _resolved: dict[str, np.ndarray] = field(default_factory=dict)

    def add(self, name: str, pose: np.ndarray, relative_to: str, line: int | None) -> None:
        """Define frame `name` at `pose` relative to frame `relative_to`.

        Parameters
        ----------
        name : str
            The new frame's name.
        pose : (4, 4) float
            Its pose in `relative_to`.
        relative_to : str
            The frame the pose is given in.
        line : int or None
            Where it is defined, for errors.

        Raises
        ------
        UrdfError
            When the name is already used in the model.
        """
        if name == MODEL_FRAME or name in self.frames:
            raise UrdfError(f"frame name '{name}' is used twice in model '{self.name}'",
                            line=line)
        self.frames[name] = FrameDef(pose, relative_to, line)

    def in_model(self, name: str) -> np.ndarray:
        """(4, 4) pose of frame `name` (possibly `a::b`) in this model's frame."""
        return self._resolve(name, ())

    def _resolve(self, name: str, visiting: tuple[str, ...]) -> np.ndarray:
        if name == MODEL_FRAME:
            return np.eye(4)
        if name in self._resolved:
            return self._resolved[name]
        head, sep, rest = name.partition("::")
        if sep and head in self.nested:
            nested: np.ndarray = self._resolve(head, visiting) @ self.nested[head].in_model(rest)
            return nested
        frame = self.frames.get(name)
        if frame is None:
            raise UrdfError(f"pose is relative to '{name}', which is no frame of model "
                            f"'{self.name}'")
        if name in visiting:
            chain = " -> ".join((*visiting, name))
            raise UrdfError(f"poses relative to each other in a cycle: {chain}",
                            line=frame.line)
        found: np.ndarray = self._resolve(frame.relative_to, (*visiting, name)) @ frame.pose
        self._resolved[name] = found
        return found
