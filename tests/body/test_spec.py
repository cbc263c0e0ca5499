"""spec.py and materials.py: reading decomposition specs, their parts and their errors."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import trimesh

from urdfinertia.body.materials import MATERIALS, material_density
from urdfinertia.body.options import FixOptions
from urdfinertia.body.spec import load_spec, parse_spec
from urdfinertia.cli import main
from urdfinertia.errors import SpecError
from urdfinertia.plan.fix import fix_file

#: Sums of closed forms: only round-off separates tool and expectation.
RTOL = 1e-12

FOREARM_URDF = """<?xml version="1.0"?>
<robot name="arm">
  <link name="forearm">
    <inertial>
      <origin xyz="0 0 0" rpy="0 0 0"/>
      <mass value="1"/>
      <inertia ixx="1" ixy="0" ixz="0" iyy="1" iyz="0" izz="1"/>
    </inertial>
    <collision name="shell">
      <origin xyz="0 0 0.15" rpy="0 0 0"/>
      <geometry><box size="0.08 0.08 0.3"/></geometry>
    </collision>
  </link>
</robot>
"""

#: The complete example of docs/sections/03-spec.md.
FOREARM_SPEC = """
[materials]
cast_magnesium = 1800.0          # your own names, kg/m^3

[links.forearm]
mass = 2.4                       # pinned total, kg (optional)

[links.forearm.elements.housing]  # an element: a frame in the link frame
xyz = [0.0, 0.0, 0.15]
rpy = [0.0, 0.0, 0.0]

[links.forearm.elements.housing.parts.shell]
collision = "shell"              # the link's own <collision> (or its index, 0)

[links.forearm.elements.housing.parts.bore]
cylinder = { radius = 0.032, length = 0.3 }
cavity = true                    # removed from the shell

[links.forearm.elements.drive]
xyz = [0.0, 0.0, 0.05]

[links.forearm.elements.drive.parts.motor]   # not in the URDF at all
cylinder = { radius = 0.03, length = 0.08 }
mass = 0.45                      # datasheet, kg

[links.forearm.elements.drive.parts.gearbox]
box = { size = [0.04, 0.04, 0.04] }
xyz = [0.0, 0.0, 0.06]           # in the element frame
rpy = [0.0, 0.0, 0.785]
material = "steel"

[links.forearm.elements.wrist]
xyz = [0.0, 0.0, 0.32]
material = "cast_magnesium"      # default for the element's parts

