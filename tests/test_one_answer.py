"""One answer per link over real robots: ``fix``, ``check``, ``compare``, ``report``,
``explain`` and the Python API give every link the same verdict, reason and numbers, and
``check`` on ``fix``'s output finds nothing ``fix`` could have acted on.

The corpus: example-robot-data (a dev dependency), pybullet_data (ships with pybullet, a
dev dependency), and, when installed, dm_control's and gymnasium-robotics' MJCF models
(large wheels, not dev dependencies: their robots are skipped without them).
"""

from __future__ import annotations

import importlib.util
from pathlib import Path

import numpy as np
import pytest
from support.corpus import example_robot_data_dir

import urdfinertia
from urdfinertia.analysis.check import check_description
from urdfinertia.analysis.compare import compare_with_geometry
from urdfinertia.analysis.explain import explain_link
from urdfinertia.body.options import FixOptions
from urdfinertia.cache.library import MeshLibrary
from urdfinertia.descriptions.formats import read_description, robot_from_bytes
from urdfinertia.plan.fix import fix_robot
from urdfinertia.plan.results import Action, LinkResult, Status
from urdfinertia.render.report import collect

pytestmark = pytest.mark.corpus


def _package_dir(name: str) -> Path | None:
    spec = importlib.util.find_spec(name)  # finds the folder without importing it
    if spec is None or not spec.submodule_search_locations:
        return None
    return Path(next(iter(spec.submodule_search_locations)))


def _erd() -> Path | None:
    found = example_robot_data_dir()
    return None if found is None else found / "robots"


#: (package folder, path in it): robots chosen for the failure classes they hold.
ROBOTS = [
    (_erd, "panda_description/urdf/panda.urdf"),  # kept CoM of recomputed links
    (_erd, "ur_description/urdf/ur5_robot.urdf"),  # wrong wrist tensors: recomputed
    (_erd, "talos_data/robots/talos_reduced.urdf"),  # zero tensors on frames
    (_erd, "cassie_description/robots/cassie.sdf"),  # marker geometry: kept
    (_erd, "romeo_description/urdf/romeo_laas_small.urdf"),  # meshes not shipped
    (_erd, "solo_description/robots/solo12.urdf"),
    (lambda: _package_dir("pybullet_data"), "kuka_iiwa/model.urdf"),
    (lambda: _package_dir("pybullet_data"), "franka_panda/panda.urdf"),
    (lambda: _package_dir("pybullet_data"), "husky/husky.urdf"),
    (lambda: _package_dir("dm_control"), "suite/cheetah.xml"),
    (lambda: _package_dir("dm_control"), "suite/quadruped.xml"),
    (lambda: _package_dir("dm_control"), "suite/humanoid.xml"),
    (lambda: _package_dir("gymnasium_robotics"), "envs/assets/fetch/reach.xml"),
]

#: Finding codes ``fix`` never acts on: they are about the file or the robot, not about a
#: link's inertial (what the reader read past, masses lumped by fixed joints).
NOT_ACTED_ON = frozenset({"lumped-mass", "massless-frame", "mesh-unresolved",
                          "geometry-unreadable", "xml-read-leniently", "vector-unparseable",
                          "unsupported-geometry", "zero-size-primitive",
                          # across links: which of two links is right is the author's call
                          "inertial-copied", "twins-disagree",
                          # check's realizability and statics: fix's policy does not act on
                          # them (yet); a tensor fix derives is always realizable
                          "not-realizable", "gyration-implausible", "joint-cannot-hold",
                          "joint-effort-margin"})


#: What ``fix`` cannot change, so ``check --strict`` of its output may still fail on it:
#: a joint's effort limit against the masses it keeps, files the package does not ship.
NOT_FIXS = frozenset({"joint-cannot-hold", "joint-effort-margin", "mesh-unresolved",
                      "geometry-unreadable"})


def _path(base, rel: str) -> Path:
    folder = base()
    if folder is None or not (folder / rel).is_file():
        pytest.skip(f"{rel}: its package is not installed")
    return folder / rel


def answer(r: LinkResult) -> tuple:
    """What must agree between commands: the link's action, status and reason."""
    return (r.name, r.action, r.status, r.why)


@pytest.fixture(scope="module", params=ROBOTS, ids=[rel for _, rel in ROBOTS])
def robot(request):
    path = _path(*request.param)
    options = FixOptions()
    model, data = read_description(path)
    fixed = fix_robot(model, data, options, MeshLibrary())
    return path, model, data, fixed


def test_every_command_gives_the_same_answer(robot):
    path, model, _, fixed = robot
    expected = [answer(r) for r in fixed.links]
    # check (a fresh mesh library: computed again, not shared)
    checked = check_description(model, meshes=MeshLibrary())
    assert [answer(r) for r in checked.links] == expected
    assert checked.would_change == fixed.changed_links
    # the Python API
    assert [answer(r) for r in urdfinertia.check(path).links] == expected
    assert [answer(r) for r in urdfinertia.fix(path).links] == expected
    # compare: the same decision for every link it lists
    for c in compare_with_geometry(path, FixOptions()):
        assert c.fix is not None and answer(c.fix) == answer(fixed.link(c.link))
        assert c.decision == fixed.link(c.link).planned
        assert c.verdict != "differs" or fixed.link(c.link).changed


