"""fix.py and cli_fix.py: the main job end to end."""

import json
from pathlib import Path

import numpy as np
import pytest
import trimesh

from urdfinertia.body.options import FixOptions
from urdfinertia.cli import main
from urdfinertia.inertia import primitives
from urdfinertia.inertia.rotation import rpy_matrix
from urdfinertia.plan.fix import fix_file

DATA = Path(__file__).resolve().parents[1] / "data"


def _all(**options) -> FixOptions:
    """``--all`` at a constant 1000 kg/m^3 (``--density``): the closed forms' density (the
    default's mass prior is tested in test_mass_prior.py)."""
    return FixOptions(recompute="all", density_prior=False, **options)


def write_urdf(folder: Path, body: str, name: str = "robot.urdf") -> Path:
    path = folder / name
    path.write_text(f'<?xml version="1.0"?>\n<robot name="r">\n{body}\n</robot>\n')
    return path


def link(name: str, inner: str) -> str:
    return f'  <link name="{name}">\n{inner}\n  </link>'


def collision(geometry: str, xyz="0 0 0", rpy="0 0 0") -> str:
    return (f'    <collision>\n      <origin xyz="{xyz}" rpy="{rpy}"/>\n'
            f'      <geometry>{geometry}</geometry>\n    </collision>')


def only(result, name):
    return next(r for r in result.links if r.name == name)


def test_geometry_origin_is_honoured(tmp_path):
    xyz, rpy = np.array([0.1, -0.2, 0.3]), np.array([0.3, -0.5, 1.1])
    path = write_urdf(tmp_path, link("l", collision('<box size="0.1 0.2 0.3"/>',
                                                    " ".join(map(str, xyz)),
                                                    " ".join(map(str, rpy)))))
    total = only(fix_file(path, _all(density=500.0)), "l").assembly.total
    expected = primitives.box([0.1, 0.2, 0.3], 500.0).rotated(rpy_matrix(rpy)).translated(xyz)
    np.testing.assert_allclose(total.com, expected.com, atol=1e-15)
    np.testing.assert_allclose(total.inertia, expected.inertia, rtol=1e-12)


def test_rotated_shifted_mesh_equals_rotated_primitive(tmp_path):
    # The same body as a <box> with an origin and as a mesh file already moved into
    # place must give the same link tensor.
    xyz, rpy = [0.05, 0.1, -0.02], [0.7, 0.2, -0.4]
    box = trimesh.creation.box([0.1, 0.2, 0.3])
    moved = box.copy()
    t = np.eye(4)
    t[:3, :3] = rpy_matrix(rpy)
    t[:3, 3] = xyz
    moved.apply_transform(t)
    moved.export(tmp_path / "moved.stl")
    path = write_urdf(tmp_path, link("a", collision('<box size="0.1 0.2 0.3"/>',
                                                    " ".join(map(str, xyz)),
                                                    " ".join(map(str, rpy))))
                      + "\n" + link("b", collision('<mesh filename="moved.stl"/>')))
    res = fix_file(path, _all())
    a, b = only(res, "a").assembly.total, only(res, "b").assembly.total
    # STL stores single-precision vertices: agreement to ~1e-7, asserted at 1e-6
    assert a.mass == pytest.approx(b.mass, rel=1e-6)
    np.testing.assert_allclose(a.com, b.com, atol=1e-7)
    np.testing.assert_allclose(a.inertia, b.inertia, rtol=1e-6, atol=1e-12)


def test_mass_keep_distributes_existing_mass(tmp_path):
    inertial = ('    <inertial><mass value="7.5"/>'
                '<inertia ixx="1" ixy="0" ixz="0" iyy="1" iyz="0" izz="1"/></inertial>')
    geo = collision('<cylinder radius="0.05" length="0.4"/>', "0 0 0.2")
    path = write_urdf(tmp_path, link("l", inertial + "\n" + geo))
    keep = only(fix_file(path, _all()), "l").assembly.total
    expected = primitives.cylinder(0.05, 0.4, 1.0).with_mass(7.5)
    assert keep.mass == 7.5
    np.testing.assert_allclose(keep.com, [0, 0, 0.2])
    np.testing.assert_allclose(keep.inertia, expected.inertia, rtol=1e-12)
    options = _all(mass="density", density=2700.0)
    dens = only(fix_file(path, options), "l").assembly.total
    assert dens.mass == pytest.approx(2700.0 * np.pi * 0.05**2 * 0.4)


def test_several_elements_sum_with_huygens_steiner(tmp_path):
    geo = (collision('<sphere radius="0.1"/>', "0.5 0 0") + "\n"
           + collision('<sphere radius="0.1"/>', "-0.5 0 0"))
    path = write_urdf(tmp_path, link("l", geo))
    total = only(fix_file(path, _all()), "l").assembly.total
    s = primitives.sphere(0.1, 1000.0)
    assert total.mass == pytest.approx(2 * s.mass)
    np.testing.assert_allclose(total.com, 0, atol=1e-15)
    assert total.inertia[1, 1] == pytest.approx(2 * (s.inertia[1, 1] + s.mass * 0.25))
    assert total.inertia[0, 0] == pytest.approx(2 * s.inertia[0, 0])


