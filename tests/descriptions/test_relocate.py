"""Outputs written to another folder find every file the input found.

Hand-made fixtures (tests/data/relocate): an MJCF model with ``meshdir``, ``texturedir``
and an ``<include>``, one whose assets are relative to the model's folder, and an SDFormat
model with relative and ``model://`` URIs. Each is relocated (or fixed with ``-o``) into
another folder and loaded from there: MuJoCo compiles the MJCF, and every relative SDF URI
resolves to the file it named before. Only the path texts change.
"""

from __future__ import annotations

import difflib
import shutil
from pathlib import Path

import pytest

from urdfinertia.descriptions.formats import relocate_references
from urdfinertia.descriptions.paths import resolve_mesh_path

DATA = Path(__file__).resolve().parents[1] / "data" / "relocate"
mujoco = pytest.importorskip("mujoco")


@pytest.fixture
def models(tmp_path: Path) -> Path:
    """A copy of the fixtures (the outputs go beside them, in other folders)."""
    shutil.copytree(DATA, tmp_path / "in")
    return tmp_path / "in"


def changed_lines(before: bytes, after: bytes) -> list[tuple[str, str]]:
    """(old line, new line) of every line that differs; the line count must not change."""
    a, b = before.decode().splitlines(), after.decode().splitlines()
    out = []
    for op in difflib.SequenceMatcher(a=a, b=b).get_opcodes():
        if op[0] != "equal":
            out.append(("\n".join(a[op[1]:op[2]]), "\n".join(b[op[3]:op[4]])))
    return out


def test_mjcf_meshdir_texturedir_and_include_are_rewritten(models, tmp_path):
    src = models / "mjcf" / "robot.xml"
    out = tmp_path / "out" / "deeper" / "robot.xml"
    out.parent.mkdir(parents=True)
    data = src.read_bytes()
    with pytest.raises(ValueError, match="Error opening file"):  # the input as it is
        out.write_bytes(data)
        mujoco.MjModel.from_xml_path(str(out))
    moved, n = relocate_references(data, src, out)
    assert n == 3
    assert changed_lines(data, moved) == [
        ('  <compiler angle="radian" meshdir="assets" texturedir=\'textures\'/>',
         '  <compiler angle="radian" meshdir="../../in/mjcf/assets" '
         'texturedir=\'../../in/mjcf/textures\'/>'),
        ('      <include file="parts/arm.xml"/>',
         '      <include file="../../in/mjcf/parts/arm.xml"/>'),
    ]
    out.write_bytes(moved)
    model = mujoco.MjModel.from_xml_path(str(out))
    assert (model.nbody, model.nmesh, model.ntex) == (3, 1, 1)


def test_mjcf_files_relative_to_the_model_get_a_folder(models, tmp_path):
    src = models / "mjcf" / "nodir.xml"
    out = tmp_path / "elsewhere" / "nodir.xml"
    out.parent.mkdir()
    data = src.read_bytes()
    moved, n = relocate_references(data, src, out)
    assert n == 1  # both kinds of asset: one assetdir
    assert changed_lines(data, moved) == [("", '  <compiler assetdir="../in/mjcf"/>')]
    out.write_bytes(moved)
    assert mujoco.MjModel.from_xml_path(str(out)).nmesh == 1


def test_mjcf_folder_set_in_an_included_file_is_overridden_last(models, tmp_path):
    mj = models / "mjcf"
    (mj / "parts" / "settings.xml").write_text(
        '<mujoco><compiler meshdir="assets"/></mujoco>\n')
    src = mj / "inc_compiler.xml"
    src.write_text('<mujoco>\n  <include file="parts/settings.xml"/>\n'
                   '  <asset><mesh name="box" file="box.stl"/></asset>\n'
                   '  <worldbody><body><geom type="mesh" mesh="box"/></body></worldbody>\n'
                   '</mujoco>\n')
    mujoco.MjModel.from_xml_path(str(src))
    out = tmp_path / "o" / "m.xml"
    out.parent.mkdir()
    moved, n = relocate_references(src.read_bytes(), src, out)
    assert n == 2  # the include, and the mesh folder it sets
    assert b'<compiler meshdir="../in/mjcf/assets"/></mujoco>' in moved
    out.write_bytes(moved)
    assert mujoco.MjModel.from_xml_path(str(out)).nmesh == 1


def test_mjcf_absolute_folder_and_same_folder_are_left(models, tmp_path):
    src = models / "mjcf" / "abs.xml"
    text = (models / "mjcf" / "robot.xml").read_text().replace(
        'meshdir="assets"', f'meshdir="{(models / "mjcf" / "assets").as_posix()}"')
    src.write_text(text)
    moved, n = relocate_references(src.read_bytes(), src, tmp_path / "x" / "abs.xml")
    assert n == 2  # texturedir and the include; the absolute meshdir stays
    assert f'meshdir="{(models / "mjcf" / "assets").as_posix()}"'.encode() in moved
    assert relocate_references(src.read_bytes(), src, src.with_name("other.xml")) == (
        src.read_bytes(), 0)


def test_mjcf_fixed_with_output_elsewhere_compiles(models, tmp_path, capsys):
    from urdfinertia.cli import main

    src = models / "mjcf" / "robot.xml"
    out = tmp_path / "fixed" / "robot.xml"
    out.parent.mkdir()
    # exit 1: the arm's body lives in the included file, which fix does not write
    assert main(["fix", str(src), "-o", str(out), "-q", "--all"]) == 1
    assert "defined in included file" in capsys.readouterr().err
    model = mujoco.MjModel.from_xml_path(str(out))
    assert model.nbody == 3
    assert b'meshdir="../in/mjcf/assets"' in out.read_bytes()


def test_sdf_relative_uris_resolve_from_the_output(models, tmp_path):
    src = models / "sdf" / "model.sdf"
    out = tmp_path / "sdf_out" / "nested" / "model.sdf"
    out.parent.mkdir(parents=True)
    data = src.read_bytes()
    moved, n = relocate_references(data, src, out)
    assert n == 2
    assert changed_lines(data, moved) == [
        ("        <geometry><mesh><uri>meshes/box.stl</uri></mesh></geometry>",
         "        <geometry><mesh><uri>../../in/sdf/meshes/box.stl</uri></mesh></geometry>"),
        ("        <geometry><mesh><uri> meshes/box.stl </uri></mesh></geometry>",
         "        <geometry><mesh><uri> ../../in/sdf/meshes/box.stl </uri></mesh>"
         "</geometry>"),
    ]
    out.write_bytes(moved)
    from urdfinertia.descriptions.formats import read_description

    robot, _ = read_description(out)
    meshes = [g.shape for link in robot.links for g in (*link.collisions, *link.visuals)
              if hasattr(g.shape, "filename")]
    relative = [m.filename for m in meshes if not m.filename.startswith("model://")]
    assert len(relative) == 2
    for uri in relative:
        assert resolve_mesh_path(uri, out.parent).samefile(src.parent / "meshes" / "box.stl")
