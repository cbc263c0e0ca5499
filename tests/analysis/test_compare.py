"""``urdf-inertia compare``: metrics, degenerate axes, invalid sides, files, CLI and plot."""

from __future__ import annotations

import csv
import json
import math
from pathlib import Path

import numpy as np
import pytest

from urdfinertia.analysis.compare import (
    compare_files,
    compare_raw,
    compare_with_geometry,
    inertia_rel_error,
    principal_axis_angle,
    summary,
)
from urdfinertia.body.options import FixOptions
from urdfinertia.cli import main
from urdfinertia.descriptions.inertial import RawInertial
from urdfinertia.inertia.rotation import rpy_matrix
from urdfinertia.render.compare_plot import error_series, plot_errors


def axis_rotation(axis, angle: float) -> np.ndarray:
    k = np.asarray(axis, float) / np.linalg.norm(axis)
    kx = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
    return np.eye(3) + math.sin(angle) * kx + (1 - math.cos(angle)) * kx @ kx


def rotated(moments, rot) -> np.ndarray:
    return rot @ np.diag(moments) @ rot.T


# --- maths ---------------------------------------------------------------------------
def test_relative_error_of_a_scaled_tensor():
    t = rotated([1.0, 2.0, 2.5], rpy_matrix([0.1, 0.2, 0.3]))
    assert inertia_rel_error(t, 1.07 * t) == pytest.approx(0.07, rel=1e-12)
    assert inertia_rel_error(np.zeros((3, 3)), np.zeros((3, 3))) == 0.0
    assert inertia_rel_error(np.zeros((3, 3)), t) == math.inf


def test_axis_angle_of_distinct_moments_is_the_rotation(rng):
    base = rotated([1.0, 2.0, 2.9], rpy_matrix(rng.uniform(-3, 3, 3)))
    for deg in (0.5, 5.0, 30.0):
        rot = axis_rotation(rng.normal(size=3), math.radians(deg))
        angle = principal_axis_angle(base, rot @ base @ rot.T)
        # Rotating by theta about an arbitrary axis moves no axis by more than theta, and
        # at least one by theta sin(angle to the rotation axis): check the upper bound and
        # that it is of the rotation's size.
        assert deg * 0.5 <= angle <= deg + 1e-9


def test_axis_angle_rotation_about_the_unique_axis_of_a_symmetric_body(rng):
    # Moments (1, 1, 2): any axis in the x-y plane is principal; spinning about z changes
    # nothing physical, so the angle must be 0 (eigenvectors alone would give anything).
    base = np.diag([1.0, 1.0, 2.0])
    spun = axis_rotation([0, 0, 1], 0.7)
    assert principal_axis_angle(base, spun @ base @ spun.T) == pytest.approx(0, abs=1e-6)
    tilt = axis_rotation([1, 0, 0], math.radians(12))
    assert principal_axis_angle(base, tilt @ base @ tilt.T) == pytest.approx(12, abs=1e-6)


def test_axis_angle_isotropic_is_zero(rng):
    rot = axis_rotation(rng.normal(size=3), 1.0)
    assert principal_axis_angle(np.eye(3), rotated([1.0, 1.5, 2.0], rot)) == 0.0


def test_identical_links_compare_ok():
    raw = RawInertial(2.0, np.array([0.1, 0.0, 0.2]), rotated([0.01, 0.02, 0.025],
                                                              rpy_matrix([0.3, 0, 0])))
    c = compare_raw("l", raw, raw)
    assert c.verdict == "ok" and c.mass_ratio == 1 and c.com_distance == 0
    assert c.inertia_rel_error == 0 and c.axis_angle_deg == pytest.approx(0, abs=1e-6)


def test_com_shift_relative_to_radius_of_gyration():
    t = np.diag([0.02, 0.03, 0.04])
    a = RawInertial(2.0, np.zeros(3), t)
    b = RawInertial(2.0, np.array([0.0, 0.03, 0.04]), t)
    c = compare_raw("l", a, b)
    size = math.sqrt(0.09 / 2.0)  # sqrt(tr I / m)
    assert c.com_distance == pytest.approx(0.05, rel=1e-12)
    assert c.com_distance_rel == pytest.approx(0.05 / size, rel=1e-12)
    assert c.verdict == "differs" and "CoM" in c.note


