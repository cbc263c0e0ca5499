"""Load one URDF in one engine and step it passively: run in a child process.

`python -m urdfinertia.engines.probe ENGINE URDF OUT.json [--seconds S]` writes what
happened as JSON to OUT.json (stdout and stderr are left to the engine's own chatter,
which the parent keeps for refusal messages). The base is fixed to the world in every
engine, as arm users load it and as MuJoCo's URDF import does; gravity is -9.81 m/s^2
along z; controls are zero (PyBullet's default velocity motors are switched off).

A runaway must come from the inertials, not from how an engine is driven: joints stop at
their position limits in every engine (Pinocchio, which only integrates the dynamics, gets
an inelastic stop here), and PyBullet runs without the URDF's joint damping, which it
applies explicitly: damping 1 N m s/rad on a 1e-3 kg m^2 gripper at 1/240 s gives
damping * dt / I = 3.5, past the explicit scheme's limit of 2, and the joint oscillates
at its speed cap (talos's grippers) whatever its inertial.

Only this module imports the engines; a crash here (engines can segfault on bad inertia)
costs the child process, never the caller.
"""

from __future__ import annotations

import argparse
import json
import math
import re
import sys
from pathlib import Path

import numpy as np

RUNAWAY_SPEED = 100.0
"""A joint speed at or above this (rad/s or m/s) in a passive run is a runaway, not motion: under
gravity alone a swinging link reaches sqrt(2 g / k) rad/s at most (k its radius of gyration: 100
rad/s needs k < 2 mm). It is also PyBullet's own speed cap (maxJointVelocity), so a runaway there
shows as a speed pinned at it.
"""
PINOCCHIO_DT = 0.002
"""Pinocchio has no stepper: semi-implicit Euler with MuJoCo's default time step."""
GRAVITY = (0.0, 0.0, -9.81)


def _result(engine: str) -> dict:
    return {"engine": engine, "accepted": False, "message": None, "link": None,
            "nan_time": None, "warnings": {}, "runaway": [], "max_speed": 0.0,
            "bodies": {}, "parser_errors": [], "seconds": 0.0}


def _speeds(result: dict, t: float, names: list[tuple[str, str]], qvel: np.ndarray) -> bool:
    """Record NaN and runaways; True when the run should stop (NaN)."""
    if not np.all(np.isfinite(qvel)):
        result["nan_time"] = t
        return True
    speed = np.abs(qvel)
    if len(speed):
        result["max_speed"] = max(result["max_speed"], float(speed.max()))
    seen = {r["joint"] for r in result["runaway"]}
    for (joint, link), v in zip(names, speed, strict=True):
        if v >= RUNAWAY_SPEED * (1 - 1e-6) and joint not in seen:
            result["runaway"].append({"joint": joint, "link": link, "speed": float(v),
                                      "time": t})
    return False


def probe_mujoco(path: Path, seconds: float) -> dict:
    """Load `path` in MuJoCo and step a passive run (in this child process).

    Parameters
    ----------
    path : Path
        The description.
    seconds : float
        Simulated seconds.

    Returns
    -------
    dict
        JSON-ready: accepted, the error, NaN or instability, runaway joints, the masses and
        inertias the engine simulates.
    """
    import mujoco

    result = _result("mujoco")
    try:
        model = mujoco.MjModel.from_xml_path(str(path))
    except ValueError as exc:
        message = str(exc).strip()
        result["message"] = message
        named = re.search(r"(?:Element|Object) name\s*[=]?\s*'?([^',\n]+)'?", message)
        result["link"] = named.group(1).strip() if named else None
        return result
    result["accepted"] = True
    for b in range(1, model.nbody):
        result["bodies"][model.body(b).name] = {
            "mass": float(model.body_mass[b]),
            "inertia": [float(x) for x in model.body_inertia[b]]}
    data = mujoco.MjData(model)
    names = []
    for dof in range(model.nv):
        joint = model.dof_jntid[dof]
        names.append((model.joint(joint).name, model.body(model.jnt_bodyid[joint]).name))
    steps = max(1, round(seconds / model.opt.timestep))
    for k in range(steps):
        mujoco.mj_step(model, data)
        if _speeds(result, (k + 1) * model.opt.timestep, names, data.qvel):
            break
    for i in range(int(mujoco.mjtWarning.mjNWARNING)):
        count = int(data.warning[i].number)
        if count:
            result["warnings"][mujoco.mjtWarning(i).name] = count
    result["seconds"] = steps * model.opt.timestep
    return result


def probe_pybullet(path: Path, seconds: float) -> dict:
    """Load `path` in PyBullet (DIRECT) and step a passive run (in this child process).

    Parameters
    ----------
    path : Path
        The description.
    seconds : float
        Simulated seconds.

    Returns
    -------
    dict
        JSON-ready: accepted, the error, NaN, runaway joints, the masses and inertias the engine
        simulates.
    """
    import pybullet as p

    result = _result("pybullet")
    client = p.connect(p.DIRECT)
    try:
        p.setGravity(*GRAVITY, physicsClientId=client)
        try:
            body = p.loadURDF(str(path), useFixedBase=True,
                              flags=p.URDF_USE_INERTIA_FROM_FILE, physicsClientId=client)
        except p.error as exc:
            result["message"] = str(exc)
            return result
        result["accepted"] = True
        n = p.getNumJoints(body, physicsClientId=client)
        movable, names = [], []
        for j in range(n):
            info = p.getJointInfo(body, j, physicsClientId=client)
            link = info[12].decode()
            dyn = p.getDynamicsInfo(body, j, physicsClientId=client)
            result["bodies"][link] = {"mass": float(dyn[0]),
                                      "inertia": [float(x) for x in dyn[2]]}
            if info[2] != p.JOINT_FIXED:
                movable.append(j)
                names.append((info[1].decode(), link))
        for j in movable:  # explicit damping is unstable on light links (module doc)
            p.changeDynamics(body, j, jointDamping=0.0, physicsClientId=client)
        if movable:  # zero controls: PyBullet's default velocity motors hold the joints
            p.setJointMotorControlArray(body, movable, p.VELOCITY_CONTROL,
                                        forces=[0.0] * len(movable), physicsClientId=client)
        dt = 1.0 / 240.0  # PyBullet's default time step
        steps = max(1, round(seconds / dt))
        for k in range(steps):
            p.stepSimulation(physicsClientId=client)
            states = p.getJointStates(body, movable, physicsClientId=client) if movable else []
            qvel = np.array([s[1] for s in states], dtype=float)
            if _speeds(result, (k + 1) * dt, names, qvel):
                break
        result["seconds"] = steps * dt
    finally:
        p.disconnect(physicsClientId=client)
    return result


