"""Tensor validity and the smallest lift (tensor_repair), and ``fix --repair-only``."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from urdfinertia.cli import main
from urdfinertia.descriptions.inertial import RawInertial
from urdfinertia.descriptions.urdf.read import read_urdf
from urdfinertia.inertia.tensor_repair import MIN_MOMENT_RTOL, REPAIR_MARGIN, repair_tensor
from urdfinertia.inertia.validity import diagnose_tensor, is_placeholder


def random_rotation(rng: np.random.Generator) -> np.ndarray:
    q, r = np.linalg.qr(rng.normal(size=(3, 3)))
    q = q * np.sign(np.diag(r))
    if np.linalg.det(q) < 0:
        q[:, 0] *= -1
    return q


def rotated_diag(moments, rot: np.ndarray) -> np.ndarray:
    return rot @ np.diag(moments) @ rot.T


def test_box_tensor_is_valid():
    # A solid box 0.1 x 0.2 x 0.3 m, 2 kg: I = m/12 (b^2 + c^2, ...).
    m, (a, b, c) = 2.0, (0.1, 0.2, 0.3)
    t = np.diag([m / 12 * (b * b + c * c), m / 12 * (a * a + c * c), m / 12 * (a * a + b * b)])
    d = diagnose_tensor(t)
    assert d.valid and d.triangle_excess < 0


def test_triangle_excess_is_relative_to_largest_moment(rng):
    rot = random_rotation(rng)
    d = diagnose_tensor(rotated_diag([1.0, 2.0, 4.0], rot))
    # (C - A - B) / C = (4 - 3) / 4; eigen round-off is ~1e-15 relative.
    assert d.triangle_excess == pytest.approx(0.25, rel=1e-12)
    assert d.positive_definite and not d.triangle_ok and not d.valid


def test_not_positive_definite_and_not_finite():
    t = np.array([[1.0, 2.0, 0.0], [2.0, 1.0, 0.0], [0.0, 0.0, 1.0]])  # eigenvalues -1, 1, 3
    d = diagnose_tensor(t)
    assert not d.positive_definite and d.moments[0] == pytest.approx(-1.0)
    t[0, 0] = np.nan
    assert not diagnose_tensor(t).finite and not diagnose_tensor(t).valid


@pytest.mark.parametrize("value, expected", [(1.0, True), (1e-6, True), (1e-9, True),
                                             (0.5, False), (0.0, False), (1e-5, False),
                                             (9.68e-7, False)])  # a real small sphere
def test_placeholder(value, expected):
    assert is_placeholder(np.eye(3) * value) is expected


def test_placeholder_needs_zero_products_and_equal_diagonal():
    t = np.eye(3)
    t[0, 1] = t[1, 0] = 1e-3
    assert not is_placeholder(t)
    assert not is_placeholder(np.diag([1.0, 1.0, 1e-6]))


def test_valid_tensors_are_left_alone(rng):
    for _ in range(50):
        m = np.sort(rng.uniform(0.1, 1.0, 3))
        m[0] = max(m[0], m[2] - m[1] + 1e-3)  # make sure A + B > C
        t = rotated_diag(m, random_rotation(rng))
        r = repair_tensor(t)
        assert not r.changed and np.array_equal(r.tensor, t)


def test_repair_lifts_only_the_smallest_moment_in_the_principal_frame(rng):
    for _ in range(50):
        c = rng.uniform(0.5, 2.0)
        b = rng.uniform(0.3, 1.0) * c
        a = rng.uniform(0.01, 0.99) * min(b, c - b)  # smallest, and breaks A + B >= C
        rot = random_rotation(rng)
        r = repair_tensor(rotated_diag([a, b, c], rot))
        assert r.changed
        after = diagnose_tensor(r.tensor)
        assert after.valid
        # The repaired tensor is diagonal in the original principal frame (same axes);
        # 1e-12 of the largest moment covers the rotation round-off.
        in_frame = rot.T @ r.tensor @ rot
        assert np.abs(in_frame - np.diag(np.diag(in_frame))).max() < 1e-12 * c
        assert np.diag(in_frame) == pytest.approx([c - b + REPAIR_MARGIN * c, b, c],
                                                  rel=1e-12)


def test_repair_of_semi_definite_rod_raises_the_zero_moment():
    r = repair_tensor(np.diag([0.0, 1.0, 1.0]))
    assert diagnose_tensor(r.tensor).valid
    assert sorted(np.diag(r.tensor)) == pytest.approx([MIN_MOMENT_RTOL, 1.0, 1.0], rel=1e-9)


def test_negative_eigenvalue_is_floored_then_triangle_lifted():
    t = np.array([[1.0, 2.0, 0.0], [2.0, 1.0, 0.0], [0.0, 0.0, 1.0]])  # -1, 1, 3
    r = repair_tensor(t)
    assert diagnose_tensor(r.tensor).valid
    assert np.all(r.moments_after >= r.moments_before - 1e-15)  # nothing lowered


@pytest.mark.parametrize("t", [np.zeros((3, 3)), -np.eye(3), np.full((3, 3), np.nan)])
def test_nothing_to_keep_is_refused(t):
    with pytest.raises(ValueError):
        repair_tensor(t)


# --- fix --repair-only -----------------------------------------------------------------
BROKEN = """<?xml version="1.0"?>
<robot name="r">
  <link name="base"/>
  <link name="arm">
    <!-- keep me -->
    <inertial>
      <origin xyz="0.01 0.02 0.03" rpy="0.3 0.2 0.1"/>
      <mass value="1.5"/>
      <inertia ixx="0.001" ixy="0" ixz="0" iyy="0.002" iyz="0" izz="0.004"/>
    </inertial>
    <visual><geometry><box size="0.1 0.1 0.1"/></geometry></visual>
  </link>
  <link name="ok">
    <inertial>
      <origin xyz="0 0 0.1"/>
      <mass value="2"/>
      <inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/>
    </inertial>
  </link>
  <joint name="j" type="revolute"><parent link="base"/><child link="arm"/>
    <axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
  <joint name="k" type="revolute"><parent link="arm"/><child link="ok"/>
    <axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
