"""What an engine does to inertials without refusing: defaults, replacements, bounds.

PyBullet gives a link without `<inertial>` 1 kg and a unit diagonal, and sets the
tensor of a link it finds "bad" (its own triangle-inequality test after diagonalising) to
zero, both with a console warning only. MuJoCo computes a missing inertial from the
collision geometry at 1000 kg/m^3, and applies `boundmass`, `boundinertia`,
`balanceinertia` and `inertiafromgeom` when the URDF's `<mujoco><compiler>` asks.
Pinocchio's URDF parser (urdfdom) prints an error for a value it cannot parse and goes on.
"""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np

from urdfinertia.analysis.check import Finding
from urdfinertia.descriptions.inertial import RawInertial
from urdfinertia.descriptions.kinematics import Kinematics
from urdfinertia.descriptions.model import Robot
from urdfinertia.engines.prepare import mujoco_compiler_options
from urdfinertia.rules import Rule

_CHANGED = 1e-3
"""Relative difference of principal moments that counts as a change (float32 in Bullet)"""


def silent_findings(engine: str, result: dict, robot: Robot, data: bytes, path: Path,
                    output: str) -> list[Finding]:
    """The inertials an engine loaded but simulates differently (UI406, UI407).

    Parameters
    ----------
    engine : str
        The engine.
    result : dict
        Its probe's result.
    robot : Robot
        The model as read.
    data : bytes
        The document.
    path : Path
        Its file.
    output : str
        Where the finding says the values are ("input", "output").

    Returns
    -------
    list of Finding
        One per link whose inertial the engine replaces.
    """
    if engine == "pybullet":
        return _pybullet(result, robot, output)
    if engine == "mujoco":
        return _mujoco(result, robot, data, path)
    if engine == "pinocchio":
        return _parser_errors(output, robot, "Pinocchio")
    return []


def _no_inertial_moving(robot: Robot) -> list[str]:
    kin = Kinematics(robot)
    return [link.name for link in robot.links if link.inertial is None and kin.moves(link.name)]


def _pybullet(result: dict, robot: Robot, output: str) -> list[Finding]:
    out = []
    bodies = result["bodies"]
    for name in _no_inertial_moving(robot):
        body = bodies.get(name)
        if body is not None and body["mass"] is not None and body["mass"] > 0:
            out.append(Finding(Rule.ENGINE_DEFAULT_INERTIAL, name,
                               f"PyBullet gives this link without <inertial> "
                               f"{body['mass']:g} kg and inertia diagonal "
                               f"{_fmt(body['inertia'])} kg m^2"))
    zeroed = set(re.findall(r"setting inertia to zero for link: (\S+)", output))
    for link in robot.links:
        body = bodies.get(link.name)
        if link.inertial is None or body is None or None in body["inertia"]:
            continue
        written = _principal(link)
        used = np.sort(np.asarray(body["inertia"], dtype=float))
        if written is None or _close(written, used):
            continue
        why = (" (its 'bad inertia tensor' test: A + B < C after diagonalising)"
               if link.name in zeroed else "")
        out.append(Finding(Rule.ENGINE_CHANGES_INERTIAL, link.name,
                           f"PyBullet uses principal moments {_fmt(used)} instead of the "
                           f"written {_fmt(written)} kg m^2{why}"))
    return out


def _principal(link) -> np.ndarray | None:
    raw = RawInertial.from_inertial(link.inertial)
    if not np.all(np.isfinite(raw.inertia)):
        return None
    return np.sort(np.linalg.eigvalsh(raw.inertia))


def _close(a: np.ndarray, b: np.ndarray) -> bool:
    scale = max(float(np.max(np.abs(a))), float(np.max(np.abs(b))), 1e-300)
    return bool(np.all(np.abs(a - b) <= _CHANGED * scale))


def _fmt(values) -> str:
    return "(" + ", ".join(f"{float(x):.4g}" for x in values) + ")"


def _mujoco(result: dict, robot: Robot, data: bytes, path: Path) -> list[Finding]:
    out = []
    kin = Kinematics(robot)
    bodies = result["bodies"]
    for name in _no_inertial_moving(robot):
        body = bodies.get(name)
        carried = [m for m in kin.group_of(name).members
                   if m != name and robot.link(m).inertial is not None]
        if body is not None and body["mass"] and not carried:
            out.append(Finding(Rule.ENGINE_DEFAULT_INERTIAL, name,
                               f"MuJoCo computes {body['mass']:.4g} kg for this link without "
                               "<inertial> from its collision geometry at 1000 kg/m^3"))
    options = mujoco_compiler_options(data, path)
    if options.get("inertiafromgeom", "").lower() == "true":
        out.append(Finding(Rule.ENGINE_CHANGES_INERTIAL, None,
                           "<mujoco><compiler inertiafromgeom=\"true\"> makes MuJoCo ignore "
                           "every <inertial> and use the collision geometry"))
    out.extend(_mujoco_bounds(robot, kin, options))
    return out


def _mujoco_bounds(robot: Robot, kin: Kinematics, options: dict[str, str]) -> list[Finding]:
    """Links MuJoCo's compiler options change, computed from the written values."""
    out = []
    boundmass = _float(options.get("boundmass"))
    boundinertia = _float(options.get("boundinertia"))
    balance = options.get("balanceinertia", "").lower() == "true"
    for link in robot.links:
        if link.inertial is None or not kin.moves(link.name):
            continue
        raw = RawInertial.from_inertial(link.inertial)
        if boundmass and np.isfinite(raw.mass) and raw.mass < boundmass:
            out.append(Finding(Rule.ENGINE_CHANGES_INERTIAL, link.name,
                               f"MuJoCo's boundmass={boundmass:g} raises the written "
                               f"{raw.mass:.4g} kg"))
        moments = _principal(link)
        if moments is None:
            continue
        if boundinertia and moments[0] < boundinertia:
            out.append(Finding(Rule.ENGINE_CHANGES_INERTIAL, link.name,
                               f"MuJoCo's boundinertia={boundinertia:g} raises principal "
                               f"moments {_fmt(moments)} kg m^2"))
        if balance and moments[0] + moments[1] < moments[2]:
            out.append(Finding(Rule.ENGINE_CHANGES_INERTIAL, link.name,
                               f"MuJoCo's balanceinertia replaces principal moments "
                               f"{_fmt(moments)} kg m^2 (A + B < C) instead of refusing them"))
    return out


def _float(text: str | None) -> float | None:
    try:
        return float(text) if text is not None else None
    except ValueError:
        return None


def _parser_errors(output: str, robot: Robot, label: str) -> list[Finding]:
    """urdfdom's "Error: ..." lines: it skips what it cannot parse and carries on."""
    out = []
    lines = output.splitlines()
    for i, line in enumerate(lines):
        if not line.strip().startswith("Error:"):
            continue
        text = line.strip()[len("Error:"):].strip()
        if "nertia" not in text and "ass" not in text:
            continue
        nxt = " ".join(lines[i + 1:i + 3])
        named = re.search(r"Link \[([^\]]+)\]", text + " " + nxt)
        link = named.group(1) if named and named.group(1) in {
            lk.name for lk in robot.links} else None
        out.append(Finding(Rule.ENGINE_CHANGES_INERTIAL, link,
                           f"{label}'s URDF parser: {text} (it loads the robot anyway)"))
    return out
