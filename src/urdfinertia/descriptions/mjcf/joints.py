"""An MJCF joint's motion for whole-robot statics: axis, range and the effort that drives it.

* `axis` (default `0 0 1`) is in the body frame (turned by any `<frame>` the joint
  stands in), the model's joint frame; `pos` is where the axis passes.
* `range` counts only when the joint is limited: `limited="true"`, or `"auto"` (the
  default, with `<compiler autolimits>` true, MuJoCo's default) when a range is given;
  a hinge's range is in the compiler's angle unit (degrees unless `angle="radian"`).
* The effort is the sum over the actuators on the joint (`joint=` transmission) of
  `|gear| x` their largest force, clamped by the joint's `actuatorfrcrange` when that
  is limited (same rule, with `actuatorfrclimited`), which alone is the effort of a
  joint no actuator names. An actuator's largest force: `motor` and `general` (fixed
  gain, no bias) give `|gain| x max|ctrlrange|` when ctrl-limited, clamped by
  `max|forcerange|` when force-limited; any other actuator (a position servo pushes as
  hard as its error asks) only its `forcerange`. An actuator with no bound leaves the
  joint with no effort (not judged), with a note.

A joint whose axis misses the body's origin is read with no effort (the model turns every
joint about its child link's origin), with a note. MuJoCo itself is the reference of the
tests (its compiled `jnt_axis`, `jnt_range`, `actuator_*`).
"""

from __future__ import annotations

import math

import numpy as np
from lxml import etree

from urdfinertia.descriptions.mjcf.document import MjcfDocument, Source
from urdfinertia.descriptions.mjcf.numbers import GeomError, numbers
from urdfinertia.findings import Finding
from urdfinertia.rules import Rule

ACTUATOR_TAGS = ("general", "motor", "position", "velocity", "intvelocity", "damper",
                 "cylinder", "muscle", "adhesion", "plugin")
"""MJCF's actuator elements (the shortcuts and `general`)"""


def _limited(attrs: dict[str, str], flag: str, values: str, doc: MjcfDocument) -> bool:
    """MuJoCo's `limited` rule: "true", or "auto" with the range stated (autolimits)."""
    value = attrs.get(flag, "auto").strip().lower()
    if value == "auto":
        auto = doc.compiler.get("autolimits", "true").strip().lower() == "true"
        return auto and values in attrs
    return value == "true"


def _largest(attrs: dict[str, str], key: str) -> float:
    lo, hi = numbers(attrs[key], 2, key)
    return max(abs(lo), abs(hi))


def joint_motion(attrs: dict[str, str], kind: str, frame: np.ndarray, doc: MjcfDocument,
                 ) -> tuple[dict[str, object], np.ndarray]:
    """Keyword arguments of `Joint` (`axis`,
    `lower`, `upper`, and `effort` from `actuatorfrcrange`) of a hinge or slide
    with class-resolved `attrs` standing in `frame` of its body; and the point its axis
    passes through, in the body frame. Raises `GeomError` on an unreadable value."""
    out: dict[str, object] = {}
    axis = np.asarray(numbers(attrs.get("axis", "0 0 1"), 3, "axis"))
    if not np.linalg.norm(axis) > 0:
        raise GeomError('axis="0 0 0" has no direction')
    axis = frame[:3, :3] @ (axis / np.linalg.norm(axis))
    out["axis"] = tuple(float(v) for v in axis)
    point = frame[:3, :3] @ np.asarray(numbers(attrs.get("pos", "0 0 0"), 3, "pos")) + frame[
        :3, 3]
    if _limited(attrs, "limited", "range", doc):
        lo, hi = numbers(attrs.get("range", "0 0"), 2, "range")
        if kind == "revolute" and doc.degrees:
            lo, hi = math.radians(lo), math.radians(hi)
        out["lower"], out["upper"] = lo, hi
    if _limited(attrs, "actuatorfrclimited", "actuatorfrcrange", doc):
        out["effort"] = _largest(attrs, "actuatorfrcrange")
    return out, point


def _actuator_attrs(doc: MjcfDocument, el: etree._Element, src: Source) -> dict[str, str]:
    """An actuator's attributes over its class's: MuJoCo keeps one actuator default per
    class, which every actuator element of the class sets."""
    cls = doc.defaults.get(el.get("class", "main"), {})
    merged: dict[str, str] = {}
    for tag, attrs in cls.items():
        if tag in ACTUATOR_TAGS:
            merged.update(attrs)
    return {**merged, **el.attrib}


def _force(tag: str, attrs: dict[str, str], doc: MjcfDocument) -> float | None:
    """The largest force (before the gear) an actuator gives; None: unbounded."""
    bounds = []
    plain = tag == "motor" or (tag == "general" and attrs.get("gaintype", "fixed") == "fixed"
                               and attrs.get("biastype", "none") == "none"
                               and attrs.get("dyntype", "none") == "none")
    if plain and _limited(attrs, "ctrllimited", "ctrlrange", doc):
        gain = 1.0 if tag == "motor" else numbers(attrs.get("gainprm", "1"), 10, "gainprm",
                                                  at_least=1)[0]
        bounds.append(abs(gain) * _largest(attrs, "ctrlrange"))
    if _limited(attrs, "forcelimited", "forcerange", doc):
        bounds.append(_largest(attrs, "forcerange"))
    return min(bounds) if bounds else None


def actuator_efforts(doc: MjcfDocument) -> tuple[dict[str, float | None], list[Finding]]:
    """Per joint name, the summed largest torque (force) of the actuators on it (None: one
    of them is unbounded); and findings on what could not be read or bounded."""
    efforts: dict[str, float | None] = {}
    notes: list[Finding] = []
    for section, src in doc.children(doc.main.root, doc.main):
        if section.tag != "actuator":
            continue
        for el, esrc in doc.children(section, src):
            joint = el.get("joint")
            if el.tag not in ACTUATOR_TAGS or not joint:
                continue
            where = f"<{el.tag}> at {esrc.path.name}:{el.sourceline}"
            try:
                attrs = _actuator_attrs(doc, el, esrc)
                gear = abs(numbers(attrs.get("gear", "1"), 6, "gear", at_least=1)[0])
                force = _force(el.tag, attrs, doc)
            except GeomError as exc:
                notes.append(Finding(Rule.JOINT_UNREADABLE, None, f"{where}: {exc}; joint "
                                     f"'{joint}' is not judged", el.sourceline, where))
                efforts[joint] = None
                continue
            if force is None:
                notes.append(Finding(Rule.READER_NOTE, None, f"{where} on joint '{joint}' "
                                     "has no force bound (no forcerange, and no ctrlrange a "
                                     "gain turns into one): not judged", el.sourceline))
                efforts[joint] = None
            elif joint not in efforts or efforts[joint] is not None:
                efforts[joint] = (efforts.get(joint) or 0.0) + gear * force
    return efforts, notes
