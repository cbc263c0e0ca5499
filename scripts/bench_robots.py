"""Real robots as they come: how many get an output, and do the outputs still load?

For each robot package (default: every package ``support.corpus.robot_packages`` finds,
installed or unpacked by ``scripts/gather_corpus.py``; ``--corpus DIR``: one folder per
package, ``manifest.json`` there used when present), runs ``fix`` on every URDF
(or ``--max-per-package`` of them, chosen by a fixed seed), writes each output next to its
input (``NAME.bench-out.urdf``, deleted afterwards: ``package://`` references resolve from
there as from the input; ``--elsewhere`` writes into a temporary folder instead, so relative
references are rewritten) and prints per package: URDFs,
outputs written, links left as they were (by cause), refusals (by cause), and, with an
engine interpreter (``--engine-python``, default this Python, which has pinocchio, mujoco
and pybullet from the dev extra), how many inputs and outputs Pinocchio, MuJoCo and
PyBullet load, and how many outputs fail to load where their input loaded (target: 0).

    nice python scripts/bench_robots.py [--corpus DIR] [--max-per-package N] [--json PATH]
"""

from __future__ import annotations

import argparse
import json
import random
import subprocess
import sys
import tempfile
from collections import Counter
from pathlib import Path

from urdfinertia.body.options import FixOptions
from urdfinertia.cache.library import MeshLibrary
from urdfinertia.descriptions.formats import relocate_references
from urdfinertia.errors import UrdfInertiaError
from urdfinertia.plan.fix import fix_file

ENGINES = ("pinocchio", "mujoco", "pybullet")
#: Loads each path given on stdin (JSON list) in each engine; prints {path: {engine: ok}}.
ENGINE_PROBE = r"""
import json, os, sys
paths = json.load(sys.stdin)
out = {}
def pin(p):
    import pinocchio
    pinocchio.buildModelFromUrdf(p)
def mj(p):
    import mujoco
    mujoco.MjModel.from_xml_path(p)
def pb(p):
    import pybullet
    c = pybullet.connect(pybullet.DIRECT)
    try:
        if pybullet.loadURDF(p, physicsClientId=c) < 0:
            raise RuntimeError("loadURDF failed")
    finally:
        pybullet.disconnect(c)
devnull = os.open(os.devnull, os.O_WRONLY)
saved = os.dup(1), os.dup(2)
for p in paths:
    r = {}
    for name, f in (("pinocchio", pin), ("mujoco", mj), ("pybullet", pb)):
        os.dup2(devnull, 1); os.dup2(devnull, 2)
        try:
            f(p); r[name] = True
        except BaseException:
            r[name] = False
        finally:
            os.dup2(saved[0], 1); os.dup2(saved[1], 2)
    out[p] = r
sys.stdout.write(json.dumps(out))
"""


def refusal_cause(message: str) -> str:
    for words, cause in (("malformed XML", "not XML / truncated"),
                         ("root element", "not a <robot>"),
                         ("duplicate link", "duplicate link name"),
                         ("not allowed", "security refusal"),
                         ("not supported", "encoding"),
                         ("cannot read", "unreadable file")):
        if words in message:
            return cause
    return message.split(": ")[-1][:40]


def urdfs_by_package(corpus: Path | None, limit: int | None,
                     seed: int) -> dict[str, list[Path]]:
    found: dict[str, list[Path]] = {}
    if corpus is None:
        sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))
        from support.corpus import robot_packages

        found = robot_packages(("urdf",))
    elif (corpus / "manifest.json").is_file():
        manifest = corpus / "manifest.json"
        entries = json.loads(manifest.read_text())
        entries = entries.get("urdfs", entries) if isinstance(entries, dict) else entries
        for e in entries:
            path = Path(e["path"] if isinstance(e, dict) else e)
            path = path if path.is_absolute() else corpus / path
            found.setdefault(path.relative_to(corpus).parts[0], []).append(path)
    else:
        for folder in sorted(p for p in corpus.iterdir() if p.is_dir()
                             and not p.name.startswith("_")):
            files = sorted(folder.rglob("*.urdf"))
            if files:
                found[folder.name] = files
    rng = random.Random(seed)
    return {k: sorted(rng.sample(v, limit)) if limit and len(v) > limit else v
            for k, v in sorted(found.items())}


def probe(engine_python: Path | None, paths: list[str], timeout: float) -> dict:
    if engine_python is None or not paths:
        return {}
    try:
        done = subprocess.run([str(engine_python), "-c", ENGINE_PROBE],
                              input=json.dumps(paths), capture_output=True, text=True,
                              timeout=timeout, check=False)
        return json.loads(done.stdout or "{}")
    except (subprocess.TimeoutExpired, json.JSONDecodeError):
        return {}


