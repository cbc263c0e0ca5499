"""What a command did with a fuzz case: one class per run, the worst that applies.

Classes, worst first:

- ``hang``: still running at the timeout (killed);
- ``crash``: exit 3 ("internal error"), a traceback on stderr, an exception past the
  command line's shell, a signal, or an undocumented exit code;
- ``input-modified``: the mutant, or any file beside it, changed, appeared or vanished;
- ``half-written``: a temporary file left in the output folder, an output written by a
  run that failed (exit 2), no output from one that succeeded, an output that cannot be
  read back at all, or ``fix --strict`` writing with links left (exit 1);
- ``output-invalid``: an output whose inertial, on any link, is not finite, out of the
  readers' range, has a negative mass, is not positive definite or breaks the triangle
  inequality (:mod:`urdfinertia.inertia.validity`), where the run did not name that link
  as left (exit 1); also an output that ``fix`` itself cannot read again;
- ``no-location``: an error or warning line that does not start with its file (and, for a
  line about a link of an XML description, its line number);
- ``noise``: stderr lines that are not the tool's (a library's warning or traceback);
- ``clean-error``: exit 2 with a one-line error; ``ok``: everything else.
"""

from __future__ import annotations

import json
import math
import re
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from support.fuzz.runner import EXIT_ESCAPED, RunResult

CLASSES = ("hang", "crash", "input-modified", "half-written", "output-invalid",
           "no-location", "noise", "clean-error", "ok")
#: The classes that are defects (the suite asserts there are none).
DEFECTS = CLASSES[:7]


@dataclass(frozen=True)
class Outcome:
    """One run's class; ``known``: the :data:`KNOWN` tag of a defect whose cause is in
    code being rewritten (reproduced by a strict xfail), "" for any other."""

    command: str
    cls: str
    detail: str
    run: RunResult
    known: str = ""


# --- reading an output back (runs in a forked child) ---------------------------------

def inspect_output(path: Path) -> dict[str, Any]:
    """Read a written description back and test every link's inertial.

    The values come from the one reading (which keeps NaN and out-of-range values, as
    ``check`` sees them); ``strict_error`` is the first finding ``fix --strict`` refuses.
    """
    from urdfinertia.descriptions.formats import detect_format, read_bytes
    from urdfinertia.errors import UrdfInertiaError
    from urdfinertia.plan.results import strict_blocking

    try:
        data = read_bytes(path)
        fmt = detect_format(data, path)
        robot = fmt.read(data, path)
    except UrdfInertiaError as exc:
        return {"readable": False, "error": str(exc), "links": {}, "problems": []}
    # what ``fix --strict`` refuses in what fix wrote (an inertial element dropped, a
    # value of it not read); the rest of the document is the input's, kept as it was
    blocking = [f for f in robot.findings if strict_blocking(f)
                and f.element is not None and "inertial" in f.element]
    strict_error = blocking[0].describe(path) if blocking else None
    links = {}
    for link in robot.links:
        if link.inertial is not None:
            try:
                why = inertial_problems(link.inertial)
            except Exception as exc:  # the validity test itself failed on these values
                why = [f"cannot be tested: {type(exc).__name__}: {exc}"]
            if why:
                links[link.name] = why
    problems = [f.describe(path) for f in robot.findings
                if f.element is not None and "inertial" in f.element]
    return {"readable": True, "strict_error": strict_error, "links": links,
            "problems": problems}


def inertial_problems(inertial: Any) -> list[str]:
    """What makes a written inertial invalid (empty: valid), in the link frame."""
    import numpy as np

    from urdfinertia.descriptions.inertial import RawInertial
    from urdfinertia.descriptions.urdf.read import MAX_MAGNITUDE
    from urdfinertia.inertia.validity import diagnose_tensor

    with np.errstate(all="ignore"):
        raw = RawInertial.from_inertial(inertial)
    values = [raw.mass, *raw.com.tolist(), *raw.inertia.reshape(-1).tolist()]
    if not all(math.isfinite(v) for v in values):
        return ["not finite"]
    out = []
    if max(abs(v) for v in values) > MAX_MAGNITUDE:
        out.append(f"beyond {MAX_MAGNITUDE:g}")
    if raw.mass < 0:
        out.append("negative mass")
    d = diagnose_tensor(raw.inertia)
    if raw.mass > 0 or not d.zero:
        if not d.positive_definite:
            out.append(f"not positive definite {d.moments.tolist()}")
        if not d.triangle_ok:
            out.append(f"breaks the triangle inequality {d.moments.tolist()}")
    return out


# --- classifying ---------------------------------------------------------------------

_PREFIXES = ("urdf-inertia: error: ", "urdf-inertia: warning: ",
             "urdf-inertia: left as it was: ", "urdf-inertia: internal error: ")
#: FILE[:LINE]: at the start of a message
_LOCATION = re.compile(r"^(?P<file>[^\s:]*[/.][^\s:]*)(?::(?P<line>\d+))?: ")
#: stderr lines of the tool that are not error or warning lines
_OWN = re.compile(r"^(urdf-inertia: |total mass |warning: total mass |mass prior: |\s*$)")


