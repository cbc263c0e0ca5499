"""MJCF side by side with MuJoCo's compiler, on real MJCF packages.

For every model of the corpus manifest that MuJoCo loads as it is:

* MuJoCo's own derivation from the geoms (``inertiafromgeom="true"``), once with the
  mesh inertia mode the file asks for (MuJoCo's default, "legacy") and once with
  ``inertia="exact"`` on every mesh (where that compiles);
* this tool's derivation from the same geoms (``fix --mass density``) and what ``fix``
  writes by default (existing masses kept);
* whether the fixed file compiles in MuJoCo, compiles with ``inertiafromgeom="false"``
  (the written values alone), and runs 2 s passive without MuJoCo instability warnings
  (the input is run too: a model unstable before is not counted against the output).

Prints one row per package and, with ``--bodies FILE``, writes one row per body (TSV).
The fixed file is written for MuJoCo next to its input under a temporary name (meshes and
includes resolve relative to the model's folder) and removed at once.

    python scripts/bench_mjcf.py [--packages dm_control,robosuite] [--corpus DIR]

Models: by default every MJCF file of the robot packages found
(``support.corpus.robot_packages``); ``--corpus DIR`` reads ``DIR/manifest.json`` instead
(a list of ``{"package": ..., "path": ...}``).
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import sys
import time
from collections import defaultdict
from pathlib import Path

import numpy as np

from urdfinertia.body.options import FixOptions
from urdfinertia.cache.library import MeshLibrary
from urdfinertia.plan.fix import fix_file


def _mujoco():
    import mujoco

    return mujoco


def derived(path: Path, exact: bool):
    """MuJoCo's body masses and inertias from the geoms, or the compile error."""
    mj = _mujoco()
    try:
        spec = mj.MjSpec.from_file(str(path))
        spec.compiler.inertiafromgeom = mj.mjtInertiaFromGeom.mjINERTIAFROMGEOM_TRUE
        if exact:
            for mesh in spec.meshes:
                mesh.inertia = mj.mjtMeshInertia.mjMESH_INERTIA_EXACT
        model = spec.compile()
    except Exception as exc:  # noqa: BLE001 - MuJoCo's compile errors are the result
        return str(exc).splitlines()[0][:80]
    return {model.body(i).name: (float(model.body_mass[i]), np.array(model.body_inertia[i]))
            for i in range(1, model.nbody)}


def stable(model) -> bool:
    """2 s of passive simulation without MuJoCo's instability warnings or NaN."""
    mj = _mujoco()
    data = mj.MjData(model)
    steps = int(round(2.0 / model.opt.timestep))
    for _ in range(steps):
        mj.mj_step(model, data)
    bad = data.warning[mj.mjtWarning.mjWARN_BADQACC].number
    return bad == 0 and bool(np.all(np.isfinite(data.qpos)))


def load(path: Path, explicit_only: bool = False):
    mj = _mujoco()
    try:
        spec = mj.MjSpec.from_file(str(path))
        if explicit_only:
            spec.compiler.inertiafromgeom = mj.mjtInertiaFromGeom.mjINERTIAFROMGEOM_FALSE
        return spec.compile()
    except Exception as exc:  # noqa: BLE001
        return str(exc).splitlines()[0][:80]


def run_file(path: Path, meshes: MeshLibrary) -> dict:
    row: dict = {"file": str(path)}
    model_in = load(path)
    if isinstance(model_in, str):
        row["input"] = model_in
        return row
    row["input_stable"] = stable(model_in)
    try:
        kept = fix_file(path, FixOptions(recompute="all"), meshes)
        geometric = fix_file(path, FixOptions(mass="density", recompute="all"), meshes)
    except Exception as exc:  # noqa: BLE001 - the benchmark records every failure
        row["fix"] = f"{type(exc).__name__}: {exc}"[:160]
        return row
    row["fix"] = "written"
    row["untouched"] = sum(r.assembly is None for r in kept.links)
    tmp = path.with_name(f".{path.stem}.urdfinertia-bench-{os.getpid()}.xml")
    try:
        tmp.write_bytes(kept.output)
        out = load(tmp)
        row["compiles"] = not isinstance(out, str)
        if isinstance(out, str):
            row["compile_error"] = out
        explicit = load(tmp, explicit_only=True)
        row["explicit"] = not isinstance(explicit, str)
        if isinstance(explicit, str):
            row["explicit_error"] = explicit
        row["output_stable"] = stable(out) if row["compiles"] else None
    finally:
        tmp.unlink(missing_ok=True)
    legacy = derived(path, exact=False)
    exact = derived(path, exact=True)
    row["exact"] = exact if isinstance(exact, str) else "ok"
    bodies = []
    written = {r.name: r for r in kept.links}
    for r in geometric.links:
        if r.assembly is None:
            continue
        body = {"body": r.name, "ours": r.assembly.total.mass,
                "ours_moments": np.linalg.eigvalsh(r.assembly.total.inertia).tolist()}
        w = written.get(r.name)
        if w is not None and w.assembly is not None:
            body["written"] = w.assembly.total.mass
        for key, found in (("legacy", legacy), ("mj_exact", exact)):
            if isinstance(found, dict) and r.name in found:
                body[key] = found[r.name][0]
                body[key + "_moments"] = sorted(found[r.name][1].tolist())
        bodies.append(body)
    row["bodies"] = bodies
    return row


