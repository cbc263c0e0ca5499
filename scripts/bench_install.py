"""What installing urdfinertia costs: size, distributions, import and check time.

    python scripts/bench_install.py [--extras report,fast] [--against REF] [--runs 5]

Installs this checkout into a fresh virtual environment (``pip install .``, the core),
and again with the extras named (``pip install '.[report,fast]'``), and with
``--against REF`` that revision's ``pip install .`` as well (from ``git archive``), each
in a new temporary folder. For each it prints the installed size of site-packages (the
files' apparent sizes; pip and setuptools, there before the install, left out), the
number of distributions installed besides pip and setuptools, the import time of
``urdfinertia.cli`` (``python -X importtime``, cumulative, median of ``--runs``) and the
wall time of ``urdf-inertia check robots/nm7mar.urdf`` from another folder (median of
``--runs``, after one untimed run) with its CPU seconds (user + system, less disturbed
by other jobs on a shared machine). All in the same run, one after the other.
"""

from __future__ import annotations

import argparse
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
#: Distributions a fresh virtual environment has before anything is installed.
SEEDED = ("pip", "setuptools")


def install(folder: Path, source: Path, extras: str = "") -> Path:
    """A fresh virtual environment in ``folder`` with ``source`` (and ``extras``)."""
    subprocess.run([sys.executable, "-m", "venv", str(folder)], check=True)
    python = folder / "bin" / "python"
    target = f"{source}[{extras}]" if extras else str(source)
    done = subprocess.run([str(python), "-m", "pip", "install", "--quiet", target],
                          env={**os.environ, "PIP_DISABLE_PIP_VERSION_CHECK": "1"},
                          capture_output=True, text=True)
    if done.returncode != 0:
        raise SystemExit(f"pip install {target} failed:\n{done.stderr[-3000:]}")
    return python


def site_packages(python: Path) -> Path:
    out = subprocess.run([str(python), "-c", "import sysconfig; "
                          "print(sysconfig.get_paths()['purelib'])"],
                         check=True, capture_output=True, text=True)
    return Path(out.stdout.strip())


def distributions(python: Path) -> list[tuple[str, list[str]]]:
    """(name, files) of every distribution installed besides pip and setuptools."""
    code = ("import importlib.metadata as m, json; print(json.dumps([(d.metadata['Name'], "
            "[str(f) for f in (d.files or [])]) for d in m.distributions()]))")
    import json

    out = subprocess.run([str(python), "-c", code], check=True, capture_output=True,
                         text=True)
    return [(n, f) for n, f in json.loads(out.stdout) if n.lower() not in SEEDED]


def installed_bytes(python: Path) -> int:
    """Apparent size of site-packages less the seeded distributions' files."""
    root = site_packages(python)
    code = ("import importlib.metadata as m, json; print(json.dumps([str(f) for d in "
            f"m.distributions() if d.metadata['Name'].lower() in {SEEDED!r} "
            "for f in (d.files or [])]))")
    import json

    out = subprocess.run([str(python), "-c", code], check=True, capture_output=True,
                         text=True)
    seeded = {os.path.normpath(root / f) for f in json.loads(out.stdout)}
    total = 0
    for folder, _, files in os.walk(root):
        for name in files:
            path = os.path.join(folder, name)
            if os.path.normpath(path) not in seeded and not os.path.islink(path):
                total += os.path.getsize(path)
    return total


def import_ms(python: Path, runs: int) -> float:
    """Median cumulative import time of urdfinertia.cli (ms)."""
    times = []
    for _ in range(runs):
        out = subprocess.run([str(python), "-X", "importtime", "-c", "import urdfinertia.cli"],
                             check=True, capture_output=True, text=True)
        line = [x for x in out.stderr.splitlines() if x.rstrip().endswith("urdfinertia.cli")]
        times.append(int(line[-1].split("|")[1]) / 1000)
    return statistics.median(times)


def check_seconds(python: Path, urdf: Path, runs: int) -> tuple[float, float]:
    """Median wall and CPU seconds of ``urdf-inertia check URDF`` from an empty folder."""
    command = [str(python.parent / "urdf-inertia"), "check", str(urdf)]
    with tempfile.TemporaryDirectory() as cwd:
        env = {**os.environ, "URDFINERTIA_CACHE_DIR": os.path.join(cwd, "cache")}
        subprocess.run(command, cwd=cwd, env=env, capture_output=True)  # untimed
        wall, cpu = [], []
        for _ in range(runs):
            before = os.times()
            start = time.perf_counter()
            done = subprocess.run(command, cwd=cwd, env=env, capture_output=True)
            wall.append(time.perf_counter() - start)
            after = os.times()
            cpu.append(after.children_user - before.children_user
                       + after.children_system - before.children_system)
            if done.returncode not in (0, 1):
                raise SystemExit(done.stderr.decode()[-2000:])
    return statistics.median(wall), statistics.median(cpu)


def measure(label: str, python: Path, urdf: Path, runs: int) -> dict:
    dists = distributions(python)
    wall, cpu = check_seconds(python, urdf, runs)
    row = {"label": label, "mb": installed_bytes(python) / 1e6, "dists": len(dists),
           "import_ms": import_ms(python, runs), "check_s": wall, "check_cpu": cpu,
           "names": sorted(n for n, _ in dists)}
    print(f"{label:34s} {row['mb']:8.1f} MB {row['dists']:4d} distributions "
          f"{row['import_ms']:7.1f} ms import {wall:6.2f} s check ({cpu:.2f} s CPU)",
          flush=True)
    return row


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--extras", default="report,fast",
                    help="extras of the second install (default report,fast)")
    ap.add_argument("--against", metavar="REF", help="also install revision REF")
    ap.add_argument("--runs", type=int, default=5)
    args = ap.parse_args(argv)
    urdf = ROOT / "robots" / "nm7mar.urdf"
    rows = []
    with tempfile.TemporaryDirectory(prefix="urdfinertia-install-") as tmp:
        base = Path(tmp)
        print(f"{'install':34s} {'site-packages':>11s} {'':16s} "
              f"{'urdfinertia.cli':>15s} {'check nm7mar':>14s}")
        if args.against:
            src = base / "against"
            archive = subprocess.run(["git", "-C", str(ROOT), "archive", args.against],
                                     check=True, capture_output=True).stdout
            src.mkdir()
            subprocess.run(["tar", "-x", "-C", str(src)], input=archive, check=True)
            rows.append(measure(f"{args.against}: pip install .",
                                install(base / "venv-against", src), urdf, args.runs))
        # a copy of the checkout as it is (pip builds in the source folder: not here)
        src = base / "checkout"
        shutil.copytree(ROOT, src, ignore=shutil.ignore_patterns(
            ".git", ".venv", "site", "build", "*.egg-info", "__pycache__"))
        rows.append(measure("pip install .", install(base / "venv-core", src), urdf,
                            args.runs))
        if args.extras:
            rows.append(measure(f"pip install '.[{args.extras}]'",
                                install(base / "venv-extras", src, args.extras), urdf,
                                args.runs))
    core = rows[-2] if args.extras else rows[-1]
    for row in rows:
        extra = sorted(set(row["names"]) - set(core["names"]))
        fewer = sorted(set(core["names"]) - set(row["names"]))
        if extra or fewer:
            print(f"{row['label']}: {'+' + ' +'.join(extra) if extra else ''}"
                  f"{' -' + ' -'.join(fewer) if fewer else ''} against the core")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
