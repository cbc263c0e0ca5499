"""Spec parts with ``shell`` and ``infill``: masses and tensors against closed forms,
reading errors, and the solid fallback."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import trimesh

from urdfinertia.body.options import FixOptions
from urdfinertia.body.spec import parse_spec
from urdfinertia.errors import SpecError
from urdfinertia.plan.fix import fix_file

#: Sums of closed forms: round-off only.
RTOL = 1e-10
PLA = 1240.0  # kg/m^3

URDF = """<?xml version="1.0"?>
<robot name="printed">
  <link name="bracket">
    <inertial><mass value="1"/>
      <inertia ixx="1" ixy="0" ixz="0" iyy="1" iyz="0" izz="1"/></inertial>
    <collision><geometry><box size="0.1 0.06 0.04"/></geometry></collision>
    <visual><geometry><mesh filename="box.stl"/></geometry></visual>
  </link>
</robot>
"""
SIZE = np.array([0.1, 0.06, 0.04])


def _box(size: np.ndarray) -> tuple[float, np.ndarray]:
    a, b, c = size
    v = a * b * c
    return v, v / 12 * np.diag([b * b + c * c, a * a + c * c, a * a + b * b])


def _expected(t: float, wall_density: float, interior_density: float,
              ) -> tuple[float, np.ndarray]:
    v_out, i_out = _box(SIZE)
    v_in, i_in = _box(SIZE - 2 * t)
    mass = wall_density * (v_out - v_in) + interior_density * v_in
    return mass, wall_density * (i_out - i_in) + interior_density * i_in


@pytest.fixture
def urdf(tmp_path: Path) -> Path:
    trimesh.creation.box(extents=SIZE).export(tmp_path / "box.stl")
    path = tmp_path / "printed.urdf"
    path.write_text(URDF)
    return path


def _fix(urdf: Path, part: str):  # type: ignore[no-untyped-def]
    spec = parse_spec(f"[links.bracket.elements.body.parts.p]\n{part}\n", urdf.parent / "s.toml")
    return fix_file(urdf, FixOptions(spec=spec)).link("bracket")


@pytest.mark.parametrize("shape", ["box = { size = [0.1, 0.06, 0.04] }",
                                   'mesh = { filename = "box.stl" }', "collision = 0",
                                   "visual = 0"])
def test_pla_shell_with_infill(urdf: Path, shape: str) -> None:
    """2 mm walls of PLA and 20 % infill, as a primitive, a mesh and selected geometry."""
    result = _fix(urdf, f"{shape}\nmaterial = \"PLA\"\nshell = {{ thickness = 0.002 }}\n"
                  "infill = 0.2")
    mass, inertia = _expected(0.002, PLA, 0.2 * PLA)
    # an STL holds float32 coordinates: ~1e-7 of the sides
    rtol = 1e-6 if "mesh" in shape or "visual" in shape else RTOL
    assert result.after.mass == pytest.approx(mass, rel=rtol)
    np.testing.assert_allclose(result.after.inertia, inertia, rtol=max(rtol, 1e-9), atol=1e-15)
    provenance = [pr.part.provenance for pr in result.assembly.parts]
    assert all("shell, 2 mm wall, interior at 0.2 x the wall's density" in p
               for p in provenance)


def test_hollow_by_default(urdf: Path) -> None:
    result = _fix(urdf, "box = { size = [0.1, 0.06, 0.04] }\ndensity = 1000\n"
                  "shell = { thickness = 0.003 }")
    assert result.after.mass == pytest.approx(_expected(0.003, 1000, 0)[0], rel=RTOL)


def test_infill_with_its_own_density(urdf: Path) -> None:
    """The interior is 30 % of a 500 kg/m^3 foam; the wall is PLA."""
    result = _fix(urdf, "box = { size = [0.1, 0.06, 0.04] }\nmaterial = \"PLA\"\n"
                  "shell = { thickness = 0.002 }\ninfill = { fraction = 0.3, density = 500 }")
    mass, inertia = _expected(0.002, PLA, 0.3 * 500)
    assert result.after.mass == pytest.approx(mass, rel=RTOL)
    np.testing.assert_allclose(result.after.inertia, inertia, rtol=1e-9)


def test_known_mass_spreads_over_wall_and_infill(urdf: Path) -> None:
    """A weighed part of 0.1 kg: shared by the wall and the 20 % infill by volume x
    density, so the tensor is the PLA one scaled to 0.1 kg."""
    result = _fix(urdf, "box = { size = [0.1, 0.06, 0.04] }\nmass = 0.1\n"
                  "shell = { thickness = 0.002 }\ninfill = 0.2")
    mass, inertia = _expected(0.002, PLA, 0.2 * PLA)
    assert result.after.mass == pytest.approx(0.1, rel=RTOL)
    np.testing.assert_allclose(result.after.inertia, inertia * 0.1 / mass, rtol=1e-9)


def test_too_thick_a_wall_keeps_the_part_solid_and_says_so(urdf: Path) -> None:
    result = _fix(urdf, "box = { size = [0.1, 0.06, 0.04] }\nmaterial = \"PLA\"\n"
                  "shell = { thickness = 0.025 }\ninfill = 0.2")
    assert result.after.mass == pytest.approx(PLA * np.prod(SIZE), rel=RTOL)
    (part,) = [pr.part for pr in result.assembly.parts]
    assert "solid: no 25 mm shell fits" in part.provenance
    assert any("kept solid" in note for note in part.notes)


def test_too_thick_a_mesh_wall_keeps_the_part_solid(urdf: Path) -> None:
    result = _fix(urdf, 'mesh = { filename = "box.stl" }\nmaterial = "PLA"\n'
                  "shell = { thickness = 0.025 }")
    assert result.after.mass == pytest.approx(PLA * np.prod(SIZE), rel=1e-6)  # float32 STL
    assert "solid: no 25 mm shell fits" in result.assembly.parts[0].part.provenance


@pytest.mark.parametrize(("part", "key", "message"), [
    ("infill = 0.2", "p.infill", "give the part a shell"),
    ("shell = { thicknes = 0.002 }", "p.shell.thicknes", "did you mean 'thickness'"),
    ("shel = { thickness = 0.002 }", "p.shel", "did you mean 'shell'"),
    ("shell = { thickness = 0.002 }\ninfil = 0.2", "p.infil", "did you mean 'infill'"),
    ("shell = 0.002", "p.shell", "expected a table"),
    ("shell = {}", "p.shell.thickness", "missing"),
    ("shell = { thickness = -1 }", "p.shell.thickness", "positive"),
    ("shell = { thickness = 0.002 }\ninfill = 1.5", "p.infill", "fraction from 0"),
    ("shell = { thickness = 0.002 }\ninfill = { fraction = 0.2, dens = 3 }",
     "p.infill.dens", "did you mean 'density'"),
    ("shell = { thickness = 0.002 }\ninfill = {}", "p.infill", "give fraction"),
    ("mass = 0.1\nshell = { thickness = 0.002 }\ninfill = { density = 300 }",
     "p.infill.density", "the part's mass is given"),
    ("shell = { thickness = 0.002 }\ninfill = { material = \"unobtainium\" }",
     "p.infill.material", "unknown material"),
    ("cavity = true\nshell = { thickness = 0.002 }", "p.shell", "no wall"),
])
def test_reading_errors(tmp_path: Path, part: str, key: str, message: str) -> None:
    text = f"[links.l.elements.e.parts.p]\nbox = {{ size = [0.1, 0.1, 0.1] }}\n{part}\n"
    with pytest.raises(SpecError) as info:
        parse_spec(text, tmp_path / "s.toml")
    assert f"links.l.elements.e.parts.{key}" in str(info.value)
    assert message in str(info.value)


def test_a_part_with_a_thin_fin_is_estimated_on_voxels(urdf: Path) -> None:
    """One body: a box with a 1.5 mm fin standing on it. The exact offset is refused (no
    2 mm wall fits in the fin) and the voxel estimate says so, with its stated error."""
    box = trimesh.creation.box(extents=SIZE)
    fin = trimesh.creation.box(extents=[0.08, 0.0015, 0.03])
    fin.apply_translation([0, 0, 0.034])  # overlaps the box by 1 mm: one body
    trimesh.boolean.union([box, fin], engine="manifold").export(urdf.parent / "fin.stl")
    result = _fix(urdf, 'mesh = { filename = "fin.stl" }\nmaterial = "PLA"\n'
                  "shell = { thickness = 0.002 }\ninfill = 0.2")
    (part,) = [pr.part for pr in result.assembly.parts]
    assert "voxel estimate" in part.method
    assert any("exact offset refused" in note for note in part.notes)
    assert part.uncertainty is not None and 0 < part.uncertainty < 0.2
    box_only, _ = _expected(0.002, PLA, 0.2 * PLA)
    fin_mass = PLA * 0.08 * 0.0015 * 0.028  # all wall
    assert result.after.mass == pytest.approx(box_only + fin_mass, rel=part.uncertainty)


@pytest.mark.parametrize("scale", ["0.001", "[-0.001, 0.001, 0.001]"])
def test_the_wall_is_in_metres_after_the_mesh_scale(urdf: Path, scale: str) -> None:
    """A mesh in millimetres (and mirrored): the 2 mm wall is measured after scaling."""
    trimesh.creation.box(extents=SIZE * 1000).export(urdf.parent / "box_mm.stl")
    result = _fix(urdf, f'mesh = {{ filename = "box_mm.stl", scale = {scale} }}\n'
                  'material = "PLA"\nshell = { thickness = 0.002 }\ninfill = 0.2')
    mass, inertia = _expected(0.002, PLA, 0.2 * PLA)
    assert result.after.mass == pytest.approx(mass, rel=1e-6)  # float32 STL
    np.testing.assert_allclose(result.after.inertia, inertia, rtol=1e-6, atol=1e-15)
    assert result.assembly.parts[0].part.method == "mesh shell (exact offset: simple corners)"


def test_a_mesh_shell_comes_from_the_mesh_cache_the_second_time(
        urdf: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """The repair and the offset (or voxels) of a mesh shell are kept in the mesh cache:
    a second run reads no mesh and gives the same part; another wall is computed anew."""
    from urdfinertia.body import parts
    from urdfinertia.cache import library

    monkeypatch.setenv("URDFINERTIA_CACHE_DIR", str(tmp_path / "cache"))
    box = trimesh.creation.box(extents=SIZE)
    fin = trimesh.creation.box(extents=[0.08, 0.0015, 0.03])
    fin.apply_translation([0, 0, 0.034])
    trimesh.boolean.union([box, fin], engine="manifold").export(urdf.parent / "fin.stl")
    part = 'mesh = { filename = "fin.stl" }\nmaterial = "PLA"\ninfill = 0.2\n'
    first = _fix(urdf, part + "shell = { thickness = 0.002 }")

    def no_reading(*args: object) -> None:
        raise AssertionError("read a mesh the cache holds")

    monkeypatch.setattr(library, "load_mesh", no_reading)
    monkeypatch.setattr(parts, "load_mesh", no_reading)
    second = _fix(urdf, part + "shell = { thickness = 0.002 }")
    (a,), (b,) = ([pr.part for pr in r.assembly.parts] for r in (first, second))
    assert (a.method, a.notes, a.provenance, a.uncertainty) == \
        (b.method, b.notes, b.provenance, b.uncertainty)
    assert second.after.mass == first.after.mass
    np.testing.assert_array_equal(second.after.inertia, first.after.inertia)
    with pytest.raises(AssertionError, match="the cache holds"):
        _fix(urdf, part + "shell = { thickness = 0.003 }")