def test_invalid_side_is_reported_not_raised():
    good = RawInertial(1.0, np.zeros(3), np.diag([1.0, 2.0, 2.5]))
    for bad in (RawInertial(1.0, np.zeros(3), np.diag([1.0, 2.0, 4.0])),  # A + B < C
                RawInertial(np.nan, np.zeros(3), np.eye(3)),
                RawInertial(1.0, np.zeros(3), np.full((3, 3), np.nan))):
        c = compare_raw("l", bad, good)
        assert c.verdict == "invalid" and c.a is None and c.b is not None
        assert c.note.startswith("A:")


def test_missing_side():
    good = RawInertial(1.0, np.zeros(3), np.eye(3))
    c = compare_raw("l", good, None, missing_b="no geometry")
    assert c.verdict == "missing" and c.note == "no geometry" and c.mass_ratio is None


def test_summary_medians_and_worst():
    t = np.diag([1.0, 1.5, 2.0])
    a = RawInertial(1.0, np.zeros(3), t)
    cs = [compare_raw(f"l{k}", a, RawInertial(1.0, np.zeros(3), t * (1 + e)))
          for k, e in enumerate([0.01, 0.2, 0.05])]
    s = summary(cs)
    assert s["median"]["inertia_rel_error"] == pytest.approx(0.05, rel=1e-9)
    assert [n for n, _ in s["worst"]["inertia_rel_error"]] == ["l1", "l2", "l0"]
    assert s["verdicts"] == {"ok": 2, "differs": 1}


# --- files -----------------------------------------------------------------------------
CUBE = """<?xml version="1.0"?>
<robot name="c">
  <link name="base"/>
  <link name="cube">
    <inertial><origin xyz="{com}" rpy="{rpy}"/><mass value="{mass}"/>
      <inertia ixx="{i}" ixy="0" ixz="0" iyy="{i}" iyz="0" izz="{i}"/></inertial>
    <collision><origin xyz="0.01 0 0"/><geometry><box size="0.2 0.2 0.2"/></geometry>
    </collision>
  </link>
  <joint name="j" type="revolute"><parent link="base"/><child link="cube"/>
    <axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
</robot>
"""


def cube(tmp_path: Path, name: str, mass=3.0, com="0.01 0 0", rpy="0 0 0", scale=1.0) -> Path:
    i = mass / 12 * (0.04 + 0.04) * scale  # solid 0.2 m cube, closed form
    path = tmp_path / name
    path.write_text(CUBE.format(com=com, rpy=rpy, mass=mass, i=repr(i)))
    return path


def test_exact_inertial_matches_the_geometry(tmp_path):
    (c,) = compare_with_geometry(cube(tmp_path, "c.urdf"), FixOptions())
    # Same closed form on both sides: only round-off (1e-12) separates them.
    assert c.verdict == "ok" and c.mass_ratio == 1
    assert c.com_distance < 1e-12 and c.inertia_rel_error < 1e-12


def test_plausible_tensor_beyond_tolerance_is_kept_not_differs(tmp_path):
    # 30 % off the homogeneous cube: beyond the 10 % tolerance, but plausible, so fix keeps
    # it; compare says so rather than "differs" (the homogeneous solid is a model)
    (c,) = compare_with_geometry(cube(tmp_path, "c.urdf", scale=1.3), FixOptions())
    assert c.verdict == "kept" and c.inertia_rel_error == pytest.approx(0.3 / 1.3,
                                                                          rel=1e-9)
    assert c.decision == "would be kept: plausible"
    assert c.fix is not None and c.fix.action == "keep"


def test_wrong_tensor_differs_from_the_geometry(tmp_path):
    # 300x the cube's tensor: beyond what the geometry allows, so fix recomputes it (an
    # isotropic tensor whose radius of gyration no 1 kg compact body has: a placeholder)
    (c,) = compare_with_geometry(cube(tmp_path, "c.urdf", scale=300.0), FixOptions())
    assert c.verdict == "differs" and c.inertia_rel_error == pytest.approx(299 / 300,
                                                                             rel=1e-9)
    assert c.decision == "would be recomputed: placeholder-inertia, inertia-vs-geometry"


