"""Run the probes in child processes and turn what the engines did into findings."""

from __future__ import annotations

import importlib.util
import json
import os
import re
import subprocess
import sys
import tempfile
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path

import urdfinertia
from urdfinertia.analysis.check import Finding
from urdfinertia.descriptions.formats import read_bytes
from urdfinertia.descriptions.model import Robot
from urdfinertia.engines.prepare import prepare_urdf
from urdfinertia.engines.silent import silent_findings
from urdfinertia.errors import UrdfInertiaError
from urdfinertia.rules import Rule


@dataclass(frozen=True)
class EngineSpec:
    name: str
    label: str
    module: str  # what is imported
    pip: str  # what is installed


ENGINES: dict[str, EngineSpec] = {
    "mujoco": EngineSpec("mujoco", "MuJoCo", "mujoco", "mujoco"),
    "pinocchio": EngineSpec("pinocchio", "Pinocchio", "pinocchio", "pin"),
    "pybullet": EngineSpec("pybullet", "PyBullet", "pybullet", "pybullet"),
}
DEFAULT_TIMEOUT = 120.0
"""Seconds a child may take to load and step one robot before it counts as hung."""
_BAD_STATE = ("mjWARN_BADQACC", "mjWARN_BADQPOS", "mjWARN_BADQVEL", "mjWARN_BADCTRL")
"""MuJoCo warnings that mean the simulation state went bad (MuJoCo then resets it)"""


def parse_engines(text: str) -> tuple[str, ...]:
    """`mujoco,pybullet` -> names; `all` is every known engine."""
    names = [n.strip().lower() for n in text.split(",") if n.strip()]
    if names == ["all"]:
        return tuple(ENGINES)
    unknown = [n for n in names if n not in ENGINES]
    if unknown or not names:
        raise ValueError(f"unknown engine(s) {', '.join(unknown) or '(none)'}; choose from "
                         f"{', '.join(ENGINES)} or all")
    return tuple(dict.fromkeys(names))


def installed(name: str) -> bool:
    """Whether engine `name` can be imported (without importing it).

    Parameters
    ----------
    name : str
        "mujoco", "pinocchio" or "pybullet".

    Returns
    -------
    bool
        True when its module is found.
    """
    return importlib.util.find_spec(ENGINES[name].module) is not None


@dataclass(frozen=True)
class Outcome:
    """What one engine did with one description: the probe's result, or why there is none."""

    engine: str
    result: dict | None = None
    failure: str | None = None  # crashed, timed out, not installed, cannot prepare
    output: str = ""  # the child's stdout and stderr (the engine's own messages)
    missing: bool = False

    @property
    def accepted(self) -> bool:
        """The engine loaded the description."""
        return self.result is not None and bool(self.result["accepted"])


def run_probe(engine: str, urdf: Path, *, seconds: float, timeout: float,
              shown_as: Path | None = None) -> Outcome:
    """Load and step `urdf` in `engine` in a child process; messages naming `urdf`
    name `shown_as` instead (the user's file, not the engine's temporary copy)."""
    outcome = _run_probe(engine, urdf, seconds=seconds, timeout=timeout)
    if shown_as is None:
        return outcome
    result = outcome.result
    if result is not None and result["message"]:
        result = {**result, "message": result["message"].replace(str(urdf), str(shown_as))}
    return Outcome(engine, result, outcome.failure,
                   outcome.output.replace(str(urdf), str(shown_as)), outcome.missing)


def _run_probe(engine: str, urdf: Path, *, seconds: float, timeout: float) -> Outcome:
    src = str(Path(urdfinertia.__file__).resolve().parents[1])
    env = dict(os.environ)
    env["PYTHONPATH"] = os.pathsep.join(p for p in (src, env.get("PYTHONPATH")) if p)
    out = urdf.parent / f"{engine}.json"
    cmd = [sys.executable, "-m", "urdfinertia.engines.probe", engine, str(urdf), str(out),
           "--seconds", repr(seconds)]
    try:
        proc = subprocess.run(cmd, capture_output=True, timeout=timeout, env=env,
                              cwd=urdf.parent, stdin=subprocess.DEVNULL)
    except subprocess.TimeoutExpired as exc:
        output = _text(exc.stdout) + _text(exc.stderr)
        return Outcome(engine, failure=f"did not finish within {timeout:g} s", output=output)
    output = _text(proc.stdout) + _text(proc.stderr)
    if proc.returncode != 0 or not out.is_file():
        how = (f"was killed by signal {-proc.returncode}" if proc.returncode < 0
               else f"exited with code {proc.returncode}")
        return Outcome(engine, failure=how, output=output)
    return Outcome(engine, json.loads(out.read_text()), output=output)