def test_geometry_modes(tmp_path):
    vis = '    <visual><geometry><box size="1 1 1"/></geometry></visual>'
    col = collision('<box size="0.1 0.1 0.1"/>')
    path = write_urdf(tmp_path, link("both", vis + "\n" + col) + "\n" + link("vis", vis))
    auto = fix_file(path, _all())
    assert only(auto, "both").geometry == "collision"
    assert only(auto, "vis").geometry == "visual"
    assert only(auto, "both").assembly.total.mass == pytest.approx(1.0)
    visual = fix_file(path, _all(geometry="visual"))
    assert only(visual, "both").assembly.total.mass == pytest.approx(1000.0)
    collision_only = fix_file(path, _all(geometry="collision"))
    assert only(collision_only, "vis").status == "untouched"


@pytest.mark.parametrize("fmt", ["stl", "stl_ascii", "obj", "ply", "glb", "dae", "off"])
def test_mesh_formats(tmp_path, fmt):
    mesh = trimesh.creation.annulus(0.02, 0.05, 0.1, sections=32)
    mesh.apply_translation([0.01, 0.02, 0.03])
    ext = "stl" if fmt == "stl_ascii" else fmt
    data = mesh.export(file_type=fmt)
    (tmp_path / f"part.{ext}").write_bytes(data if isinstance(data, bytes) else data.encode())
    path = write_urdf(tmp_path, link("l", collision(f'<mesh filename="part.{ext}"/>')))
    total = only(fix_file(path, _all()), "l").assembly.total
    ref = mesh.mass_properties
    assert total.mass == pytest.approx(1000.0 * ref.volume, rel=1e-5)
    np.testing.assert_allclose(total.com, ref.center_mass, atol=1e-6)


def test_negative_scale_mirrors_com_and_keeps_mass_positive(tmp_path):
    mesh = trimesh.creation.box([0.1, 0.2, 0.3])
    mesh.apply_translation([0.3, 0.1, 0.2])
    mesh.apply_transform(trimesh.transformations.rotation_matrix(0.4, [1, 1, 0]))
    mesh.export(tmp_path / "m.stl")
    geo = (collision('<mesh filename="m.stl"/>'), collision('<mesh filename="m.stl" '
                                                            'scale="1 -1 1"/>'))
    path = write_urdf(tmp_path, link("a", geo[0]) + "\n" + link("b", geo[1]))
    res = fix_file(path, _all())
    a, b = only(res, "a").assembly.total, only(res, "b").assembly.total
    assert b.mass == pytest.approx(a.mass)
    np.testing.assert_allclose(b.com, a.com * [1, -1, 1], atol=1e-12)
    mirror = np.diag([1.0, -1.0, 1.0])
    np.testing.assert_allclose(b.inertia, mirror @ a.inertia @ mirror, rtol=1e-9, atol=1e-15)
    assert "mirrored" in " ".join(f.message for f in only(res, "b").findings)


def test_multi_body_mesh_gives_one_part_per_body(tmp_path):
    a = trimesh.creation.box([0.1, 0.1, 0.1])
    b = trimesh.creation.icosphere(radius=0.05)
    b.apply_translation([0.5, 0, 0])
    trimesh.util.concatenate([a, b]).export(tmp_path / "two.stl")
    path = write_urdf(tmp_path, link("l", collision('<mesh filename="two.stl"/>')))
    parts = only(fix_file(path, _all()), "l").assembly.parts
    assert len(parts) == 2
    assert {round(p.part.volume, 6) for p in parts} == {round(a.volume, 6), round(b.volume, 6)}


def test_cli_writes_output_and_json_and_leaves_input(tmp_path, capsys):
    src = tmp_path / "in.urdf"
    src.write_bytes((DATA / "styled.urdf").read_bytes())
    before = src.read_bytes()
    out, js = tmp_path / "out.urdf", tmp_path / "r.json"
    assert main(["fix", "--all", str(src), "-o", str(out), "--json", str(js)]) == 0
    assert src.read_bytes() == before
    report = json.loads(js.read_text())
    arm = next(lk for lk in report["links"] if lk["link"] == "arm_link")
    assert arm["status"] == "recomputed" and arm["result"]["mass"] == 1.5
    assert len(arm["parts"]) == 2
    tool = next(lk for lk in report["links"] if lk["link"] == "tool0")
    assert tool["status"] == "untouched"
    assert b"<inertial>" in out.read_bytes()
    table = capsys.readouterr().out
    assert "arm_link" in table and "base_link" in table


def test_cli_in_place_keeps_backup(tmp_path):
    src = tmp_path / "robot.urdf"
    src.write_bytes((DATA / "styled.urdf").read_bytes())
    before = src.read_bytes()
    assert main(["fix", "--all", str(src), "--in-place", "-q"]) == 0
    assert (tmp_path / "robot.urdf.bak").read_bytes() == before
    assert src.read_bytes() != before


def test_cli_missing_mesh_leaves_the_link(tmp_path, capsys):
    path = write_urdf(tmp_path, link("hand", collision('<mesh filename="nope.stl"/>')))
    before = path.read_bytes()
    out = tmp_path / "out.urdf"
    assert main(["fix", "--all", str(path), "-o", str(out), "-q"]) == 1
    err = capsys.readouterr().err.strip()
    assert "left as it was" in err and "hand" in err and "nope.stl" in err
    assert path.read_bytes() == before and out.read_bytes() == before


def test_cli_missing_mesh_strict_is_one_line_error(tmp_path, capsys):
    path = write_urdf(tmp_path, link("hand", collision('<mesh filename="nope.stl"/>')))
    before = path.read_bytes()
    out = tmp_path / "out.urdf"
    assert main(["fix", "--all", str(path), "-o", str(out), "--strict"]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1
    assert str(path) in err and "hand" in err and "nope.stl" in err
    assert path.read_bytes() == before and not out.exists()
