"""Every value the default ``fix`` changes on a corpus of robots, one line per link.

The corpus is a folder with a ``manifest.json`` listing description files (as
``scripts/gather_corpus.py`` or a hand-gathered corpus writes it: entries with ``file``,
``package``, ``format``, ``package_dirs`` and ``xacro_args``, paths relative to the
folder). For each file the default ``fix`` is run through the public API and each link it
changes is printed with its decision, the mass before and after and the change of the
robot's total mass; a summary counts changes by decision and package.

Used to judge the tool on robots nobody tuned it on: run it on a held-out corpus after a
change of the rules, and read every line.

Usage: ``python scripts/changed_links.py CORPUS [--json OUT] [--only PACKAGE ...]
[--seconds S]``
"""

from __future__ import annotations

import argparse
import json
import signal
import sys
import time
from collections import Counter
from pathlib import Path


class _Timeout(Exception):
    pass


def _alarm(signum, frame):  # noqa: ANN001, ANN202
    raise _Timeout


def run_file(root: Path, entry: dict, seconds: float) -> dict:
    import urdfinertia

    path = root / entry["file"]
    dirs = {k: str(root / v) for k, v in (entry.get("package_dirs") or {}).items()}
    args = dict(entry.get("xacro_args") or {})
    row: dict = {"file": entry["file"], "package": entry.get("package", "?"), "links": []}
    signal.signal(signal.SIGALRM, _alarm)
    signal.setitimer(signal.ITIMER_REAL, seconds)
    start = time.perf_counter()
    try:
        kwargs = {"package_dirs": dirs}
        if args:
            kwargs["xacro_args"] = args
        result = urdfinertia.fix(str(path), **kwargs)
    except _Timeout:
        row["error"] = f"over {seconds:g} s"
        return row
    except Exception as exc:  # noqa: BLE001 - a report, not a verdict
        row["error"] = f"{type(exc).__name__}: {exc}"
        return row
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
    row["seconds"] = round(time.perf_counter() - start, 2)
    before = after = 0.0
    for r in result.links:
        b, a = r.before, r.after
        mb = b.mass if b is not None else 0.0
        ma = a.mass if a is not None else mb
        before += mb
        after += ma if r.changed else mb
        if r.changed or str(r.status) == "left":
            row["links"].append({"link": r.name, "status": str(r.status),
                                 "decision": r.decision, "mass_before": mb,
                                 "mass_after": ma if r.changed else None})
    row["total_before"], row["total_after"] = before, after
    row["count"] = len(result.links)
    return row


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("corpus", type=Path)
    ap.add_argument("--json", type=Path)
    ap.add_argument("--only", nargs="*", default=None, help="packages to run")
    ap.add_argument("--seconds", type=float, default=300.0, help="per file")
    ap.add_argument("--include-doubtful", action="store_true")
    args = ap.parse_args(argv)
    entries = json.loads((args.corpus / "manifest.json").read_text())
    if isinstance(entries, dict):
        entries = entries.get("files", entries.get("entries", []))
    rows = []
    decisions: Counter[str] = Counter()
    for entry in entries:
        if args.only and entry.get("package") not in args.only:
            continue
        if entry.get("doubtful") and not args.include_doubtful:
            continue
        row = run_file(args.corpus, entry, args.seconds)
        rows.append(row)
        if "error" in row:
            print(f"{row['file']}: ERROR {row['error']}", flush=True)
            continue
        delta = row["total_after"] - row["total_before"]
        rel = f"{100 * delta / row['total_before']:+.2f} %" if row["total_before"] else "n/a"
        print(f"{row['file']}: {len(row['links'])} of {row['count']} links changed or left; "
              f"total mass {row['total_before']:.4g} -> {row['total_after']:.4g} kg ({rel}); "
              f"{row['seconds']} s", flush=True)
        for link in row["links"]:
            decisions[link["decision"].split(":")[0]] += 1
            mass = (f"{link['mass_before']:.4g} -> {link['mass_after']:.4g} kg"
                    if link["mass_after"] is not None else f"{link['mass_before']:.4g} kg")
            print(f"    {link['link']:32} {link['status']:10} {mass:24} {link['decision']}",
                  flush=True)
    changed = sum(len(r.get("links", ())) for r in rows)
    print(f"\n{len(rows)} files, {changed} links changed or left; by decision: "
          + ", ".join(f"{k} {n}" for k, n in decisions.most_common()))
    if args.json is not None:
        args.json.write_text(json.dumps(rows, indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main())