def classify(command: str, run: RunResult, *, before: dict[str, str],
             after: dict[str, str], out_dir: Path, output: Path | None,
             inspected: dict[str, Any] | None, xml: bool) -> Outcome:
    """The class of one run (module doc); ``output`` is the description it was to write
    (None for ``check``), ``inspected`` what :func:`inspect_output` said of it."""

    def result(cls: str, detail: str = "", known: str = "") -> Outcome:
        return Outcome(command, cls, detail, run, known)

    err = run.stderr
    if run.timed_out:
        return result("hang", f"killed after {run.seconds:.0f} s")
    if run.code not in (0, 1, 2) or "Traceback (most recent call last)" in err \
            or "internal error" in err:
        why = {3: "internal error", EXIT_ESCAPED: "exception past cli.main", None:
               f"signal {run.signal}"}.get(run.code, f"exit {run.code}")
        return result("crash", f"{why}: {_first(err, 'internal error') or _last(err)}")
    if before != after:
        changed = sorted(set(before.items()) ^ set(after.items()))
        return result("input-modified", ", ".join(sorted({k for k, _ in changed}))[:300])
    if output is not None:
        half = _half_written(run, out_dir, output, inspected)
        if half:
            return result("half-written", half)
        invalid, tag = _invalid(run, out_dir, output, inspected)
        if invalid:
            return result("output-invalid", invalid, tag)
    located = _unlocated(err, xml)
    if located:
        return result("no-location", located)
    noise = [line for line in err.splitlines() if not _OWN.match(line)]
    if noise:
        return result("noise", " | ".join(noise[:3])[:300])
    if run.code == 2:
        return result("clean-error", _first(err, "urdf-inertia: error:"))
    return result("ok")


def _half_written(run: RunResult, out_dir: Path, output: Path,
                  inspected: dict[str, Any] | None) -> str:
    json_path = output.with_name(output.stem + ".json")
    expected = {output.name, json_path.name}
    stray = sorted(p.name for p in out_dir.iterdir()
                   if p.name not in expected
                   and not p.name.startswith(("fix.", "fix-all.", "fix-strict.")))
    stray += sorted(p.name for p in out_dir.iterdir()
                    if p.name.startswith(".") or p.name.endswith((".tmp", ".bak")))
    if stray:
        return f"left in the output folder: {', '.join(sorted(set(stray)))}"
    if run.code == 2 and output.exists():
        return "exit 2 but the output was written"
    if run.code == 1 and output.stem == "fix-strict":
        return "--strict wrote an output and left links (exit 1): all or nothing"
    if run.code in (0, 1) and not output.exists():
        return f"exit {run.code} but no output"
    if run.code in (0, 1) and not json_path.exists():
        return f"exit {run.code} but no --json"
    if run.code in (0, 1) and inspected is not None and not inspected.get("readable"):
        return f"output unreadable: {inspected.get('error')}"[:300]
    return ""


def _invalid(run: RunResult, out_dir: Path, output: Path,
             inspected: dict[str, Any] | None) -> tuple[str, str]:
    """Why the output is invalid ("" when it is not) and the :data:`KNOWN` tag of it."""
    if run.code not in (0, 1) or inspected is None:
        return "", ""
    left: set[str] = set()
    status: dict[str, str] = {}
    json_path = output.with_name(output.stem + ".json")
    try:
        doc = json.loads(json_path.read_text())
        left = {entry["link"] for entry in doc["links_left"]}
        status = {entry["link"]: entry["status"] for entry in doc["links"]}
    except (OSError, ValueError, KeyError, TypeError):
        pass
    bad = {name: why for name, why in inspected["links"].items()
           if run.code == 0 or name not in left}
    if bad:
        name = sorted(bad)[0]
        derived = [n for n in bad if status.get(n) == "recomputed"]
        if not derived:
            tag = "kept"
        elif len(derived) == len(bad) and all(_out_of_range(why) for why in bad.values()):
            tag = "derived-range"
        else:
            tag = ""
        return (f"{len(bad)} link(s) invalid, e.g. '{name}': {'; '.join(bad[name])}"[:300],
                tag if tag in KNOWN else "")
    if inspected.get("strict_error"):
        return f"fix cannot read its own output: {inspected['strict_error']}"[:300], ""
    if inspected.get("problems"):
        return (f"inertial read past in the output: {inspected['problems'][0]}"[:300],
                "kept" if "kept" in KNOWN else "")
    return "", ""


def _out_of_range(why: list[str]) -> bool:
    """Every reason is a magnitude past the readers' range, or moments that underflowed
    (a derived tensor scaled by a mass near the smallest one)."""
    def underflow(reason: str) -> bool:
        numbers = re.findall(r"-?[0-9.]+e[-+][0-9]+|-?[0-9.]+", reason.split("[", 1)[-1])
        return "[" in reason and all(abs(float(x)) < 1e-290 for x in numbers)

    return all(r.startswith("beyond") or underflow(r) for r in why)


#: Defects the fuzzer still finds that a strict xfail reproduces: the tag :func:`classify`
#: gives them -> the test. Empty: the invalid values kept with exit 0 ("kept") and derived
#: values past the readers' range ("derived-range") are fixed, and any run showing them
#: again is a defect of the slice.
KNOWN: dict[str, str] = {}


def _unlocated(err: str, xml: bool) -> str:
    for line in err.splitlines():
        prefix = next((p for p in _PREFIXES if line.startswith(p)), None)
        if prefix is None or prefix == "urdf-inertia: internal error: ":
            continue
        message = line[len(prefix):]
        found = _LOCATION.match(message)
        if found is None:
            return line[:300]
        if xml and found.group("line") is None and "link '" in message \
                and not found.group("file").endswith((".usda", ".usd", ".usdc")):
            return line[:300]
    return ""


def _first(text: str, marker: str) -> str:
    return next((line for line in text.splitlines() if marker in line), "")[:300]


def _last(text: str) -> str:
    lines = [line for line in text.splitlines() if line.strip()]
    return lines[-1][:300] if lines else ""
