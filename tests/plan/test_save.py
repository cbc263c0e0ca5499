"""``FixResult.save``: the command line's bytes, relocated references, atomic, backups."""

from __future__ import annotations

import shutil
from pathlib import Path

import pytest

from urdfinertia.body.options import FixOptions
from urdfinertia.cli import main
from urdfinertia.errors import OutputError
from urdfinertia.plan.fix import fix_file

DATA = Path(__file__).resolve().parents[1] / "data" / "relocate"

URDF = """<?xml version="1.0"?>
<robot name="r">
  <link name="base">
    <inertial><origin xyz="0 0 0" rpy="0 0 0"/><mass value="1"/>
      <inertia ixx="-1" ixy="0" ixz="0" iyy="1" iyz="0" izz="1"/></inertial>
    <collision><geometry><mesh filename="../sdf/meshes/box.stl"/></geometry></collision>
  </link>
</robot>
"""


@pytest.fixture
def inputs(tmp_path: Path) -> Path:
    shutil.copytree(DATA, tmp_path / "in")
    (tmp_path / "in" / "urdf").mkdir()
    (tmp_path / "in" / "urdf" / "r.urdf").write_text(URDF)
    return tmp_path / "in"


@pytest.mark.parametrize("name", ["urdf/r.urdf", "mjcf/robot.xml", "sdf/model.sdf"])
def test_save_writes_the_cli_bytes(inputs, tmp_path, name):
    src = inputs / name
    (tmp_path / "cli").mkdir()
    (tmp_path / "api").mkdir()
    main(["fix", str(src), "--all", "-q", "-o", str(tmp_path / "cli" / src.name)])
    report = fix_file(src, FixOptions(recompute="all")).save(tmp_path / "api" / src.name)
    written = (tmp_path / "api" / src.name).read_bytes()
    assert written == (tmp_path / "cli" / src.name).read_bytes()
    assert report.written and report.path == tmp_path / "api" / src.name
    assert report.references_rewritten >= 1
    assert b"../in/" in written  # the references name the inputs' files


def test_save_keep_mesh_paths_writes_the_document_as_fixed(inputs, tmp_path):
    result = fix_file(inputs / "urdf" / "r.urdf", FixOptions(recompute="all"))
    report = result.save(tmp_path / "r.urdf", keep_mesh_paths=True)
    assert report.references_rewritten == 0
    assert (tmp_path / "r.urdf").read_bytes() == result.output


def test_save_in_place_keeps_a_backup(inputs):
    src = inputs / "urdf" / "r.urdf"
    result = fix_file(src, FixOptions())
    assert result.changed  # the invalid tensor
    report = result.save(in_place=True)
    assert report.written and report.backup == src.with_name("r.urdf.bak")
    assert src.read_bytes() == result.output  # in its own folder: nothing relocated
    assert report.backup.read_text() == URDF


def test_save_in_place_without_backup_and_unchanged(inputs):
    src = inputs / "urdf" / "r.urdf"
    fix_file(src, FixOptions()).save(in_place=True, backup=False)
    assert not src.with_name("r.urdf.bak").exists()
    again = fix_file(src, FixOptions())  # nothing left to change
    before = src.stat().st_mtime_ns
    report = again.save(in_place=True)
    assert not report.written and src.stat().st_mtime_ns == before


def test_save_refuses_the_input_and_a_missing_path(inputs, tmp_path):
    src = inputs / "urdf" / "r.urdf"
    result = fix_file(src, FixOptions())
    with pytest.raises(OutputError, match="output is the input file"):
        result.save(src)
    with pytest.raises(OutputError, match="pass a path or in_place"):
        result.save()
    with pytest.raises(OutputError, match="pass no other path"):
        result.save(tmp_path / "x.urdf", in_place=True)
    assert src.read_text() == URDF
    assert not (tmp_path / "x.urdf").exists()


def test_save_into_a_missing_folder_writes_nothing(inputs, tmp_path):
    result = fix_file(inputs / "urdf" / "r.urdf", FixOptions())
    with pytest.raises(OutputError, match="cannot write"):
        result.save(tmp_path / "no" / "such" / "r.urdf")
    assert not (tmp_path / "no").exists()


def test_save_of_a_xacro_relocates_the_expansion_mesh_references(inputs, tmp_path):
    src = inputs / "urdf" / "r.urdf.xacro"
    src.write_text(URDF.replace('<robot name="r">',
                                '<robot name="r" xmlns:xacro="http://www.ros.org/wiki/xacro">'
                                '<xacro:property name="m" value="1"/>'))
    result = fix_file(src, FixOptions(recompute="all"))
    report = result.save(tmp_path / "r.urdf")
    assert report.references_rewritten == 1
    assert b'filename="in/sdf/meshes/box.stl"' in (tmp_path / "r.urdf").read_bytes()
    with pytest.raises(OutputError, match="not replaced by its expansion"):
        result.save(in_place=True)
