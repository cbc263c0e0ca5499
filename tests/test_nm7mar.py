"""The shipped NM7MAR robot (robots/nm7mar.urdf + its spec): a sound URDF the demo fixes."""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from urdfinertia.body.options import FixOptions
from urdfinertia.body.spec import load_spec
from urdfinertia.cli import main
from urdfinertia.descriptions.urdf.read import read_urdf
from urdfinertia.plan.fix import fix_file

ROOT = Path(__file__).resolve().parents[1]
URDF, SPEC = ROOT / "robots" / "nm7mar.urdf", ROOT / "robots" / "nm7mar.inertia.toml"
#: Link lengths L_i of robots/README.md.
LENGTHS = {"link1": 0.44, "link2": 0.35, "link3": 0.24}


@pytest.fixture(scope="module")
def fixed():
    return fix_file(URDF, FixOptions(spec=load_spec(SPEC)))


def test_kinematic_chain():
    robot, _ = read_urdf(URDF)
    assert [link.name for link in robot.links] == ["base_link", "link1", "link2", "link3"]
    chain = [(j.parent, j.child, j.type) for j in robot.joints]
    assert chain == [("base_link", "link1", "revolute"), ("link1", "link2", "revolute"),
                     ("link2", "link3", "prismatic")]
    # the next joint sits at 0_l, L_i along -x from the link frame (paper eq. 6)
    joints = {j.child: j for j in robot.joints}
    assert joints["link2"].origin.xyz[0] == pytest.approx(-LENGTHS["link1"], abs=1e-15)
    assert joints["link3"].origin.xyz[0] == pytest.approx(-LENGTHS["link2"], abs=1e-15)


def test_collision_boxes_are_the_spec_elements(fixed):
    # Without the spec, the same boxes at the same density give the same link tensors.
    by_geometry = fix_file(URDF, FixOptions(mass="density", density=2000.0))
    spec_total = next(r for r in fixed.links if r.name == "link1").assembly.total
    geo_total = next(r for r in by_geometry.links if r.name == "link1").assembly.total
    assert geo_total.mass == pytest.approx(spec_total.mass, rel=1e-12)
    np.testing.assert_allclose(geo_total.com, spec_total.com, atol=1e-15)
    np.testing.assert_allclose(geo_total.inertia, spec_total.inertia, rtol=1e-12, atol=1e-15)


def test_placeholders_get_corrected(fixed):
    for r in fixed.links:
        if r.name in LENGTHS:
            assert r.geometry == "spec"
            assert r.previous.ixx == 1.0  # the shipped placeholder
            assert np.abs(r.assembly.total.inertia).max() < 0.6
    masses = {r.name: r.assembly.total.mass for r in fixed.links}
    assert masses["link1"] == pytest.approx(14.4, rel=1e-12)  # pinned in the spec
    assert masses["link2"] == pytest.approx(3 * 0.00144 * 1800, rel=1e-12)
    assert masses["link3"] == pytest.approx(3 * 0.00018 * 7850, rel=1e-12)  # steel


def test_fix_is_idempotent_and_physical(fixed, tmp_path):
    out = tmp_path / "nm7mar.fixed.urdf"
    out.write_bytes(fixed.output)
    again = fix_file(out, FixOptions(spec=load_spec(SPEC)))
    assert not again.changed
    for r in fixed.links:
        assert r.assembly.total.is_physical()
        assert not [f for f in r.findings if f.severity == "warning"
                    and f.rule.scope == "element"]


def test_mujoco_reads_the_fixed_robot(fixed, tmp_path):
    mujoco = pytest.importorskip("mujoco")
    out = tmp_path / "nm7mar.fixed.urdf"
    out.write_bytes(fixed.output)
    model = mujoco.MjModel.from_xml_path(str(out))
    for r in fixed.links:
        if r.name not in LENGTHS:
            continue  # the fixed base merges into MuJoCo's world body
        body = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, r.name)
        assert model.body_mass[body] == pytest.approx(r.assembly.total.mass, rel=1e-9)
        moments, _ = r.assembly.total.principal()
        # MuJoCo stores principal moments (its own eigen-decomposition, float64)
        np.testing.assert_allclose(np.sort(model.body_inertia[body]), moments, rtol=1e-7)


def test_demo_script_runs_the_spec_fix(tmp_path):
    """scripts/demo.sh in a copy of the checkout whose .venv is this test's environment:
    it writes the fixed robot, which check then passes, and prints the breakdowns."""
    demo = ROOT / "scripts" / "demo.sh"
    assert os.access(demo, os.X_OK)
    env_root = Path(sys.executable).parent.parent
    if not (env_root / "bin" / "urdf-inertia").exists():
        pytest.skip("the urdf-inertia command is not installed in this environment")
    (tmp_path / "scripts").mkdir()
    shutil.copy2(demo, tmp_path / "scripts" / "demo.sh")
    shutil.copytree(ROOT / "robots", tmp_path / "robots")
    (tmp_path / ".venv").symlink_to(env_root, target_is_directory=True)
    done = subprocess.run(["bash", str(tmp_path / "scripts" / "demo.sh")], capture_output=True,
                          text=True, timeout=600, env={**os.environ, "COLUMNS": "200"})
    assert done.returncode == 0, done.stderr
    assert "per-element contributions" in done.stdout and "link 'link1'" in done.stdout
    assert done.stdout.rstrip().endswith("wrote out/nm7mar.fixed.urdf")
    fixed = tmp_path / "out" / "nm7mar.fixed.urdf"
    assert main(["check", str(fixed), "--strict", "-q"]) == 0


def test_cli_fix_prints_element_contributions(tmp_path, capsys):
    out = tmp_path / "nm7mar.fixed.urdf"
    assert main(["fix", str(URDF), "--spec", str(SPEC), "-o", str(out)]) == 0
    text = capsys.readouterr().out
    assert "per-element contributions" in text
    assert "33.3" in text  # eq. 47: each element a third of its link's mass
    assert out.is_file()
