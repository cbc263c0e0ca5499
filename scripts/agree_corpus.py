"""Do the commands agree on real robots, run as a user runs them?

For a sample of description files of every robot package found
(``support.corpus.robot_packages``: installed and ``scripts/gather_corpus.py``'s), through
the command line with ``--json``:

1. ``fix IN -o OUT``: every file gets an output or a stated refusal (exit 0, 1 or a
   security/parse refusal of the input, never a crash);
2. ``check IN``: its plan gives every link the action, status and reason ``fix`` gave;
3. ``check OUT``: nothing would change any more, and no error is left on a link ``fix``
   changed.

Prints one row per package and every disagreement. Exit 1 when there is one.

Usage: ``nice .venv/bin/python scripts/agree_corpus.py [--per-package N] [--formats urdf,mjcf,sdf]``
"""

from __future__ import annotations

import argparse
import json
import random
import subprocess
import sys
import tempfile
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))
from support.corpus import robot_packages  # noqa: E402

EXE = [sys.executable, "-m", "urdfinertia"]
#: Outcomes a user may get for a broken input: a refusal with a message, never a traceback.
REFUSED = 2


def run(args: list[str]) -> tuple[int, str]:
    done = subprocess.run(EXE + args, capture_output=True, text=True, timeout=900,
                          check=False)
    return done.returncode, done.stderr


def plan(check_json: Path) -> dict[str, tuple]:
    """Each link's (action, status, reason) in check's plan; a file check could not read
    has none (its ``error`` says why)."""
    entry = json.loads(check_json.read_text())["files"][0]
    if entry.get("links") == 0:
        return {}  # nothing to plan (a model of world geoms only)
    if "fix_plan" not in entry:
        raise ValueError(entry.get("error") or f"no plan: {sorted(entry)}")
    return {p["link"]: (p["action"], p["status"], p["why"]) for p in entry["fix_plan"]}


def one(src: Path, tmp: Path) -> list[str]:
    """Disagreements for one file (empty: the commands agree)."""
    out = tmp / f"out{src.suffix}"
    fix_json, check_in, check_out = tmp / "fix.json", tmp / "in.json", tmp / "out.json"
    for p in (out, fix_json, check_in, check_out):
        p.unlink(missing_ok=True)
    code, err = run(["fix", str(src), "-o", str(out), "--json", str(fix_json)])
    if code == REFUSED:
        return [] if "Traceback" not in err else [f"fix crashed: {err.strip()[-300:]}"]
    if code not in (0, 1) or not fix_json.is_file():
        return [f"fix exit {code}: {err.strip()[-300:]}"]
    fixed = json.loads(fix_json.read_text())
    answers = {r["link"]: (r["action"], r["status"], r["why"]) for r in fixed["links"]}
    changed = {r["link"] for r in fixed["links"]
               if r["status"] in ("recomputed", "repaired")}
    # a link fix left as it was (stated, exit 1) may still be flagged in the output
    left = {r["link"] for r in fixed["links"] if r["status"] == "left"}
    problems = []
    code, err = run(["check", str(src), "--json", str(check_in)])
    if not check_in.is_file():
        return [f"check exit {code}: {err.strip()[-300:]}"]
    try:
        planned = plan(check_in)
    except ValueError as exc:
        return [f"check could not read what fix read: {exc}"]
    for link, ans in planned.items():
        if answers.get(link) != ans:
            problems.append(f"{link}: fix says {answers.get(link)}, check says {ans}")
    if not out.is_file():
        return problems  # nothing written (e.g. every link left): nothing to re-check
    code, err = run(["check", str(out), "--json", str(check_out)])
    if not check_out.is_file():
        return [*problems, f"check of the output exit {code}: {err.strip()[-300:]}"]
    after = json.loads(check_out.read_text())["files"][0]
    try:
        planned = plan(check_out)
    except ValueError as exc:
        return [*problems, f"check cannot read fix's output: {exc}"]
    for link, (action, _, why) in planned.items():
        if action not in ("keep", "leave") and link not in left:
            problems.append(f"{link}: check of the output would still {action} ({why})")
    for f in after["findings"]:
        if f["severity"] == "error" and f.get("link") in changed:
            problems.append(f"{f['link']}: error after fix: {f['code']}: {f['message']}")
    return problems


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--per-package", type=int, default=4)
    ap.add_argument("--formats", default="urdf,mjcf,sdf")
    ap.add_argument("--seed", type=int, default=5)
    args = ap.parse_args()
    rng = random.Random(args.seed)
    packages = robot_packages(tuple(args.formats.split(",")))
    total = bad = 0
    print(f"{'package':24} {'files':>5} {'agree':>5}")
    with tempfile.TemporaryDirectory() as tmp:
        for name, files in packages.items():
            chosen = sorted(rng.sample(files, min(args.per_package, len(files))))
            agree = 0
            notes = []
            for src in chosen:
                problems = one(src, Path(tmp))
                agree += not problems
                notes += [f"  {src.name}: {p}" for p in problems]
            total += len(chosen)
            bad += len(chosen) - agree
            print(f"{name:24} {len(chosen):>5} {agree:>5}", flush=True)
            for n in notes:
                print(n, flush=True)
    print(f"\n{total - bad} of {total} files: fix, check and check of the output agree")
    return 1 if bad else 0


if __name__ == "__main__":
    raise SystemExit(main())
