"""analysis/against.py: compare SOURCE --against CONVERTED names every difference a
conversion made, and nothing when it kept the values (float32 round-off aside)."""

from __future__ import annotations

import json
import subprocess
import sys

import numpy as np
import pytest
from descriptions.usd.assets import all_assets, asset, copy, source

from urdfinertia.analysis.against import compare_import
from urdfinertia.descriptions.formats import read_description
from urdfinertia.inertia import primitives


@pytest.mark.parametrize("name", all_assets())
def test_faithful_conversions_have_no_difference(name):
    report = compare_import(source(name), asset(name))
    assert report.differences == []
    assert report.total_engine == pytest.approx(report.total_source, rel=1e-5)
    assert report.total_source > 0


def plant(root):
    """Hand-made damage in the converter's physics payload of a spirit40 copy: the four
    ways an import is known to lose mass properties. Returns {link: planted kind}."""
    from pxr import Gf, Sdf, Usd

    stage = Usd.Stage.Open(str(root))
    path = {p.GetName(): p.GetPath() for p in stage.Traverse()}
    layer = Sdf.Layer.FindOrOpen(str(root.parent / "Payload" / "Physics.usda"))
    robot, _ = read_description(root)

    def spec(link):
        return layer.GetPrimAtPath(path[link])

    # hip1: MassAPI values dropped (the body keeps its collision shapes)
    hip = spec("hip1")
    for attr in ("physics:mass", "physics:diagonalInertia", "physics:principalAxes",
                 "physics:centerOfMass", "newton:inertia"):
        if attr in hip.attributes:  # the converter leaves a zero CoM unwritten
            hip.RemoveProperty(hip.attributes[attr])
    # upper0: the importers' 1 kg default
    spec("upper0").attributes["physics:mass"].default = 1.0
    # upper2: mass from the collision box at water's density
    box = robot.link("upper2").collisions[0].shape
    spec("upper2").attributes["physics:mass"].default = \
        primitives.box(box.size, 1000.0).mass
    # body: principal frame turned 30 degrees about an axis across its unique axis
    tensor = robot.link("body").inertial.tensor_in_link()
    moments, axes = np.linalg.eigh(tensor)
    unique = axes[:, 0]  # moments (0.05, 0.1, 0.1): the smallest is the unique one
    across = np.cross(unique, [0.0, 0.0, 1.0] if abs(unique[2]) < 0.9 else [1.0, 0, 0])
    turn = Gf.Rotation(Gf.Vec3d(*across), 30.0).GetQuat()
    attr = spec("body").attributes["physics:principalAxes"]
    q = attr.default
    q_turn = Gf.Quatf(float(turn.GetReal()), Gf.Vec3f(*turn.GetImaginary()))
    attr.default = (q_turn * q).GetNormalized()
    layer.Save()
    return {"hip1": "dropped", "upper0": "defaulted", "upper2": "density-derived",
            "body": "frame-change"}


def test_every_planted_difference_is_found_and_named(tmp_path):
    root = copy("spirit40", tmp_path)
    planted = plant(root)
    report = compare_import(source("spirit40"), root)
    found = {}
    for d in report.differences:
        found.setdefault(d.link, set()).add(d.kind)
    assert found == {link: {kind} for link, kind in planted.items()}
    body = next(d for d in report.differences if d.link == "body")
    assert "rotated by 30 deg" in body.message
    hip = next(d for d in report.differences if d.link == "hip1")
    # the engine's mass of hip1: its collision cylinder at 1000 kg/m^3
    cyl = read_description(root)[0].link("hip1").collisions[0].shape
    want = primitives.cylinder(cyl.radius, cyl.length, 1000.0).mass
    assert f"{want:.6g} kg" in hip.message
    # totals: source, as authored (hip1 missing, upper0 at 1 kg ...), as engines load it
    assert report.total_source == pytest.approx(11.51, rel=1e-6)
    assert report.total_engine == pytest.approx(
        11.51 - 0.575 + want - 0.775 + 1.0 - 0.775 + primitives.box(
            read_description(root)[0].link("upper2").collisions[0].shape.size, 1000.0).mass,
        rel=1e-5)


def test_cli_compare_against_prints_and_writes_the_differences(tmp_path):
    root = copy("spirit40", tmp_path)
    plant(root)
    out = tmp_path / "c.json"
    done = subprocess.run([sys.executable, "-m", "urdfinertia", "compare", "-q",
                           str(source("spirit40")), "--against", str(root), "--json",
                           str(out), "--fail-above", "1"], capture_output=True, text=True)
    assert done.returncode == 1, done.stderr
    assert "hip1: dropped:" in done.stdout
    assert "4 difference(s) beyond round-off" in done.stdout
    doc = json.loads(out.read_text())["conversion"]
    assert {d["kind"] for d in doc["differences"]} == {"dropped", "defaulted",
                                                      "density-derived", "frame-change"}
    assert doc["total_mass"]["source"] == pytest.approx(11.51)


def test_a_mass_without_a_tensor_keeps_its_mass_and_is_named(tmp_path):
    """A MassAPI with ``physics:mass`` alone is valid (the engine derives CoM and tensor
    from the colliders at that mass): the mass counts in the converted total, and the
    missing tensor is named, not read as a dropped body."""
    from pxr import Sdf, Usd

    root = copy("spirit40", tmp_path)
    stage = Usd.Stage.Open(str(root))
    path = {p.GetName(): p.GetPath() for p in stage.Traverse()}
    layer = Sdf.Layer.FindOrOpen(str(root.parent / "Payload" / "Physics.usda"))
    prim = layer.GetPrimAtPath(path["upper1"])
    for attr in ("physics:diagonalInertia", "physics:principalAxes", "physics:centerOfMass",
                 "newton:inertia"):
        if attr in prim.attributes:
            prim.RemoveProperty(prim.attributes[attr])
    layer.Save()
    report = compare_import(source("spirit40"), root)
    assert [(d.link, d.kind) for d in report.differences] == [("upper1", "mass-only")]
    assert report.total_converted == pytest.approx(report.total_source, rel=1e-5)
    converted = read_description(root)[0].link("upper1")
    assert converted.inertial is None and converted.implicit.mass == pytest.approx(
        read_description(source("spirit40"))[0].link("upper1").inertial.mass, rel=1e-6)
