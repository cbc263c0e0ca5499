"""`check`'s errors on the MJCF models MuJoCo loads, set against MuJoCo's compiled model.

A model MuJoCo compiles has inertials MuJoCo accepts: every error ``check`` reports on
one is false unless MuJoCo's own compiled inertial for that body is itself invalid (a
zero mass or a tensor breaking the triangle inequality MuJoCo lets through on a body
without joints). For every MJCF model of the installed collections (dm_control,
robosuite, gymnasium-robotics, metaworld) that ``mujoco.MjModel.from_xml_path`` loads,
this prints the models and errors counted, each error with MuJoCo's compiled mass and
principal moments of its body, and whether those are valid.

    python scripts/mjcf_errors.py [--packages dm_control,robosuite] [--sample N --seed S]

Exit status 1 when an error is found on a body whose compiled inertial MuJoCo holds
valid (a false error).
"""

from __future__ import annotations

import argparse
import importlib.util
import logging
import random
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))
from support.corpus import MJCF_COLLECTIONS  # noqa: E402

import urdfinertia  # noqa: E402


def models(packages: tuple[str, ...]) -> list[tuple[str, Path]]:
    """Every MJCF file of the installed ``packages``, as (package/relative, path)."""
    out = []
    for name in packages:
        spec = importlib.util.find_spec(name)
        if spec is None or not spec.submodule_search_locations:
            continue
        root = Path(next(iter(spec.submodule_search_locations)))
        for path in sorted(root.rglob("*.xml")):
            try:
                head = path.read_bytes()[:4096]
            except OSError:
                continue
            if b"<mujoco" in head:
                out.append((f"{name}/{path.relative_to(root).as_posix()}", path))
    return out


def compiled(path: Path) -> dict[str, tuple[float, np.ndarray, bool]] | None:
    """MuJoCo's compiled (mass, principal moments, has a joint) by body name (None: MuJoCo
    does not load the file)."""
    import mujoco

    try:
        m = mujoco.MjModel.from_xml_path(str(path))
    except Exception:  # noqa: BLE001 - any refusal: not a model MuJoCo loads
        return None
    out = {}
    for b in range(m.nbody):
        name = mujoco.mj_id2name(m, mujoco.mjtObj.mjOBJ_BODY, b) or f"body{b}"
        out[name] = (float(m.body_mass[b]), np.array(m.body_inertia[b]),
                     bool(m.body_jntnum[b] > 0))
    return out


def valid(mass: float, moments: np.ndarray) -> bool:
    """A body MuJoCo's compiled values describe: positive mass and moments holding the
    triangle inequality (to round-off)."""
    a, b, c = sorted(moments)
    tol = 1e-9 * max(c, 1e-30)
    return mass > 0 and a > 0 and a + b >= c - tol


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--packages", default=",".join(MJCF_COLLECTIONS))
    parser.add_argument("--sample", type=int, default=0, help="check N models at random")
    parser.add_argument("--seed", type=int, default=0)
    args = parser.parse_args(argv)
    logging.disable(logging.CRITICAL)
    found = models(tuple(args.packages.split(",")))
    if args.sample:
        found = sorted(random.Random(args.seed).sample(found, min(args.sample, len(found))))
    loaded = errors = false = 0
    start = time.perf_counter()
    for label, path in found:
        mj = compiled(path)
        if mj is None:
            continue
        loaded += 1
        result = urdfinertia.check(path)
        for f in result.findings:
            if f.severity != "error":
                continue
            errors += 1
            mass, moments, jointed = mj.get(f.link or "", (float("nan"), np.zeros(3), False))
            ok = f.link in mj and valid(mass, moments)
            false += ok
            print(f"{label}: {f.link}: {f.code}: {f.message[:120]}\n    MuJoCo compiles "
                  f"mass {mass:.4g}, moments {np.round(moments, 8).tolist()}, "
                  f"{'jointed' if jointed else 'no joint'}: "
                  f"{'valid (a false error)' if ok else 'invalid or absent'}")
    print(f"{loaded} of {len(found)} models load in MuJoCo; {errors} errors, {false} on "
          f"bodies MuJoCo compiles valid; {time.perf_counter() - start:.1f} s")
    return 1 if false else 0


if __name__ == "__main__":
    raise SystemExit(main())
