"""A seeded slice of the fuzzer (:mod:`support.fuzz`; the long run is ``scripts/fuzz.py``).

Every format's real seeds are mutated (byte flips, truncation, elements and attributes
deleted or duplicated, NaN/inf/1e308/1e-320/-0, huge strings, unicode, negative masses,
empty and duplicate names, joint cycles, mesh paths to /etc/passwd, folders, FIFOs,
sparse files, symbolic-link loops, entity bombs; for meshes NaN and huge coordinates,
triangle soups, degenerate faces, absurd units ...) and ``check``, ``fix`` and
``fix --all`` run on each mutant in a forked child under a timeout. Every run must end in
a documented outcome (:mod:`support.fuzz.classify`): no crash, hang, modified input,
half-written or invalid output, message without its file, or library noise; the only
defects let through are those whose cause is in code being rewritten, each reproduced by a
strict xfail (:data:`support.fuzz.classify.KNOWN`, ``tests/test_fuzz_regressions.py``). The small
synthetic robot (``tests/data/fuzz``) also runs ``fix --strict``: all or nothing.

The first tests check the classifier itself on runs made to fail each way, so that a
clean slice means the defects were looked for; :data:`REPLAYS` runs again the cases of the
long run on which the code before its fixes crashed, hung or named no file.
"""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from support.fuzz.cases import make_case, make_cases
from support.fuzz.classify import CLASSES, classify, inspect_output
from support.fuzz.drive import run_case
from support.fuzz.runner import Runner, RunResult
from support.fuzz.seeds import DESCRIPTION_FORMATS, MESH_FORMATS
from support.fuzz.table import defect_lines

SEED = 20240611
#: Cases per format: about a minute of CPU in all (most runs take a fraction of a second
#: in the warm fork server; a mesh case computes its mesh cold).
PER_FORMAT = {"urdf": 4, "xacro": 3, "sdf": 3, "mjcf": 3, "usd": 3, "stl": 2,
              "stl-ascii": 2, "obj": 2, "dae": 3, "ply": 2, "glb": 2}
#: Cases of the synthetic robot, each also under fix --strict (the old in-process fuzz).
INLINE_CASES = 10
#: (generator seed, case) of the long run (``scripts/fuzz.py --seed S --cases 300``) where
#: the code before its fixes failed, one per cause: a USD layer whose message is not UTF-8,
#: an empty sublayer, a sublayer /dev/zero, a kept mass of 1e307 in check, moments of 1e308
#: ("Eigenvalues did not converge"), an MJCF include that is a link loop, random triangle
#: soups (hangs of minutes, gigabytes, out of memory), trimesh's traceback on a COLLADA
#: texture, an MJCF include name too long.
REPLAYS = [(1, 99), (1, 107), (1, 146), (1, 122), (1, 253), (1, 284), (1, 7), (2, 137),
           (2, 211), (2, 246), (2, 32)]
TIMEOUT = 40.0


@pytest.fixture(scope="module")
def runner(tmp_path_factory):
    cache = tmp_path_factory.mktemp("fuzz-cache")
    with Runner(timeout=TIMEOUT, memory_mb=4096,
                env={"URDFINERTIA_CACHE_DIR": str(cache)}) as server:
        yield server


# --- the classifier finds each defect ------------------------------------------------

def _run(code: int | None = 0, stderr: str = "", timed_out: bool = False,
         sig: int | None = None) -> RunResult:
    return RunResult(code, sig, timed_out, 0.1, 0.1, 50.0, "", stderr)


GOOD_URDF = """<robot name="r"><link name="a"><inertial><mass value="1"/>
<inertia ixx="0.1" ixy="0" ixz="0" iyy="0.1" iyz="0" izz="0.1"/></inertial></link></robot>"""


def _classify(tmp_path: Path, run: RunResult, *, urdf: str | None = GOOD_URDF,
              before=None, after=None, extra: str | None = None) -> str:
    out = tmp_path / "out"
    out.mkdir(parents=True, exist_ok=True)
    output = out / "fix.urdf"
    inspected = None
    if urdf is not None:
        output.write_text(urdf)
        (out / "fix.json").write_text(json.dumps({"links_left": []}))
        inspected = inspect_output(output)
    if extra:
        (out / extra).write_text("x")
    return classify("fix", run, before=before or {}, after=after or {}, out_dir=out,
                    output=output, inspected=inspected, xml=True).cls


def test_classifier_ok_and_clean_error(tmp_path):
    assert _classify(tmp_path / "a", _run(0)) == "ok"
    assert _classify(tmp_path / "b", _run(2, "urdf-inertia: error: r.urdf:3: bad"),
                     urdf=None) == "clean-error"


