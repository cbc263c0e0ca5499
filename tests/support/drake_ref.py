"""Drake as a reference reader of SDFormat (and its ``fix_inertia``), run in a child process.

Drake comes from PyPI (the ``drake`` wheel, in the dev extra). The child is this interpreter
when it can import ``pydrake``, or the Python named by ``URDFINERTIA_DRAKE_PYTHON`` (a
separate environment that has it). The test command sets ``URDFINERTIA_REQUIRE_DRAKE=1`` so
that a missing Drake fails the comparison tests instead of skipping them. Run as a script
(``python drake_ref.py FILE [NAME=DIR ...]``) under that Python, this module prints one JSON
object: per body (scoped ``model::body``), the mass, the CoM and the inertia about the CoM in
the body frame, as Drake parsed them.
"""

from __future__ import annotations

import importlib.util
import json
import os
import subprocess
import sys
from pathlib import Path

REQUIRE_ENV = "URDFINERTIA_REQUIRE_DRAKE"


def drake_python() -> str | None:
    """A Python that imports ``pydrake``, or None."""
    env = os.environ.get("URDFINERTIA_DRAKE_PYTHON")
    if env:
        return env
    if importlib.util.find_spec("pydrake") is not None:
        return sys.executable
    return None


def drake_required() -> bool:
    """True where a missing Drake is a failure (the test command), not a reason to skip."""
    return os.environ.get(REQUIRE_ENV, "") not in ("", "0")


def drake_bodies(path: Path, package_dirs: dict[str, Path] | None = None,
                 timeout: float = 300.0) -> dict:
    """``{"bodies": {name: {mass, com, inertia}}}`` or ``{"error": text}``."""
    python = drake_python()
    if python is None:
        raise RuntimeError("no Python with pydrake: pip install drake (in the dev extra)")
    args = [python, __file__, str(path)]
    args += [f"{k}={v}" for k, v in (package_dirs or {}).items()]
    done = subprocess.run(args, capture_output=True, text=True, timeout=timeout)
    if done.returncode != 0:
        return {"error": (done.stderr.strip().splitlines() or ["?"])[-1]}
    return json.loads(done.stdout)


def drake_fix_inertia(src: Path, dst: Path, timeout: float = 300.0) -> str | None:
    """Run Drake's ``fix_inertia`` on ``src`` into ``dst``; None, or its last error line."""
    python = drake_python()
    if python is None:
        raise RuntimeError("no Python with pydrake: pip install drake (in the dev extra)")
    done = subprocess.run([python, "-m", "pydrake.multibody.fix_inertia", str(src), str(dst)],
                          capture_output=True, text=True, timeout=timeout,
                          env={**os.environ, "ROS_PACKAGE_PATH": os.environ.get(
                              "ROS_PACKAGE_PATH", "")})
    if done.returncode != 0:
        return (done.stderr.strip().splitlines() or ["?"])[-1]
    return None


def drake_batch(jobs: list[dict], timeout: float = 3600.0) -> list[dict]:
    """Many jobs in one Drake process: ``{"parse": path, "packages": {name: dir}}`` gives
    :func:`drake_bodies`'s answer, ``{"fix": src, "out": dst}`` runs ``fix_inertia``
    (``{"error": text}`` or ``{}``). Answers in the order of ``jobs``."""
    python = drake_python()
    if python is None:
        raise RuntimeError("no Python with pydrake: pip install drake (in the dev extra)")
    done = subprocess.run([python, __file__, "--batch"], input=json.dumps(jobs),
                          capture_output=True, text=True, timeout=timeout)
    if done.returncode != 0:
        raise RuntimeError(done.stderr.strip()[-2000:])
    return json.loads(done.stdout)


def _batch() -> int:  # runs under Drake's Python
    import contextlib
    import io

    from pydrake.multibody import _inertia_fixer

    answers = []
    for job in json.load(sys.stdin):
        try:
            with contextlib.redirect_stdout(io.StringIO()):
                if "fix" in job:
                    _inertia_fixer.InertiaFixer(
                        input_file=job["fix"], output_file=job["out"], in_place=False,
                        geom_inertia_role_order=_inertia_fixer.GEOM_INERTIA_ROLE_ORDER_DEFAULT,
                    ).fix_inertia()
                    answers.append({})
                else:
                    answers.append({"bodies": _bodies(job["parse"], job.get("packages", {}))})
        except Exception as exc:  # noqa: BLE001 - every failure is an answer
            answers.append({"error": f"{type(exc).__name__}: {str(exc).strip()[:300]}"})
    json.dump(answers, sys.stdout)
    return 0


def _bodies(path: str, packages: dict[str, str]) -> dict:
    from pydrake.multibody.parsing import Parser
    from pydrake.multibody.plant import MultibodyPlant
    from pydrake.multibody.tree import BodyIndex, RigidBody

    plant = MultibodyPlant(time_step=0.0)
    parser = Parser(plant)
    for name, folder in packages.items():
        parser.package_map().Add(name, folder)
    parser.AddModels(path)
    bodies = {}
    for i in range(plant.num_bodies()):
        body = plant.get_body(BodyIndex(i))
        if not isinstance(body, RigidBody) or body.name() == "world":
            continue
        m = body.default_spatial_inertia()
        com = m.get_com()
        about_com = m.Shift(com).CalcRotationalInertia().CopyToFullMatrix3()
        scoped = plant.GetModelInstanceName(body.model_instance()) + "::" + body.name()
        bodies[scoped] = {"mass": m.get_mass(), "com": list(com),
                          "inertia": about_com.tolist()}
    return bodies


def _main(argv: list[str]) -> int:  # runs under Drake's Python
    if argv == ["--batch"]:
        return _batch()
    packages = dict(item.partition("=")[::2] for item in argv[1:])
    json.dump({"bodies": _bodies(argv[0], packages)}, sys.stdout)
    return 0


if __name__ == "__main__":
    sys.path.pop(0)  # this folder: its modules must not shadow Drake's imports
    sys.exit(_main(sys.argv[1:]))
