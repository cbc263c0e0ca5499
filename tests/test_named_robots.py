"""What was seen on named robots of example-robot-data, kept as tests."""

from __future__ import annotations

import json

import numpy as np
import pytest
from support.corpus import example_robot_data_dir

import urdfinertia
from urdfinertia.body.options import FixOptions
from urdfinertia.cli import main
from urdfinertia.descriptions.formats import read_description
from urdfinertia.plan.results import Action, Status
from urdfinertia.render.report import collect

pytestmark = pytest.mark.corpus

ERD = example_robot_data_dir()
ROBOTS = ERD / "robots" if ERD is not None else None
needs_erd = pytest.mark.skipif(ERD is None, reason="example-robot-data is not installed")


@needs_erd
def test_panda_report_and_fix_recompute_the_same_links():
    path = ROBOTS / "panda_description/urdf/panda.urdf"
    fixed = urdfinertia.fix(path)
    assert fixed.recomputed == ("panda_link1", "panda_link2", "panda_link7")
    data = collect(path, FixOptions(), face_budget=2000)
    assert tuple(r.name for r in data.rows if r.fix.status == Status.RECOMPUTED) == \
        fixed.recomputed


@needs_erd
def test_panda_explain_shows_the_kept_com_fix_writes():
    path = ROBOTS / "panda_description/urdf/panda.urdf"
    model, _ = read_description(path)
    b = urdfinertia.explain(path, "panda_link1")
    # the written CoM, kept by fix (the geometry's centroid is about (-0.031, -0.069, ..))
    np.testing.assert_array_equal(b.total.com, [0.003875, 0.002081, -0.04762])
    assert b.decision == "recomputed: inertia-vs-geometry"
    assert not np.allclose(b.geometry_total.com, b.total.com, atol=1e-3)


@needs_erd
def test_cassie_reference_links_come_out_unchanged():
    path = ROBOTS / "cassie_description/robots/cassie.sdf"
    fixed = urdfinertia.fix(path)
    refs = [r for r in fixed.links if r.name.endswith("-reference")]
    assert len(refs) == 10
    for r in refs:
        assert r.action in (Action.KEEP, Action.REPAIR), r.name
        assert "geometry is a marker, not the body" in r.why
        assert r.after is not None and r.after.is_physical()
        if r.action == Action.KEEP:  # valid: as written, CoM not moved to the box
            np.testing.assert_array_equal(r.after.com, r.before.com)
        else:  # the foot references' invalid tensors: lifted, mass and CoM kept
            assert r.kept == ("mass", "com")
    assert {r.name for r in refs if r.action == Action.REPAIR} == {
        "left-foot-reference", "right-foot-reference"}


@needs_erd
def test_romeo_laas_small_invalid_links_without_meshes_are_repaired(tmp_path, capsys):
    path = ROBOTS / "romeo_description/urdf/romeo_laas_small.urdf"
    fixed = urdfinertia.fix(path)
    repaired = {r.name for r in fixed.links if r.status == Status.REPAIRED
                and "geometry could not be read" in r.why}
    assert repaired == {"LShoulderYaw_link", "LElbowYaw_link", "body", "LHipPitch_link",
                        "RHipPitch_link"}
    assert not fixed.left and all(fixed.link(n).after.is_physical() for n in repaired)
    out = tmp_path / "romeo.urdf"
    # fix and check could not read 20 links' meshes: both say so, even with -q, and exit 1
    capsys.readouterr()
    assert main(["fix", "-q", str(path), "-o", str(out)]) == 1
    assert "not verified: 20 meshes unresolved or unreadable in 20 links" \
        in capsys.readouterr().err
    assert main(["check", "-q", str(path)]) == 1
    assert "not verified: 20 meshes unresolved or unreadable in 20 links: pass " \
        "--package-dir NAME=PATH" in capsys.readouterr().out


@needs_erd
def test_ur5_library_check_gives_the_cli_findings(tmp_path, capsys):
    path = ROBOTS / "ur_description/urdf/ur5_robot.urdf"
    js = tmp_path / "ur5.json"
    assert main(["check", "-q", str(path), "--json", str(js)]) == 0
    cli = [(f["link"], f["code"], f["message"]) for f in
           json.loads(js.read_text())["files"][0]["findings"]]
    lib = [(f.link, f.code, f.message) for f in urdfinertia.check(path).findings]
    assert lib == cli
    codes = [f.code for f in urdfinertia.check(path).findings if f.severity == "warning"]
    # the three wrist links: CoM outside, tensor too large, and so not realizable inside
    assert sorted(set(codes)) == ["com-outside-geometry", "inertia-vs-geometry",
                                  "not-realizable"]
    assert len(codes) == 9


@needs_erd
@pytest.mark.parametrize("rel", ["panda_description/urdf/panda.urdf",
                                 "ur_description/urdf/ur5_robot.urdf",
                                 "talos_data/robots/talos_reduced.urdf"])
def test_check_engines_exits_0_on_stock_robots(rel, capsys):
    from urdfinertia.engines.run import installed

    if not all(installed(e) for e in ("mujoco", "pinocchio", "pybullet")):
        pytest.skip("an engine is not installed")
    # the engines' verdict alone: statics judges the declared efforts (TALOS's torso and
    # shoulders cannot hold every pose of their range), not what the engines do
    assert main(["check", "-q", "--no-statics", "--engines", "all", str(ROBOTS / rel)]) == 0
    assert "engine-runaway" not in capsys.readouterr().out