def run_package(name: str, files: list[Path], out_dir: Path | None,
                engine_python: Path | None, timeout: float) -> dict:
    meshes = MeshLibrary({})
    row: dict = {"package": name, "urdfs": len(files), "written": 0, "partial": 0,
                 "left": Counter(), "refused": Counter(), "dropped": Counter(), "pairs": []}
    for i, path in enumerate(files):
        try:
            result = fix_file(path, FixOptions(), meshes)
        except UrdfInertiaError as exc:
            row["refused"][refusal_cause(exc.cause)] += 1
            continue
        except Exception as exc:  # noqa: BLE001 - a bug: counted, the run goes on
            row["refused"][f"internal {type(exc).__name__}"] += 1
            continue
        if out_dir is None:
            out = path.with_name(path.stem + ".bench-out.urdf")
        else:
            out = out_dir / name / f"{i}" / path.name
            out.parent.mkdir(parents=True, exist_ok=True)
        document, _ = relocate_references(result.output, path, out)
        out.write_bytes(document)
        row["written"] += 1
        row["partial"] += bool(result.left)
        for r in result.left:
            codes = {p.code for p in r.problems if p.kind == "dropped"} or {"other"}
            row["left"].update(codes)
        row["dropped"].update(p.code for p in result.problems if p.kind == "dropped")
        row["pairs"].append((str(path), str(out)))
    loads = probe(engine_python, [p for pair in row["pairs"] for p in pair]
                  + [str(f) for f in files if str(f) not in {a for a, _ in row["pairs"]}],
                  timeout)
    row["loads"] = {e: {"input": sum(bool(loads.get(str(f), {}).get(e)) for f in files),
                        "output": sum(bool(loads.get(o, {}).get(e)) for _, o in row["pairs"]),
                        "lost": sum(bool(loads.get(i, {}).get(e))
                                    and not loads.get(o, {}).get(e)
                                    for i, o in row["pairs"])}
                    for e in ENGINES} if loads else {}
    if out_dir is None:
        for _, o in row["pairs"]:
            Path(o).unlink(missing_ok=True)
    refused_paths = {str(f) for f in files} - {i for i, _ in row["pairs"]}
    row["pinocchio_refused"] = sum(bool(loads.get(p, {}).get("pinocchio"))
                                   for p in refused_paths)
    return row


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--corpus", type=Path, help="one folder per package (default: found)")
    ap.add_argument("--engine-python", type=Path, default=Path(sys.executable))
    ap.add_argument("--no-engines", action="store_true")
    ap.add_argument("--max-per-package", type=int, default=40)
    ap.add_argument("--seed", type=int, default=13)
    ap.add_argument("--timeout", type=float, default=900.0,
                    help="seconds for the engine probe of one package")
    ap.add_argument("--elsewhere", action="store_true",
                    help="write outputs into a temporary folder (mesh references rewritten)")
    ap.add_argument("--json", type=Path)
    args = ap.parse_args(argv)
    engine = None if args.no_engines or not args.engine_python.exists() else args.engine_python
    packages = urdfs_by_package(args.corpus, args.max_per_package, args.seed)
    rows = []
    head = (f"{'package':28} {'URDFs':>5} {'written':>7} {'w/left':>6} "
            + " ".join(f"{e[:5]} in/out/lost" for e in ENGINES if engine)
            + "  links left by cause | refusals by cause")
    print(head)
    with tempfile.TemporaryDirectory() as tmp:
        for name, files in packages.items():
            row = run_package(name, files, Path(tmp) if args.elsewhere else None, engine,
                              args.timeout)
            rows.append(row)
            loads = row["loads"]
            eng = " ".join(f"{loads[e]['input']:>5}/{loads[e]['output']}/{loads[e]['lost']:<5}"
                           if loads else f"{'-':>13}" for e in ENGINES) if engine else ""
            left = ", ".join(f"{k} {v}" for k, v in row["left"].most_common()) or "-"
            refused = ", ".join(f"{k} {v}" for k, v in row["refused"].most_common()) or "-"
            print(f"{name:28} {row['urdfs']:>5} {row['written']:>7} {row['partial']:>6} "
                  f"{eng}  {left} | {refused}", flush=True)
    total = {k: sum(r[k] for r in rows) for k in ("urdfs", "written", "partial",
                                                  "pinocchio_refused")}
    lost = {e: sum(r["loads"][e]["lost"] for r in rows if r["loads"]) for e in ENGINES}
    print(f"\ntotal: {total['urdfs']} URDFs, {total['written']} outputs written "
          f"({total['partial']} with links left as they were), "
          f"{total['urdfs'] - total['written']} refused "
          f"({total['pinocchio_refused']} of them load in Pinocchio); outputs that fail to "
          f"load where their input loaded: " + ", ".join(f"{e} {n}" for e, n in lost.items()))
    if args.json is not None:
        for r in rows:
            r.pop("pairs")
        args.json.write_text(json.dumps(rows, indent=1, default=dict))
    return 0


if __name__ == "__main__":
    sys.exit(main())