</robot>
"""


def test_repair_only_keeps_mass_com_and_valid_links(tmp_path: Path):
    src = tmp_path / "r.urdf"
    src.write_text(BROKEN)
    out = tmp_path / "out.urdf"
    assert main(["fix", str(src), "--repair-only", "-o", str(out), "-q"]) == 0
    before, _ = read_urdf(src)
    after, text = read_urdf(out)
    raw0 = RawInertial.from_inertial(before.link("arm").inertial)
    raw1 = RawInertial.from_inertial(after.link("arm").inertial)
    assert raw1.mass == raw0.mass
    assert np.array_equal(raw1.com, raw0.com)
    d0, d1 = diagnose_tensor(raw0.inertia), diagnose_tensor(raw1.inertia)
    assert not d0.valid and d1.valid
    # Largest two moments kept (1e-12: eigen round-off); smallest lifted to C - B (+margin).
    assert sorted(d1.moments) == pytest.approx([0.002, 0.002 + 0.004 * REPAIR_MARGIN, 0.004],
                                               rel=1e-9)
    # The valid link and the comment are byte for byte as they were.
    assert b"<!-- keep me -->" in text
    ok_block = BROKEN[BROKEN.index('<link name="ok">'):BROKEN.index("</robot>")]
    assert ok_block.encode() in text


def test_repaired_file_loads_in_mujoco(tmp_path: Path):
    mujoco = pytest.importorskip("mujoco")
    src = tmp_path / "r.urdf"
    src.write_text(BROKEN)
    with pytest.raises(ValueError, match="A \\+ B >= C"):
        mujoco.MjModel.from_xml_path(str(src))
    out = tmp_path / "out.urdf"
    assert main(["fix", str(src), "--repair-only", "-o", str(out), "-q"]) == 0
    model = mujoco.MjModel.from_xml_path(str(out))
    assert model.nbody >= 2
    assert main(["check", str(out), "--strict", "-q", "--no-geometry"]) == 0


def test_repair_only_leaves_unrepairable_alone(tmp_path: Path):
    src = tmp_path / "r.urdf"
    src.write_text(BROKEN.replace('ixx="0.001" ixy="0" ixz="0" iyy="0.002" iyz="0" izz="0.004"',
                                  'ixx="0" ixy="0" ixz="0" iyy="0" iyz="0" izz="0"'))
    out = tmp_path / "out.urdf"
    js = tmp_path / "out.json"
    assert main(["fix", str(src), "--repair-only", "-o", str(out), "-q", "--json", str(js)]) == 0
    assert out.read_bytes() == src.read_bytes()
    assert "not repaired" in js.read_text()