def _text(data: bytes | str | None) -> str:
    if data is None:
        return ""
    return data if isinstance(data, str) else data.decode("utf-8", errors="replace")


@dataclass(frozen=True)
class EngineCheck:
    """`--engines`: which engines, how long a passive run, how long before a child hangs."""

    engines: tuple[str, ...]
    seconds: float = 2.0
    timeout: float = DEFAULT_TIMEOUT

    def outcomes(self, path: Path, robot: Robot,
                 package_dirs: Mapping[str, Path] | None = None,
                 data: bytes | None = None) -> dict[str, Outcome]:
        """Load the description in each requested engine, each in a child process.

        Parameters
        ----------
        path : Path
            The description's file.
        robot : Robot
            Its model.
        package_dirs : mapping of str to Path, optional
            Where `package://` points.
        data : bytes, optional
            The document (default: read from `path`).

        Returns
        -------
        dict of str to Outcome
            Engine name -> what happened.
        """
        data = read_bytes(path) if data is None else data
        found: dict[str, Outcome] = {}
        for name in self.engines:
            if not installed(name):
                found[name] = Outcome(name, missing=True)
                continue
            with tempfile.TemporaryDirectory(prefix=f"urdfinertia-{name}-") as tmp:
                try:
                    copy = prepare_urdf(data, path, Path(tmp), for_mujoco=name == "mujoco",
                                        package_dirs=package_dirs)
                except UrdfInertiaError as exc:
                    found[name] = Outcome(name, failure=f"cannot prepare a copy: {exc.cause}")
                    continue
                found[name] = run_probe(name, copy, seconds=self.seconds,
                                        timeout=self.timeout, shown_as=path)
        return found

    def findings(self, path: Path, robot: Robot,
                 package_dirs: Mapping[str, Path] | None = None,
                 data: bytes | None = None) -> list[Finding]:
        """The findings of loading the description in each requested engine (UI4xx).

        Parameters
        ----------
        path : Path
            The description's file.
        robot : Robot
            Its model.
        package_dirs : mapping of str to Path, optional
            Where `package://` points.
        data : bytes, optional
            The document (default: read from `path`).

        Returns
        -------
        list of Finding
            One or more per engine; UI410 when no engine reads the format.
        """
        if robot.format != "urdf":
            return [Finding(Rule.ENGINE_SKIPPED, None,
                            f"engine checks read URDF only; this is {robot.format}")]
        data = read_bytes(path) if data is None else data
        out: list[Finding] = []
        for outcome in self.outcomes(path, robot, package_dirs, data).values():
            out.extend(outcome_findings(outcome, robot, data, path))
        return out