[links.forearm.elements.wrist.parts.bracket]
mesh = { filename = "meshes/bracket.stl", scale = 0.001 }
"""


def write_forearm(folder: Path, spec_text: str = FOREARM_SPEC) -> tuple[Path, Path]:
    (folder / "meshes").mkdir(exist_ok=True)
    trimesh.creation.box([40.0, 20.0, 10.0]).export(folder / "meshes" / "bracket.stl")  # mm
    urdf, spec = folder / "arm.urdf", folder / "arm.inertia.toml"
    urdf.write_text(FOREARM_URDF)
    spec.write_text(spec_text)
    return urdf, spec


def box_i(m, size):
    a, b, c = size
    return m / 12 * np.diag([b * b + c * c, a * a + c * c, a * a + b * b])


def cyl_i(m, r, h):
    return np.diag([m * (3 * r * r + h * h) / 12] * 2 + [m * r * r / 2])


def shift(m, d):
    d = np.asarray(d, dtype=float)
    return m * (d @ d * np.eye(3) - np.outer(d, d))


def test_complete_example(tmp_path):
    urdf, spec = write_forearm(tmp_path)
    lr = fix_file(urdf, FixOptions(spec=load_spec(spec))).links[0]
    # independently: masses, centres and central tensors of the five bodies
    v_shell, v_bore = 0.08 * 0.08 * 0.3, np.pi * 0.032**2 * 0.3
    m_motor, m_gear, m_bracket = 0.45, 7850 * 0.04**3, 1800 * 0.04 * 0.02 * 0.01
    rho_free = (2.4 - m_motor - m_gear - m_bracket) / (v_shell - v_bore)  # pinned, by volume
    bodies = [  # mass, centre, central tensor (all axis-aligned or isotropic)
        (rho_free * v_shell, [0, 0, 0.15], box_i(rho_free * v_shell, [0.08, 0.08, 0.3])),
        (-rho_free * v_bore, [0, 0, 0.15], cyl_i(-rho_free * v_bore, 0.032, 0.3)),
        (m_motor, [0, 0, 0.05], cyl_i(m_motor, 0.03, 0.08)),
        (m_gear, [0, 0, 0.11], box_i(m_gear, [0.04] * 3)),  # a cube: rotation-invariant
        (m_bracket, [0, 0, 0.32], box_i(m_bracket, [0.04, 0.02, 0.01])),
    ]
    mass = sum(b[0] for b in bodies)
    com = sum(b[0] * np.array(b[1], dtype=float) for b in bodies) / mass
    inertia = sum(b[2] + shift(b[0], np.array(b[1]) - com) for b in bodies)
    total = lr.assembly.total
    assert lr.geometry == "spec"
    assert total.mass == pytest.approx(2.4, rel=RTOL)
    np.testing.assert_allclose(total.com, com, rtol=1e-12, atol=1e-15)
    np.testing.assert_allclose(total.inertia, inertia, rtol=1e-10, atol=1e-12 * inertia.max())
    names = [pr.part.name for pr in lr.assembly.parts]
    assert names == ["housing/shell", "housing/bore", "drive/motor", "drive/gearbox",
                     "wrist/bracket"]


def test_parts_compose_element_and_part_frames(tmp_path):
    _, spec_path = write_forearm(tmp_path)
    spec = load_spec(spec_path)
    gearbox = spec.link("forearm").elements[1].parts[1]
    assert gearbox.density == MATERIALS["steel"].density
    assert spec.link("forearm").elements[2].parts[0].density == 1800.0  # element default
    assert spec.link("nope") is None
    assert not spec.link("forearm").uses_default_mass()


def test_part_mass_is_split_over_mesh_bodies_by_volume(tmp_path):
    a, b = trimesh.creation.box([1.0, 2.0, 3.0]), trimesh.creation.box([1.0, 1.0, 1.0])
    b.apply_translation([5.0, 0.0, 0.0])
    trimesh.util.concatenate([a, b]).export(tmp_path / "two.stl")
    urdf = tmp_path / "r.urdf"
    urdf.write_text('<robot name="r">\n  <link name="a">\n  </link>\n</robot>\n')
    spec = tmp_path / "r.toml"
    spec.write_text('[links.a.elements.e.parts.p]\nmesh = { filename = "two.stl", '
                    'scale = [0.01, 0.01, 0.01] }\nmass = 7.0\n')
    lr = fix_file(urdf, FixOptions(spec=load_spec(spec))).links[0]
    masses = sorted(pr.mass_properties.mass for pr in lr.assembly.parts)
    np.testing.assert_allclose(masses, [1.0, 6.0], rtol=RTOL)  # volumes 1 : 6
    np.testing.assert_allclose(lr.assembly.total.com, [0.05 / 7, 0, 0], atol=1e-15)


def test_cavity_makes_a_hollow_tube(tmp_path):
    urdf = tmp_path / "r.urdf"
    urdf.write_text('<robot name="r">\n  <link name="a">\n  </link>\n</robot>\n')
    spec = tmp_path / "r.toml"
    spec.write_text("[links.a.elements.e]\nmaterial = 'aluminium'\n"
                    "[links.a.elements.e.parts.tube]\ncylinder = { radius = 0.05, length = 0.4 }\n"
                    "[links.a.elements.e.parts.bore]\ncylinder = { radius = 0.04, length = 0.4 }\n"
                    "cavity = true\n")
    total = fix_file(urdf, FixOptions(spec=load_spec(spec))).links[0].assembly.total
    rho, ro, ri, h = 2700.0, 0.05, 0.04, 0.4
    m = rho * np.pi * (ro**2 - ri**2) * h  # thick-walled tube, textbook formulas
    izz = m * (ro**2 + ri**2) / 2
    ixx = m * (3 * (ro**2 + ri**2) + h**2) / 12
    assert total.mass == pytest.approx(m, rel=RTOL)
    np.testing.assert_allclose(np.diag(total.inertia), [ixx, ixx, izz], rtol=1e-12)


def test_reference_keeps_default_mass_policy(tmp_path):
    urdf, spec = write_forearm(tmp_path, "[links.forearm.elements.all.parts.shell]\n"
                                         "collision = 0\n")
    s = load_spec(spec)
    assert s.link("forearm").uses_default_mass()
    total = fix_file(urdf, FixOptions(spec=s)).links[0].assembly.total
    assert total.mass == pytest.approx(1.0, rel=RTOL)  # --mass keep: the URDF's mass
    np.testing.assert_allclose(total.com, [0, 0, 0.15], atol=1e-15)
    total = fix_file(urdf, FixOptions(spec=s, mass="density", density=500.0)).links[0]
    assert total.assembly.total.mass == pytest.approx(500 * 0.08 * 0.08 * 0.3, rel=RTOL)


def test_materials_table():
    assert material_density("Steel") == 7850.0
    assert material_density("aluminum") == material_density("Aluminium") == 2700.0
    assert material_density("carbon fibre composite") == 1600.0
    assert material_density("CFRP") == 1600.0
    assert material_density("unobtainium") is None
    assert material_density("steel", {"steel": 7800.0}) == 7800.0  # a spec may override
    for m in MATERIALS.values():
        assert 900.0 <= m.density <= 9000.0  # all solids that sink in water, lighter than Cu


# --- errors: each names the spec file and the TOML key --------------------------------

PART = "[links.a.elements.e.parts.p]\n"
BOX = "box = { size = [0.1, 0.1, 0.1] }\n"


@pytest.mark.parametrize("text, key, words", [
    ("foo = 1\n" + PART + BOX, "foo", "unknown key"),
    ("[links.a]\nmasss = 2\n" + PART + BOX, "links.a.masss", "did you mean 'mass'"),
    ("[links.a.elements.e]\nxzy = [0, 0, 0]\n" + PART + BOX, "links.a.elements.e.xzy",
     "unknown key"),
    (PART + BOX + "densty = 3\n", "links.a.elements.e.parts.p.densty", "did you mean"),
    (PART + BOX + "sphere = { radius = 0.1 }\n", "links.a.elements.e.parts.p",
     "exactly one of"),
    (PART + "mass = 2.0\n", "links.a.elements.e.parts.p.mass", "needs a volume"),
    (PART + BOX + "density = -3\n", "links.a.elements.e.parts.p.density", "positive number"),
    (PART + BOX + "density = true\n", "links.a.elements.e.parts.p.density", "positive number"),
    (PART + BOX + "density = 3\nmaterial = 'steel'\n", "links.a.elements.e.parts.p.material",
     "not both"),
    (PART + BOX + "mass = 1\nmaterial = 'steel'\n", "links.a.elements.e.parts.p.mass",
     "not both"),
    (PART + BOX + "material = 'adamantium'\n", "links.a.elements.e.parts.p.material",
     "steel"),
    (PART + BOX + "xyz = [1, 2]\n", "links.a.elements.e.parts.p.xyz", "3 numbers"),
    (PART + "box = { size = [0.1, -0.1, 0.1] }\n", "links.a.elements.e.parts.p.box.size",
     "positive"),
    (PART + "cylinder = { radius = 0.1 }\n", "links.a.elements.e.parts.p.cylinder.length",
     "missing"),
    (PART + "cylinder = { radius = 0.1, length = 1, lenght = 1 }\n",
     "links.a.elements.e.parts.p.cylinder.lenght", "unknown key"),
    (PART + "mesh = { filename = 'nothere.stl' }\n",
     "links.a.elements.e.parts.p.mesh.filename", "not found"),
    (PART + BOX + "cavity = 'yes'\n", "links.a.elements.e.parts.p.cavity", "true or false"),
    (PART + "collision = 0\nxyz = [0, 0, 1]\n", "links.a.elements.e.parts.p.xyz", "<origin>"),
    (PART + "visual = -1\n", "links.a.elements.e.parts.p.visual", "index"),
    ("[materials]\nsteel = 0\n" + PART + BOX, "materials.steel", "positive"),
    ("[links.a]\nmass = 1\n", "links.a.elements", "at least one element"),
    ("[links.a.elements.e]\nxyz = [0, 0, 0]\n", "links.a.elements.e.parts", "at least one"),
    ("", "links", "no links"),
    ('[links."my link".elements.e.parts.p]\nbox = 3\n', 'links."my link".elements.e.parts.p.box',
     "table"),
])
def test_spec_errors_name_the_key(tmp_path, text, key, words):
    path = tmp_path / "bad.inertia.toml"
    with pytest.raises(SpecError) as info:
        parse_spec(text, path)
    message = str(info.value)
    assert message.startswith(str(path)), message
    assert f" {key}: " in message, message
    assert words in message, message


def test_toml_syntax_error_gives_the_line(tmp_path):
    path = tmp_path / "bad.toml"
    path.write_text("[links.a]\nmass = 2\nthis is not toml\n")
    with pytest.raises(SpecError) as info:
        load_spec(path)
    assert info.value.line == 3
    assert str(info.value).startswith(f"{path}:3:")


def test_missing_spec_file(tmp_path):
    with pytest.raises(SpecError, match="cannot read spec"):
        load_spec(tmp_path / "nothere.toml")


LINK_ERRORS = [
    # (spec text, key, words)
    ("[links.forarm.elements.e.parts.p]\n" + BOX, "links.forarm", "did you mean forearm"),
    ("[links.forearm.elements.e.parts.p]\ncollision = 3\n",
     "links.forearm.elements.e.parts.p.collision", "out of range"),
    ("[links.forearm.elements.e.parts.p]\nvisual = 'shell'\n",
     "links.forearm.elements.e.parts.p.visual", "has no <visual> named 'shell'"),
    ("[links.forearm]\nmass = 1.0\n[links.forearm.elements.e.parts.p]\n" + BOX
     + "[links.forearm.elements.e.parts.q]\ncollision = 0\n[links.forearm.elements.e.parts.m]\n"
     + BOX + "mass = 1.5\n", "links.forearm.mass", "already weigh 1.5 kg"),
    ("[links.forearm]\nmass = 1.0\n[links.forearm.elements.e.parts.p]\n" + BOX
     + "density = 2000\n", "links.forearm.mass", "sum to 2 kg, not the pinned 1 kg"),
    ("[links.forearm]\nmass = 3.0\n[links.forearm.elements.e.parts.p]\n" + BOX
     + "mass = 1\n[links.forearm.elements.e.parts.q]\n" + BOX + "cavity = true\n",
     "links.forearm.mass", "no net volume"),
    ("[links.forearm.elements.e.parts.p]\n" + BOX + "density = 1000\n"
     "[links.forearm.elements.e.parts.q]\nbox = { size = [0.2, 0.1, 0.1] }\ndensity = 1000\n"
     "cavity = true\n", "link 'forearm'", "cavities larger"),
]


@pytest.mark.parametrize("text, key, words", LINK_ERRORS)
def test_errors_against_the_urdf_via_cli(tmp_path, capsys, text, key, words):
    urdf, spec = write_forearm(tmp_path, text)
    assert main(["fix", str(urdf), "--spec", str(spec), "-q", "-o",
                 str(tmp_path / "out.urdf")]) == 2
    err = capsys.readouterr().err.strip()
    assert "\n" not in err  # one line
    assert err.startswith(f"urdf-inertia: error: {spec}"), err
    assert f" {key}: " in err, err
    assert words in err, err
    assert not (tmp_path / "out.urdf").exists()