@pytest.mark.parametrize(("run", "expected"), [
    (_run(3, "urdf-inertia: internal error: ValueError: x (this is a bug; ...)"), "crash"),
    (_run(0, "Traceback (most recent call last):\n  File ..."), "crash"),
    (_run(None, sig=11), "crash"),
    (_run(70), "crash"),
    (_run(None, timed_out=True, sig=14), "hang"),
    (_run(0, "urdf-inertia: warning: link 'a' has no mass"), "no-location"),
    (_run(0, "urdf-inertia: warning: r.urdf: link 'a': no line"), "no-location"),
    (_run(0, "WARNING:trimesh:unable to load emissive texture"), "noise"),
])
def test_classifier_finds_defects(tmp_path, run, expected):
    assert _classify(tmp_path, run) == expected


@pytest.mark.parametrize("inertia", [
    'ixx="nan" ixy="0" ixz="0" iyy="1" iyz="0" izz="1"',
    'ixx="1" ixy="0" ixz="0" iyy="1" iyz="0" izz="3"',  # A + B < C
    'ixx="1" ixy="2" ixz="0" iyy="1" iyz="0" izz="1"',  # not positive definite
    'ixx="1e12" ixy="0" ixz="0" iyy="1e12" iyz="0" izz="1e12"',  # beyond the readers
    'ixx="0" ixy="0" ixz="0" iyy="0" iyz="0" izz="0"',  # a point mass
])
def test_classifier_reads_outputs_back(tmp_path, inertia):
    urdf = GOOD_URDF.replace('ixx="0.1" ixy="0" ixz="0" iyy="0.1" iyz="0" izz="0.1"', inertia)
    assert _classify(tmp_path, _run(0), urdf=urdf) == "output-invalid"


def test_classifier_finds_written_failures(tmp_path):
    assert _classify(tmp_path / "a", _run(0), extra=".fix.urdf.x1y2.tmp") == "half-written"
    assert _classify(tmp_path / "b", _run(2, "urdf-inertia: error: r.urdf: x")) \
        == "half-written"  # exit 2, yet the output is there
    assert _classify(tmp_path / "c", _run(0), urdf="<robot name='r'><link") == "half-written"
    assert _classify(tmp_path / "d", _run(0), before={"r.urdf": "1"},
                     after={"r.urdf": "2"}) == "input-modified"


def test_cases_are_reproducible():
    """A case is drawn from the seed and its index alone."""
    again = make_case(SEED, 7)
    assert make_cases(SEED, 8)[7] == again
    assert make_case(SEED + 1, 7) != again


# --- the slice ---------------------------------------------------------------------

@pytest.mark.corpus
@pytest.mark.parametrize("fmt", [*DESCRIPTION_FORMATS, *MESH_FORMATS])
def test_fuzz_slice(fmt, runner, tmp_path):
    try:
        cases = make_cases(SEED, PER_FORMAT[fmt], formats=(fmt,))
    except ValueError:
        pytest.skip(f"no {fmt} seed installed")
    results = [run_case(runner, case, tmp_path) for case in cases]
    defects = defect_lines(results, known=False)
    assert not defects, "\n".join(defects)
    seen = {o.cls for r in results for o in r.outcomes}
    assert seen <= set(CLASSES)


@pytest.mark.corpus
@pytest.mark.parametrize(("seed", "index"), REPLAYS)
def test_fuzz_cases_the_long_run_found(seed, index, runner, tmp_path):
    case = make_case(seed, index)
    result = run_case(runner, case, tmp_path)
    defects = defect_lines([result], known=False)
    assert not defects, "\n".join(defects)


def test_fuzz_inline_robot_with_strict(runner, tmp_path):
    """The synthetic robot (every primitive and a mesh): also all or nothing under
    --strict, and both a written output and a refusal occur (the slice tests both)."""
    from support.fuzz.cases import COMMANDS
    from support.fuzz.seeds import description_seeds

    inline = [s for s in description_seeds() if s.name == "inline/base"]
    assert inline, "tests/data/fuzz is missing"
    results = []
    index = 0
    while len(results) < INLINE_CASES:
        case = make_case(SEED, index, formats=("urdf",))
        index += 1
        if case.seed == "inline/base":
            results.append(run_case(runner, case, tmp_path,
                                    only=(*COMMANDS, "fix-strict")))
    defects = defect_lines(results, known=False)
    assert not defects, "\n".join(defects)
    strict = [o.cls for r in results for o in r.outcomes if o.command == "fix-strict"]
    assert "ok" in strict and "clean-error" in strict, strict
