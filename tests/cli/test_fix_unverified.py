"""fix on a robot whose kept link's mesh cannot be read: a line on stderr even with -q,
and exit 1 as check's (the link was not verified). Found by review: exit 0, and with -q
the cause was only in --json."""

from __future__ import annotations

import json

import pytest

from urdfinertia.cli import main

ROBOT = """<?xml version="1.0"?>
<robot name="r">
  <link name="base">
    <inertial><mass value="2"/>
      <inertia ixx="0.1" ixy="0" ixz="0" iyy="0.1" iyz="0" izz="0.1"/></inertial>
    <collision><geometry><mesh filename="part.stl"/></geometry></collision>
  </link>
</robot>
"""


@pytest.mark.parametrize("mesh", ["missing", "folder", "garbage"])
def test_an_unreadable_mesh_of_a_kept_link_is_said_and_exits_1(tmp_path, capsys, mesh):
    path = tmp_path / "r.urdf"
    path.write_text(ROBOT)
    if mesh == "folder":
        (tmp_path / "part.stl").mkdir()
    elif mesh == "garbage":
        (tmp_path / "part.stl").write_bytes(bytes(range(256)) * 2)
    out, report = tmp_path / "out.urdf", tmp_path / "r.json"
    assert main(["fix", str(path), "-q", "-o", str(out), "--json", str(report),
                 "--no-cache"]) == 1
    err = capsys.readouterr().err
    assert "not verified: 1 mesh unresolved or unreadable in 1 link" in err
    assert json.loads(report.read_text())["exit_code"] == 1
    assert out.read_bytes() == path.read_bytes()  # the link kept, byte for byte
    assert main(["check", str(path), "--no-cache"]) == 1  # the same answer as check


def test_a_readable_robot_still_exits_0(tmp_path, capsys):
    from pathlib import Path

    cube = Path(__file__).parents[1] / "data" / "broken" / "cube.stl"
    path = tmp_path / "r.urdf"
    path.write_text(ROBOT)
    (tmp_path / "part.stl").write_bytes(cube.read_bytes())
    assert main(["fix", str(path), "-q", "-o", str(tmp_path / "out.urdf"), "--no-cache"]) == 0
    assert "not verified" not in capsys.readouterr().err