def _ratio_stats(bodies: list[dict], key: str) -> tuple[int, float | None, int]:
    """(bodies compared, median |ratio - 1| in %, bodies off by more than 1 %)."""
    errs = [abs(b[key] / b["ours"] - 1.0) * 100 for b in bodies if key in b and b["ours"] > 0]
    if not errs:
        return 0, None, 0
    return len(errs), statistics.median(errs), sum(e > 1.0 for e in errs)


def summarise(rows: list[dict], package: str) -> str:
    loaded = [r for r in rows if "input" not in r]
    wrote = [r for r in loaded if r.get("fix") == "written"]
    bodies = [b for r in wrote for b in r.get("bodies", [])]
    n_leg, med_leg, off_leg = _ratio_stats(bodies, "legacy")
    n_ex, med_ex, off_ex = _ratio_stats(bodies, "mj_exact")
    exact_ok = sum(r.get("exact") == "ok" for r in wrote)
    stable_in = [r for r in wrote if r.get("input_stable")]

    def pct(v: float | None) -> str:
        return "-" if v is None else f"{v:.2g} %"

    return (f"| {package} | {len(rows)} | {len(loaded)} | {len(wrote)} | "
            f"{sum(bool(r.get('compiles')) for r in wrote)} | "
            f"{sum(bool(r.get('explicit')) for r in wrote)} | "
            f"{sum(bool(r.get('output_stable')) for r in stable_in)}/{len(stable_in)} | "
            f"{len(bodies)} | {pct(med_leg)} ({off_leg}/{n_leg} > 1 %) | "
            f"{exact_ok} | {pct(med_ex)} ({off_ex}/{n_ex} > 1 %) |")


HEADER = (
    "| package | models | MuJoCo loads | fix wrote | output compiles | compiles with "
    "inertiafromgeom=false | stable 2 s (of stable inputs) | bodies computed | MuJoCo "
    "default vs ours: median mass diff (bodies > 1 %) | models compiling with exact | "
    "MuJoCo exact vs ours: median (bodies > 1 %) |\n|---|---|---|---|---|---|---|---|---|---|---|"
)


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--corpus", type=Path, help="a folder with manifest.json")
    p.add_argument("--packages", help="comma-separated; default: every package found")
    p.add_argument("--bodies", type=Path, help="write per-body rows (TSV) here")
    p.add_argument("--json", type=Path, help="write every row as JSON here")
    args = p.parse_args(argv)
    if args.corpus is not None:
        manifest = [{"package": e["package"], "path": str(args.corpus / e["path"])}
                     for e in json.loads((args.corpus / "manifest.json").read_text())]
    else:
        sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))
        from support.corpus import robot_packages

        manifest = [{"package": pkg, "path": str(f)}
                    for pkg, files in robot_packages(("mjcf",)).items() for f in files]
    packages = (args.packages.split(",") if args.packages
                else list(dict.fromkeys(e["package"] for e in manifest)))
    meshes = MeshLibrary()
    rows: dict[str, list[dict]] = defaultdict(list)
    start = time.perf_counter()
    for entry in manifest:
        if entry["package"] not in packages:
            continue
        row = run_file(Path(entry["path"]), meshes)
        rows[entry["package"]].append(row)
        status = row.get("input") and "input does not load" or row.get("fix")
        print(f"{entry['path']}: {status}", file=sys.stderr, flush=True)
    print(f"\n{time.perf_counter() - start:.0f} s\n")
    print(HEADER)
    for package in packages:
        print(summarise(rows[package], package))
    problems = [(pkg, r) for pkg, rs in rows.items() for r in rs
                if "input" not in r and (r.get("fix") != "written" or not r.get("compiles")
                                         or not r.get("explicit"))]
    for pkg, r in problems:
        cause = (r.get("fix") if r.get("fix") != "written"
                 else r.get("compile_error") or r.get("explicit_error"))
        print(f"- {pkg}: {Path(r['file']).name}: {cause}")
    if args.bodies:
        with args.bodies.open("w") as fh:
            fh.write("package\tfile\tbody\tours_kg\twritten_kg\tmujoco_default_kg\t"
                     "mujoco_exact_kg\tours_moments\tmujoco_default_moments\t"
                     "mujoco_exact_moments\n")
            for pkg, rs in rows.items():
                for r in rs:
                    for b in r.get("bodies", []):
                        fh.write("\t".join(str(x) for x in (
                            pkg, r["file"], b["body"], b["ours"], b.get("written", ""),
                            b.get("legacy", ""), b.get("mj_exact", ""),
                            b["ours_moments"], b.get("legacy_moments", ""),
                            b.get("mj_exact_moments", ""))) + "\n")
    if args.json:
        args.json.write_text(json.dumps(rows, indent=1, default=str))
    return 0


if __name__ == "__main__":
    sys.exit(main())
