"""Does this checkout's ``fix`` write what another revision wrote, file for file?

    python scripts/compare_outputs.py OLD_REF [ROBOTS_DIR] [--new REF] [--keep DIR]
                                      [-- FIX_OPTIONS...]

Checks out OLD_REF (a commit, branch or tag) into a temporary git worktree, runs
``urdf-inertia fix ROBOTS_DIR -o OUT`` with that revision's code and with this checkout's
(or revision ``--new REF``'s; each with a private, empty mesh cache), and compares the
written files byte for byte.
ROBOTS_DIR defaults to example-robot-data's ``robots`` folder. For every file that differs
it prints, per link, the relative change of mass, the CoM shift and the relative change of
the tensor (Frobenius). Exit code 0 when every output is byte-identical, 1 otherwise.
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tests"))
sys.path.insert(0, str(ROOT / "src"))


def run_fix(src: Path, robots: Path, out: Path, cache: Path, extra: list[str]) -> float:
    env = dict(os.environ, PYTHONPATH=str(src), URDFINERTIA_CACHE_DIR=str(cache))
    start = time.perf_counter()
    proc = subprocess.run([sys.executable, "-m", "urdfinertia.cli", "fix", str(robots),
                           "-o", str(out), "-q", *extra], env=env, capture_output=True,
                          text=True)
    if not out.is_dir():  # a file that fails is reported and the rest written (exit 1 or 2)
        sys.stderr.write(proc.stderr)
        raise SystemExit(f"fix failed with exit code {proc.returncode} ({src})")
    failed = [line for line in proc.stderr.splitlines() if ": error: " in line]
    print(f"{src}: exit {proc.returncode}, {len(failed)} file error(s)")
    for line in failed:
        print(f"    {line[:160]}")
    return time.perf_counter() - start


def link_changes(old: Path, new: Path) -> list[str]:
    from urdfinertia.descriptions.formats import read_description
    from urdfinertia.descriptions.inertial import RawInertial

    a, _ = read_description(old)
    b, _ = read_description(new)
    lines = []
    for link in a.links:
        other = b.link(link.name)
        if link.inertial == other.inertial:
            continue
        if link.inertial is None or other.inertial is None:
            what = "added" if link.inertial is None else "removed"
            lines.append(f"    {link.name}: inertial {what}")
            continue
        ra, rb = RawInertial.from_inertial(link.inertial), RawInertial.from_inertial(other.inertial)
        dm = abs(rb.mass - ra.mass) / abs(ra.mass) if ra.mass else float("inf")
        dc = float(np.linalg.norm(rb.com - ra.com))
        norm = float(np.linalg.norm(ra.inertia))
        di = float(np.linalg.norm(rb.inertia - ra.inertia)) / norm if norm else float("inf")
        lines.append(f"    {link.name}: mass {dm:.3g} rel, CoM {dc:.3g} m, tensor {di:.3g} rel")
    return lines


def main(argv: list[str] | None = None) -> int:
    argv = list(sys.argv[1:] if argv is None else argv)
    extra: list[str] = []
    if "--" in argv:
        cut = argv.index("--")
        argv, extra = argv[:cut], argv[cut + 1:]
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("old_ref")
    p.add_argument("robots", type=Path, nargs="?")
    p.add_argument("--new", metavar="REF", help="compare with revision REF, not this checkout")
    p.add_argument("--keep", type=Path, help="keep both output trees here")
    args = p.parse_args(argv)
    robots = args.robots
    if robots is None:
        from support.corpus import example_robot_data_dir

        found = example_robot_data_dir()
        if found is None:
            raise SystemExit("example-robot-data is not installed; name a ROBOTS_DIR")
        robots = found / "robots"
    with tempfile.TemporaryDirectory(prefix="urdfinertia-compare-") as tmp:
        base = args.keep or Path(tmp)
        trees = {"old": args.old_ref, "new": args.new}
        sources = {}
        for side, ref in trees.items():
            if ref is None:
                sources[side] = ROOT / "src"
                continue
            worktree = Path(tmp) / f"tree-{side}"
            subprocess.run(["git", "-C", str(ROOT), "worktree", "add", "--detach", "-q",
                            str(worktree), ref], check=True)
            sources[side] = worktree / "src"
        try:
            t_old = run_fix(sources["old"], robots, base / "old", Path(tmp) / "c1", extra)
            t_new = run_fix(sources["new"], robots, base / "new", Path(tmp) / "c2", extra)
        finally:
            for side in trees:
                if trees[side] is not None:
                    subprocess.run(["git", "-C", str(ROOT), "worktree", "remove", "--force",
                                    str(Path(tmp) / f"tree-{side}")], check=False)
        old_files = {p.relative_to(base / "old") for p in (base / "old").rglob("*")
                     if p.is_file()}
        new_files = {p.relative_to(base / "new") for p in (base / "new").rglob("*")
                     if p.is_file()}
        differing = []
        for rel in sorted(old_files | new_files):
            a, b = base / "old" / rel, base / "new" / rel
            if rel not in new_files or rel not in old_files:
                print(f"{rel}: written by {'the old' if rel in old_files else 'the new'} "
                      "revision only")
                differing.append(rel)
            elif a.read_bytes() != b.read_bytes():
                print(f"{rel}: differs")
                for line in link_changes(a, b):
                    print(line)
                differing.append(rel)
        print(f"{len(old_files | new_files)} outputs, {len(differing)} differ; "
              f"fix took {t_old:.1f} s ({args.old_ref}) and {t_new:.1f} s "
              f"({args.new or 'this checkout'})")
    return 1 if differing else 0


if __name__ == "__main__":
    sys.exit(main())
