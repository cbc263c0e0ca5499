"""check's realizability (UI210) and gyration (UI211) rules on a hand-made fixture and a real
robot: the findings, their severity, and that JSON and SARIF carry them."""

import json
import sys
from pathlib import Path

import numpy as np
import pytest

import urdfinertia
from urdfinertia.body.bounds import BoundsCache
from urdfinertia.cache.library import mesh_library
from urdfinertia.cli import main
from urdfinertia.descriptions.formats import read_description
from urdfinertia.descriptions.model import Capsule, Cone, Cylinder, Ellipsoid, Sphere
from urdfinertia.inertia.realizable import bounding_ellipsoid
from urdfinertia.judge.realizability import (
    link_realizability,
    primitive_points,
    realizability_findings,
)

FIXTURE = Path(__file__).resolve().parents[1] / "data" / "realizable" / "housing.urdf"


def by_link(result):
    out = {}
    for f in result.findings:
        out.setdefault(f.link, []).append(f)
    return out


def test_fixture_findings():
    found = by_link(urdfinertia.check(FIXTURE))
    housing = [f for f in found["housing"] if f.code == "not-realizable"]
    assert housing and housing[0].severity == "warning" and housing[0].rule.id == "UI210"
    assert "outside the part by several of its sizes" in housing[0].message
    # the motor passes every other rule and fails this one, by a warning
    motor = found["motor"]
    assert [f.code for f in motor] == ["not-realizable"]
    assert motor[0].severity == "warning"
    assert "solid" not in found
    assert [f.code for f in found["base"]] == ["lumped-mass"]  # the fixed motor: info
    assert [f.code for f in found["tool_frame"]] == ["gyration-implausible"]


def test_scale_of_the_motor_in_closed_form():
    """CoM 0.045 m off-centre in a 10 cm cube whose ellipsoid has semi-axes sqrt(3) 0.05:
    mean r^2 = tr(Sigma) / (m a^2) + |c|^2 / a^2 with tr(Sigma) = tr(I) / 2."""
    robot, _ = read_description(FIXTURE)
    cache = BoundsCache(mesh_library(use_cache=False))
    found = link_realizability(robot.link("motor"), cache, FIXTURE.parent)
    a2 = 3 * 0.05 ** 2
    expected = np.sqrt(0.039 / 2 / (2 * a2) + 0.045 ** 2 / a2)
    assert found.scale == pytest.approx(expected, rel=2e-2)  # the ellipsoid's tolerance
    assert not found.realizable


@pytest.mark.parametrize("shape", [Cylinder(0.05, 0.3), Cone(0.05, 0.3), Sphere(0.1),
                                   Capsule(0.05, 0.2), Ellipsoid((0.1, 0.05, 0.2))])
def test_primitive_points_hold_the_primitive(shape):
    """The hull of the points holds the shape: its bounding ellipsoid holds points sampled on
    the shape's surface (radius 1 % inside at most, for the circumscribed polygons)."""
    pts = primitive_points(shape)
    region = bounding_ellipsoid(pts)
    rng = np.random.default_rng(3)
    u = rng.normal(size=(2000, 3))
    u /= np.linalg.norm(u, axis=1, keepdims=True)
    if isinstance(shape, Sphere):
        surface = u * shape.radius
    elif isinstance(shape, Ellipsoid):
        surface = u * shape.radii
    elif isinstance(shape, Capsule):
        surface = u * shape.radius + np.where(u[:, 2:] > 0, 1, -1) * [0, 0, shape.length / 2]
    else:  # the rims of cylinder and cone
        a = rng.uniform(0, 2 * np.pi, 2000)
        surface = np.column_stack([shape.radius * np.cos(a), shape.radius * np.sin(a),
                                   np.full(2000, -shape.length / 2)])
    assert region.radii_squared(surface).max() <= 1.0 + 1e-9


def test_json_and_sarif_carry_the_rule(tmp_path, capsys):
    assert main(["check", str(FIXTURE), "--format", "json", "--strict"]) == 1
    data = json.loads(capsys.readouterr().out)
    codes = {f["code"] for file in data["files"] for f in file["findings"]}
    assert {"not-realizable", "gyration-implausible"} <= codes
    sarif = tmp_path / "out.sarif"
    main(["check", str(FIXTURE), "--sarif", str(sarif)])
    capsys.readouterr()
    run = json.loads(sarif.read_text())["runs"][0]
    rule_ids = {r["ruleId"] for r in run["results"]}
    assert {"UI210", "UI211"} <= rule_ids


def test_no_geometry_no_finding():
    robot, _ = read_description(FIXTURE)
    cache = BoundsCache(mesh_library(use_cache=False))
    assert realizability_findings(robot.link("solid"), cache, FIXTURE.parent) == []


def _real_robot(name: str) -> Path | None:
    sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
    from support.corpus import example_robot_data_dir

    root = example_robot_data_dir()
    if root is None:
        return None
    found = sorted((root / "robots").rglob(name))
    return found[0] if found else None


@pytest.mark.parametrize("name", ["go2.urdf", "so101.urdf"])
def test_real_robots_with_cad_inertials_pass(name):
    """Unitree Go2's and the SO-101's CAD inertials are realizable in their meshes."""
    path = _real_robot(name)
    if path is None:
        pytest.skip("example-robot-data not installed")
    result = urdfinertia.check(path)
    assert not [f for f in result.findings if f.code == "not-realizable"]


def test_panda_first_link_fails():
    """example-robot-data's Panda link1: 4.97 kg with ixx 0.70 kg m^2 puts the mass 0.37 m
    (RMS) from an axis through a part 0.11 m wide."""
    path = _real_robot("panda.urdf")
    if path is None:
        pytest.skip("example-robot-data not installed")
    found = by_link(urdfinertia.check(path))
    assert "not-realizable" in {f.code for f in found["panda_link1"]}
    assert "not-realizable" not in {f.code for f in found.get("panda_leftfinger", ())}  # 1.01x


def test_a_real_robot_with_a_thin_rod_of_wide_tensor_fails():
    """double_pendulum_simple: link2 is a 2.5 cm square rod of 0.3 kg whose izz 0.002 puts
    the mass 8 cm from its axis (every other rule passes it)."""
    path = _real_robot("double_pendulum_simple.urdf")
    if path is None:
        pytest.skip("example-robot-data not installed")
    found = by_link(urdfinertia.check(path))
    assert "not-realizable" in {f.code for f in found["link2"]}