def probe_pinocchio(path: Path, seconds: float) -> dict:
    """Build `path`'s Pinocchio model and integrate a passive run (in this child process).

    Parameters
    ----------
    path : Path
        The description.
    seconds : float
        Simulated seconds.

    Returns
    -------
    dict
        JSON-ready: accepted, the error, NaN, runaway joints.
    """
    import pinocchio as pin

    result = _result("pinocchio")
    try:
        model = pin.buildModelFromUrdf(str(path))
    except (RuntimeError, ValueError) as exc:
        result["message"] = str(exc).strip()
        return result
    result["accepted"] = True
    model.gravity.linear = np.array(GRAVITY)
    data = model.createData()
    names = []
    for j in range(1, model.njoints):
        for _ in range(model.joints[j].nv):
            names.append((model.names[j], _child_body(model, j)))
    q, v = pin.neutral(model), np.zeros(model.nv)
    tau = np.zeros(model.nv)
    stops = _joint_stops(model)
    steps = max(1, round(seconds / PINOCCHIO_DT))
    with np.errstate(all="ignore"):
        for k in range(steps):
            a = pin.aba(model, data, q, v, tau)
            v = v + a * PINOCCHIO_DT
            if _speeds(result, (k + 1) * PINOCCHIO_DT, names, v):
                break
            q = pin.integrate(model, q, v * PINOCCHIO_DT)
            _stop_at_limits(q, v, stops)
    result["seconds"] = steps * PINOCCHIO_DT
    return result


def _joint_stops(model) -> list[tuple[int, int, float, float]]:
    """(q index, v index, lower, upper) of every one-coordinate joint with position limits.

    Pinocchio integrates the dynamics alone and enforces no limit; MuJoCo and PyBullet
    stop a joint at its limits. Without the stop, a passive prismatic finger (panda's, 4 cm
    of travel) falls forever and reaches any speed: a false runaway.
    """
    lower, upper = model.lowerPositionLimit, model.upperPositionLimit
    stops = []
    for j in range(1, model.njoints):
        joint = model.joints[j]
        if joint.nq != 1 or joint.nv != 1:
            continue  # continuous, spherical and free joints have no position limits
        lo, hi = float(lower[joint.idx_q]), float(upper[joint.idx_q])
        if math.isfinite(lo) and math.isfinite(hi) and lo <= hi:
            stops.append((joint.idx_q, joint.idx_v, lo, hi))
    return stops


def _stop_at_limits(q: np.ndarray, v: np.ndarray,
                    stops: list[tuple[int, int, float, float]]) -> None:
    """An inelastic stop: a joint past a limit is put back on it, its speed into the limit
    dropped (in place)."""
    for iq, iv, lo, hi in stops:
        if q[iq] < lo:
            q[iq] = lo
            v[iv] = max(v[iv], 0.0)
        elif q[iq] > hi:
            q[iq] = hi
            v[iv] = min(v[iv], 0.0)


def _child_body(model, joint: int) -> str:
    """The link a Pinocchio joint moves: the first body frame attached to it."""
    import pinocchio as pin

    for frame in model.frames:
        if frame.parentJoint == joint and frame.type == pin.FrameType.BODY:
            return frame.name
    return model.names[joint]


PROBES = {"mujoco": probe_mujoco, "pybullet": probe_pybullet, "pinocchio": probe_pinocchio}


def main(argv: list[str] | None = None) -> int:
    """The probe's command line: one engine, one file, the result as JSON in a file.

    Parameters
    ----------
    argv : list of str, optional
        The arguments (default: `sys.argv[1:]`).

    Returns
    -------
    int
        0.
    """
    parser = argparse.ArgumentParser(prog="urdfinertia.engines.probe")
    parser.add_argument("engine", choices=sorted(PROBES))
    parser.add_argument("urdf", type=Path)
    parser.add_argument("out", type=Path)
    parser.add_argument("--seconds", type=float, default=2.0)
    args = parser.parse_args(argv)
    result = PROBES[args.engine](args.urdf, args.seconds)
    args.out.write_text(json.dumps(_finite(result), allow_nan=False))
    return 0


def _finite(x: object) -> object:
    """JSON has no NaN: non-finite numbers (an engine's NaN mass) become None."""
    if isinstance(x, dict):
        return {k: _finite(v) for k, v in x.items()}
    if isinstance(x, list | tuple):
        return [_finite(v) for v in x]
    if isinstance(x, float) and not math.isfinite(x):
        return None
    return x


if __name__ == "__main__":
    sys.exit(main())
