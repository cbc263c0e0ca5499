"""spec.py point parts: a motor or battery as a point mass, against the parallel-axis
closed form (eq. 43: m (|r|^2 E - r r^T))."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from urdfinertia.body.options import FixOptions
from urdfinertia.body.spec import parse_spec
from urdfinertia.errors import SpecError
from urdfinertia.plan.fix import fix_file

#: Sums of closed forms: only round-off separates tool and expectation.
RTOL = 1e-12

HOUSING_URDF = """<?xml version="1.0"?>
<robot name="drive">
  <link name="housing">
    <inertial><mass value="1"/>
      <inertia ixx="1" ixy="0" ixz="0" iyy="1" iyz="0" izz="1"/></inertial>
    <collision><geometry><box size="0.1 0.2 0.3"/></geometry></collision>
  </link>
</robot>
"""


def _box_inertia(m: float, size: tuple[float, float, float]) -> np.ndarray:
    a, b, c = size
    return m / 12 * np.diag([b * b + c * c, a * a + c * c, a * a + b * b])


def _steiner(m: float, r: np.ndarray) -> np.ndarray:
    return m * (r @ r * np.eye(3) - np.outer(r, r))


@pytest.fixture
def urdf(tmp_path: Path) -> Path:
    path = tmp_path / "drive.urdf"
    path.write_text(HOUSING_URDF)
    return path


@pytest.mark.parametrize("pinned", [None, 2.5])
def test_point_mass_in_a_housing(urdf: Path, tmp_path: Path, pinned: float | None) -> None:
    # a 0.3 kg motor at (0.02, -0.05, 0.1) in a box housing; the housing weighs 1.2 kg
    # (its own stated mass), or takes the rest of a pinned 2.5 kg link mass
    link_mass = f"mass = {pinned}" if pinned is not None else ""
    housing = "" if pinned is not None else "mass = 1.2"
    spec = parse_spec(f"""
[links.housing]
{link_mass}
[links.housing.elements.body.parts.shell]
box = {{ size = [0.1, 0.2, 0.3] }}
{housing}
[links.housing.elements.body.parts.motor]
point = {{ xyz = [0.02, -0.05, 0.1], mass = 0.3 }}
""", tmp_path / "s.toml")
    total = fix_file(urdf, FixOptions(spec=spec)).link("housing").after
    m_box = 2.2 if pinned is not None else 1.2
    m_pt, r = 0.3, np.array([0.02, -0.05, 0.1])
    com = m_pt * r / (m_box + m_pt)
    expected = (_box_inertia(m_box, (0.1, 0.2, 0.3)) + _steiner(m_box, -com)
                + _steiner(m_pt, r - com))
    assert total.mass == pytest.approx(m_box + m_pt, rel=RTOL)
    np.testing.assert_allclose(total.com, com, rtol=RTOL, atol=1e-15)
    np.testing.assert_allclose(total.inertia, expected, rtol=1e-10, atol=1e-15)


def test_point_in_a_rotated_element(urdf: Path, tmp_path: Path) -> None:
    """The point's xyz is in its element's frame: an element turned 90 degrees about z
    and moved carries it along (x -> y)."""
    spec = parse_spec("""
[links.housing.elements.body.parts.shell]
box = { size = [0.1, 0.2, 0.3] }
mass = 1.0
[links.housing.elements.drive]
xyz = [0, 0, 0.05]
rpy = [0, 0, 1.5707963267948966]
[links.housing.elements.drive.parts.battery]
point = { xyz = [0.04, 0, 0], mass = 0.5 }
""", tmp_path / "s.toml")
    total = fix_file(urdf, FixOptions(spec=spec)).link("housing").after
    r = np.array([0.0, 0.04, 0.05])
    com = 0.5 * r / 1.5
    expected = _box_inertia(1.0, (0.1, 0.2, 0.3)) + _steiner(1.0, -com) + _steiner(0.5, r - com)
    np.testing.assert_allclose(total.com, com, rtol=1e-12, atol=1e-15)
    np.testing.assert_allclose(total.inertia, expected, rtol=1e-10, atol=1e-14)


@pytest.mark.parametrize(("part", "message"), [
    ("point = { xyz = [0, 0, 0] }", r"parts.m.point.mass: missing"),
    ("point = { xyz = [0, 0], mass = 1 }", r"parts.m.point.xyz: must be a list of 3"),
    ("point = { xyz = [0, 0, 0], mass = 0 }", r"parts.m.point.mass: must be a positive"),
    ("point = { xyz = [0, 0, 0], mas = 1 }", r"parts.m.point.mas: unknown key \(did you "
                                             r"mean 'mass'\?"),
    ("point = { mass = 1 }\nxyz = [0, 0, 1]", r"parts.m.xyz: a point part is given by its "
                                              r"point table alone"),
    ("pont = { mass = 1 }", r"parts.m.pont: unknown key \(did you mean 'point'\?"),
    ("mass = 1", r"parts.m.mass: a known mass needs a volume.*point"),
])
def test_point_errors(part: str, message: str, tmp_path: Path) -> None:
    text = f"[links.housing.elements.body.parts.m]\n{part}\n"
    with pytest.raises(SpecError, match=message):
        parse_spec(text, tmp_path / "s.toml")