def test_compare_two_files(tmp_path):
    a = cube(tmp_path, "a.urdf")
    b = cube(tmp_path, "b.urdf", mass=6.0, com="0.01 0.02 0")
    (c,) = compare_files(a, b)
    assert c.mass_ratio == 2.0 and c.com_distance == pytest.approx(0.02, rel=1e-12)
    assert c.inertia_rel_error == pytest.approx(1.0, rel=1e-12)  # tensor doubles with mass
    assert c.verdict == "differs" and "mass" in c.note


def test_invalid_written_tensor_compares_as_invalid(tmp_path):
    path = tmp_path / "bad.urdf"
    path.write_text(CUBE.format(com="0 0 0", rpy="0 0 0", mass=3, i="0.001").replace(
        'izz="0.001"', 'izz="0.01"'))
    (c,) = compare_with_geometry(path, FixOptions())
    assert c.verdict == "invalid" and "A+B<C" in c.note and c.b is not None


# --- CLI and plot ------------------------------------------------------------------------
def test_cli_writes_json_csv_png_and_fails_above(tmp_path, capsys):
    path = cube(tmp_path, "c.urdf", scale=1.3)
    js, cs, png = tmp_path / "c.json", tmp_path / "c.csv", tmp_path / "c.png"
    argv = ["compare", str(path), "--json", str(js), "--csv", str(cs), "--plot", str(png)]
    assert main(argv) == 0
    assert f"urdf-inertia: wrote {png}" in capsys.readouterr().err  # where the PNG went
    doc = json.loads(js.read_text())
    (row,) = doc["links"]
    # 23 % off the homogeneous cube and plausible: fix keeps it, so it does not fail
    assert row["verdict"] == "kept" and row["inertia_rel_error"] == pytest.approx(0.3 / 1.3)
    assert row["action"] == "keep" and row["fix"] == "would be kept: plausible"
    (line,) = list(csv.DictReader(cs.open()))
    assert float(line["inertia_rel_error"]) == pytest.approx(0.3 / 1.3)
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert main(["compare", str(path), "-q", "--fail-above", "0.2"]) == 0
    # 300x: fix recomputes it, so it differs and fails above the threshold
    wrong = cube(tmp_path, "w.urdf", scale=300.0)
    assert main(["compare", str(wrong), "-q", "--fail-above", "0.5"]) == 1
    assert main(["compare", str(wrong), "-q", "--fail-above", "1.5"]) == 0


def test_cli_against_other_file(tmp_path, capsys):
    a = cube(tmp_path, "a.urdf")
    b = cube(tmp_path, "b.urdf", mass=3.3)
    assert main(["compare", str(a), "--against", str(b), "--fail-above", "0.05"]) == 1
    assert "1.1" in capsys.readouterr().out  # the mass ratio shows in the table


def test_error_series_is_worst_first():
    t = np.diag([1.0, 1.5, 2.0])
    a = RawInertial(1.0, np.zeros(3), t)
    cs = [compare_raw(f"l{k}", a, RawInertial(1.0, np.zeros(3), t * (1 + e)))
          for k, e in enumerate([0.01, 0.2, 0.05])]
    cs.append(compare_raw("bad", RawInertial(1.0, np.zeros(3), np.diag([1, 1, 3.0])), a))
    s = error_series(cs)
    assert s["links"] == ["bad", "l1", "l2", "l0"]
    assert s["inertia_rel_error"][1] == pytest.approx(0.2, rel=1e-9)


def test_compare_on_a_cad_robot(erd_dir, tmp_path):
    """A real robot with CAD inertials: table, JSON, CSV and PNG without a failure."""
    urdf = erd_dir / "robots" / "solo_description" / "robots" / "solo12.urdf"
    png = tmp_path / "solo.png"
    js = tmp_path / "solo.json"
    assert main(["compare", str(urdf), "-q", "--plot", str(png), "--json", str(js)]) == 0
    doc = json.loads(js.read_text())
    assert len(doc["links"]) == doc["summary"]["links"] > 10
    assert png.stat().st_size > 10_000
    assert plot_errors([], tmp_path / "empty.png") == error_series([])