def outcome_findings(outcome: Outcome, robot: Robot, data: bytes, path: Path,
                     ) -> list[Finding]:
    """The findings of one engine's outcome.

    Parameters
    ----------
    outcome : Outcome
        What happened in the engine.
    robot : Robot
        The model it loaded.
    data : bytes
        The document.
    path : Path
        Its file.

    Returns
    -------
    list of Finding
        Refused, NaN, unstable, runaway, crashed, or inertials it replaces.
    """
    spec = ENGINES[outcome.engine]
    label = spec.label
    if outcome.missing:
        return [Finding(Rule.ENGINE_MISSING, None,
                        f"{label} is not installed, not checked: pip install {spec.pip} "
                        "(or pip install 'urdfinertia[engines]')")]
    if outcome.result is None:
        return [Finding(Rule.ENGINE_CRASHED, None,
                        f"{label} {outcome.failure} loading or stepping the robot"
                        f"{_tail(outcome.output)}")]
    r = outcome.result
    links = {link.name for link in robot.links}
    if not r["accepted"]:
        link = r["link"] if r["link"] in links else None
        message = r["message"] or "refused"
        reasons = [ln for ln in engine_lines(outcome.output) if "rror" in ln]
        extra = (": " + " | ".join(reasons[-3:])[:400]) if reasons else ""
        return [Finding(Rule.ENGINE_REFUSED, link,
                        f"{label} refuses to load it: {_one_line(message)}{extra}")]
    out: list[Finding] = []
    if r["nan_time"] is not None:
        out.append(Finding(Rule.ENGINE_NAN, None,
                           f"{label}: joint speeds became NaN after {r['nan_time']:.3g} s of "
                           "a passive run (gravity, zero controls)"))
    for warning, count in sorted(r["warnings"].items()):
        severe = warning in _BAD_STATE
        out.append(Finding(Rule.ENGINE_UNSTABLE if severe else Rule.ENGINE_WARNED, None,
                           f"{label} warned {warning} x{count} in a {r['seconds']:.3g} s "
                           f"passive run{' (it resets the simulation)' if severe else ''}"))
    for run in r["runaway"]:
        link = run["link"] if run["link"] in links else None
        out.append(Finding(Rule.ENGINE_RUNAWAY, link,
                           f"{label}: joint '{run['joint']}' reached {run['speed']:.3g} rad/s "
                           f"(or m/s) after {run['time']:.3g} s of a passive run"))
    out.extend(silent_findings(outcome.engine, r, robot, data, path, outcome.output))
    return out


def _one_line(text: str) -> str:
    return " ".join(text.split())


def engine_lines(output: str) -> list[str]:
    """An engine's console output as messages: Bullet's `b3Error[file,line]:` prefixes
    become line breaks (it prints the message after them), its banner is dropped."""
    text = re.sub(r"b3(Error|Warning|Printf)\[[^\]]*\]:\s*", r"\n\1: ", output)
    keep: list[str] = []
    for line in text.splitlines():
        line = line.strip()
        if line and "build time" not in line and (not keep or keep[-1] != line):
            keep.append(line)
    return keep


def _tail(output: str, lines: int = 3) -> str:
    """The engine's last few messages (a crash leaves no exception to quote)."""
    keep = engine_lines(output)
    return (": " + " | ".join(keep[-lines:])[:400]) if keep else ""


def stable(outcome: Outcome) -> bool:
    """Accepted, and the passive run stayed finite, calm and within speed."""
    r = outcome.result
    return (outcome.accepted and r is not None and r["nan_time"] is None and not r["runaway"]
            and not any(w in _BAD_STATE for w in r["warnings"]))


def regressions(before: Mapping[str, Outcome], after: Mapping[str, Outcome],
                ) -> list[Finding]:
    """What `fix` made worse in an engine: refused (error) or unstable (warning) output
    where the input was accepted or stable. Neither must ever happen."""
    out = []
    for name, old in before.items():
        new = after.get(name)
        if new is None or old.missing:
            continue
        label = ENGINES[name].label
        if old.accepted and not new.accepted:
            why = (new.result or {}).get("message") or new.failure or "refused"
            out.append(Finding(Rule.ENGINE_REGRESSION, None,
                               f"{label} loads the input but not the fixed output: "
                               f"{_one_line(str(why))}"))
        elif stable(old) and not stable(new):
            out.append(Finding(Rule.ENGINE_LESS_STABLE, None,
                               f"{label} runs the input stably but not the fixed output"))
    return out


def outcome_summary(outcome: Outcome) -> str:
    """One engine's outcome in a word or two ("stable", "refused", "not installed").

    Parameters
    ----------
    outcome : Outcome
        What happened.

    Returns
    -------
    str
        The summary.
    """
    if outcome.missing:
        return "not installed"
    if outcome.result is None:
        return str(outcome.failure)
    if not outcome.accepted:
        return "refused"
    return "stable" if stable(outcome) else "unstable"