def test_report_and_explain_show_what_fix_writes(robot):
    path, _, _, fixed = robot
    data = collect(path, FixOptions(), face_budget=2000)
    assert [answer(row.fix) for row in data.rows] == [answer(r) for r in fixed.links]
    for row, r in zip(data.rows, fixed.links, strict=True):
        if r.changed:
            _same(row.recomputed, r.after)
        else:
            assert row.recomputed is None
    changed = [r for r in fixed.links if r.changed]
    if changed:  # explain the first link fix changes: its total is what fix writes
        model, _ = read_description(path)
        if changed[0].assembly is not None and changed[0].assembly.parts:
            b = explain_link(model, changed[0].name, FixOptions())
            _same(b.total, changed[0].after)
            assert b.decision == changed[0].decision


#: Robots whose inertials live in ``<include>``d files, which ``fix`` does not patch yet
#: (only the main document is written): its output still holds what it recomputed.


def test_check_on_fix_output_is_clean(robot, request):
    path, _, _, fixed = robot
    # the output read where the input lies, so its references resolve as the input's do
    out = robot_from_bytes(fixed.output, path)
    after = check_description(out, meshes=MeshLibrary())
    assert after.would_change == ()
    by_name = {r.name: r for r in after.links}
    for f in after.findings:
        if f.severity == "info" or f.code in NOT_ACTED_ON:
            continue
        assert f.severity != "error", f
        # a warning left is one fix states it leaves: a kept link with a stated reason
        r = by_name[f.link]
        assert r.action in (Action.KEEP, Action.LEAVE) and r.why != "plausible", (f, r.why)
        assert fixed.link(f.link).why == r.why or fixed.link(f.link).changed


def test_nothing_fix_writes_is_invalid(robot):
    _, _, _, fixed = robot
    for r in fixed.links:
        assert r.status != Status.LEFT or r.assembly is None
        if r.changed:
            assert r.after is not None and r.after.is_physical(), r.name


def _same(a, b) -> None:
    # the same objects' numbers: only round-off from being computed twice
    assert a is not None and b is not None
    assert a.mass == pytest.approx(b.mass, rel=1e-12)
    np.testing.assert_allclose(a.com, b.com, rtol=1e-12, atol=1e-15)
    np.testing.assert_allclose(a.inertia, b.inertia, rtol=1e-9,
                               atol=1e-12 * float(np.abs(b.inertia).max()))


def test_strict_check_of_fix_output_passes(robot):
    """``check --strict`` on what ``fix`` wrote exits 0: every warning left is on a value
    ``fix`` keeps on purpose, with its reason."""
    path, model, _, fixed = robot
    after = check_description(robot_from_bytes(fixed.output, path), meshes=MeshLibrary())
    failing = [f for f in after.failing(strict=True) if f.rule.value not in NOT_FIXS
               and not (f.link is not None and model.link(f.link).read_only)]
    assert failing == [], [f.describe() for f in failing]
    if not after.unverified and len(failing) == len(after.failing(strict=True)):
        assert after.exit_code(strict=True) == 0


#: Options a user may run ``fix`` with: each leaves no invalid tensor and converges.
VARIANTS = {"default": {}, "all": {"recompute": "all"},
            "collision": {"geometry": "collision"},
            "all-collision": {"recompute": "all", "geometry": "collision"},
            "visual": {"geometry": "visual"}, "no-slips": {"slips": False}}


@pytest.mark.parametrize("variant", list(VARIANTS), ids=list(VARIANTS))
def test_fix_converges_in_one_run_under_every_option(robot, variant):
    """A second ``fix`` of ``fix``'s output writes the same bytes and changes no link, and
    no option leaves an invalid tensor (the minimal repair is the fallback of each)."""
    path, model, data, _ = robot
    options = FixOptions(**VARIANTS[variant])
    first = fix_robot(model, data, options, MeshLibrary())
    for r in first.links:
        if model.link(r.name).read_only or r.status == Status.UNTOUCHED:
            # in a file fix does not write (an MJCF include), or left on purpose with its
            # reason (a frame on a fixed joint, a massless root): said so
            continue
        written = _written(first.output, path, r.name)
        assert written is None or written, (variant, r.name, r.decision)
    again = fix_robot(robot_from_bytes(first.output, path), first.output, options,
                      MeshLibrary())
    if options.recompute == "needed":
        assert again.changed_links == (), [again.link(n).decision for n in again.changed_links]
    assert again.output == first.output


def _written(output: bytes, path: Path, name: str) -> bool | None:
    """The link's inertial in ``output`` is a physical body (None: it has none)."""
    from urdfinertia.descriptions.inertial import RawInertial
    from urdfinertia.inertia.validity import diagnose_tensor

    link = robot_from_bytes(output, path).link(name)
    if link.inertial is None:
        return None
    raw = RawInertial.from_inertial(link.inertial)
    if raw.mass == 0:
        return None  # a massless frame, left as written (a moving one gets a body)
    return bool(raw.mass_ok and diagnose_tensor(raw.inertia).valid)


def test_links_option_recomputes_the_named_link_and_repairs_the_invalid(robot):
    """``--links NAME`` recomputes NAME and still gives every invalid link the minimal
    repair; its output converges too."""
    path, model, data, fixed = robot
    named = next((r.name for r in fixed.links if r.assembly is not None
                  and r.assembly.parts), None)
    if named is None:
        pytest.skip("no link with geometry to recompute")
    options = FixOptions(recompute="links", links=(named,))
    first = fix_robot(model, data, options, MeshLibrary())
    for r in first.links:
        if model.link(r.name).read_only or r.status == Status.UNTOUCHED:
            continue
        assert _written(first.output, path, r.name) is not False, (r.name, r.decision)
    again = fix_robot(robot_from_bytes(first.output, path), first.output, options,
                      MeshLibrary())
    assert again.output == first.output
