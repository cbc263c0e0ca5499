"""An SDFormat joint's motion for whole-robot statics: axis, limits, effort and mimic.

The model wants the axis in the joint frame as URDF has it, which is the child link frame
(`Joint`). SDFormat writes `<axis><xyz>` (default
`0 0 1`) in the joint frame (the joint's `<pose>`, relative to its child link by
default), or in the frame its `expressed_in` attribute names (1.7+); up to 1.6,
`<use_parent_model_frame>true` puts it in the model frame, and up to 1.4 it always was
(libsdformat's 1.4 -> 1.5 conversion adds `use_parent_model_frame` true). The axis is
turned into the child link frame here.

`<limit>`: `lower`/`upper` (rad or m; SDFormat's defaults +-1e16 mean no limit) and
`effort` (N m or N; SDFormat's default -1, like any negative value, means no limit: the
joint is read as having no effort, so statics computes its load without judging it).
`<axis><mimic joint>` (1.11) with `<multiplier>` and `<offset>`.

A joint frame whose axis line misses the child link's origin (Drake's cart-pole pins its
pole 0.5 m from the pole's frame) cannot be said in the model, which turns every joint about
its child link's origin: such a joint is read with no effort (not judged) and a note says so.
An unreadable value is left at its default, with a note.
"""

from __future__ import annotations

import math

import numpy as np
from lxml import etree

from urdfinertia.descriptions.sdf.poses import MODEL_FRAME, Scope
from urdfinertia.descriptions.urdf.read import _NUMBER, MAX_MAGNITUDE
from urdfinertia.errors import UrdfError
from urdfinertia.findings import Finding
from urdfinertia.rules import Rule


def _unread(el: etree._Element, name: str, message: str) -> Finding:
    """What statics cannot read of joint ``name``'s motion (it judges the joint without)."""
    return Finding(Rule.JOINT_UNREADABLE, None, message, el.sourceline, f"joint '{name}'")

_UNLIMITED = 1e16
"""SDFormat's default limits (+-1e16) and anything beyond: no limit."""
_OFF_AXIS = 1e-9
"""An axis line this far (m) from the child link's origin is off it."""


def _child(el: etree._Element | None, tag: str) -> etree._Element | None:
    if el is None:
        return None
    for c in el:
        if isinstance(c.tag, str) and c.tag == tag:
            return c
    return None


def _floats(el: etree._Element, n: int, bound: float = MAX_MAGNITUDE,
            ) -> tuple[float, ...] | None:
    parts = (el.text or "").split()
    if len(parts) != n or not all(_NUMBER.match(p) for p in parts):
        return None
    values = tuple(float(p) for p in parts)
    return values if all(abs(v) <= bound for v in values) else None


def _axis_frame(axis: etree._Element | None, xyz: etree._Element | None,
                version: tuple[int, ...]) -> str | None:
    """The frame the axis is expressed in; None: the joint frame."""
    if xyz is not None and xyz.get("expressed_in"):
        return xyz.get("expressed_in")
    if version <= (1, 4):
        return MODEL_FRAME
    flag = _child(axis, "use_parent_model_frame")
    if version < (1, 7) and flag is not None and (flag.text or "").strip().lower() in (
            "true", "1"):
        return MODEL_FRAME
    return None


def joint_motion(el: etree._Element, scope: Scope, child: str, name: str,
                 version: tuple[int, ...], notes: list[Finding]) -> dict[str, object]:
    """Keyword arguments of [`Joint`][urdfinertia.descriptions.model.Joint] for `axis`,
    `lower`, `upper`, `effort` and `mimic` of joint `el` of model `scope`
    (`child`: its child link's name in that scope; `name`: as the robot names it)."""
    out: dict[str, object] = {}
    axis_el = _child(el, "axis")
    xyz = _child(axis_el, "xyz")
    local = el.get("name") or ""
    direction = np.array([0.0, 0.0, 1.0])
    if xyz is not None:
        read = _floats(xyz, 3)
        if read is None or not any(read):
            notes.append(_unread(el, name, f"<axis><xyz>{(xyz.text or '').strip()}</xyz> "
                                 f"unreadable (line {xyz.sourceline}): 0 0 1 taken"))
        else:
            direction = np.array(read)
    try:
        child_pose = scope.in_model(child)
        joint_pose = scope.in_model(local)
        frame = _axis_frame(axis_el, xyz, version)
        expressed = joint_pose if frame is None else scope.in_model(frame)
    except UrdfError as exc:
        notes.append(_unread(el, name, f"axis frame unresolved ({exc.cause}): statics "
                             "takes it as given, in the child link frame"))
        child_pose = joint_pose = expressed = np.eye(4)
    in_child = child_pose[:3, :3].T @ expressed[:3, :3] @ direction
    in_child = in_child / np.linalg.norm(in_child)
    out["axis"] = tuple(float(v) for v in in_child)
    limit = _child(axis_el, "limit")
    for key in ("lower", "upper", "effort"):
        item = _child(limit, key)
        if item is None:
            continue
        read = _floats(item, 1, math.inf)
        if read is None:
            notes.append(_unread(el, name, f"<limit><{key}> unreadable (line "
                                 f"{item.sourceline}): left out"))
            continue
        value = read[0]
        if key == "effort":
            out[key] = value if 0 <= value < _UNLIMITED else None
        elif abs(value) < _UNLIMITED:
            out[key] = value
    mimic = _child(axis_el, "mimic")
    if mimic is not None and mimic.get("joint"):
        prefix = name[:len(name) - len(local)]
        factors = []
        for key, default in (("multiplier", 1.0), ("offset", 0.0)):
            item = _child(mimic, key)
            read = _floats(item, 1) if item is not None else None
            factors.append(read[0] if read is not None else default)
        out["mimic"] = (prefix + (mimic.get("joint") or ""), factors[0], factors[1])
    point = (np.linalg.inv(child_pose) @ joint_pose)[:3, 3]
    if np.all(np.isfinite(point)) and float(np.linalg.norm(point)) > _OFF_AXIS:
        out["axis_point"] = tuple(float(v) for v in point)
    return out
