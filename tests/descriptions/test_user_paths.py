"""Paths a user types resolve from the working directory, whatever file asks for them.

A real xacro package from the dev extra: example-robot-data's hector quadrotor, whose
macro file names its meshes ``package://example-robot-data/...``. A robot of the user's
includes it through ``$(find example-robot-data)`` (or a ``package://`` include) from a
folder elsewhere, and the package's folder is given *relative* to the working directory,
which is neither the robot's folder nor the package's. xacro joins a relative name to the
including file's folder, so the relative folder must be made absolute before it.
"""

from __future__ import annotations

import json
import os
from pathlib import Path

import pytest

import urdfinertia
from urdfinertia.cli import main
from urdfinertia.errors import MeshError, UrdfError

INCLUDE = "robots/hector_description/robots/quadrotor_base.urdf.xacro"


@pytest.fixture
def project(tmp_path, erd_dir, monkeypatch):
    """tmp/work (the working directory) and tmp/robot/urdf/hector.urdf.xacro; returns the
    robot and the package folder as typed: relative to the working directory."""
    monkeypatch.delenv("ROS_PACKAGE_PATH", raising=False)
    monkeypatch.delenv("AMENT_PREFIX_PATH", raising=False)
    robot = tmp_path / "robot" / "urdf" / "hector.urdf.xacro"
    robot.parent.mkdir(parents=True)
    robot.write_text(f"""<?xml version="1.0"?>
<robot name="hector" xmlns:xacro="http://www.ros.org/wiki/xacro">
  <xacro:arg name="via" default="find"/>
  <xacro:if value="${{'$(arg via)' == 'find'}}">
    <xacro:include filename="$(find example-robot-data)/{INCLUDE}"/>
  </xacro:if>
  <xacro:unless value="${{'$(arg via)' == 'find'}}">
    <xacro:include filename="package://example-robot-data/{INCLUDE}"/>
  </xacro:unless>
  <xacro:quadrotor_base_macro/>
</robot>
""")
    work = tmp_path / "work"
    work.mkdir()
    monkeypatch.chdir(work)
    typed = os.path.relpath(erd_dir, work)
    assert not Path(typed).is_absolute() and (work / typed / INCLUDE).is_file()
    return robot, typed


@pytest.mark.parametrize("via", ["find", "package"])
def test_relative_package_dir_is_the_working_directorys(project, capsys, via):
    robot, typed = project
    code = main(["check", str(robot), "--package-dir", f"example-robot-data={typed}",
                 "--xacro-arg", f"via:={via}", "-q"])
    out = capsys.readouterr()
    assert code == 0, out.err
    # the include was found and so were its package:// meshes (no unresolved mesh)
    assert f"{robot}: 1 links, 0 error(s)" in out.out
    assert "not verified" not in out.out + out.err


def test_relative_package_dirs_in_python(project):
    robot, typed = project
    found = urdfinertia.check(robot, package_dirs={"example-robot-data": typed})
    assert [r.name for r in found.links] == ["base_link"]
    assert not found.unverified  # its meshes resolved
    result = urdfinertia.fix(robot, package_dirs={"example-robot-data": typed}, recompute="all")
    assert result.changed_links == ("base_link",)


def test_every_typed_path_is_the_working_directorys(project, capsys):
    """-o, --json, --sarif, --write-baseline, --baseline and --spec, all relative, from a
    working directory that is neither the robot's folder nor the package's."""
    robot, typed = project
    Path("out").mkdir()
    Path("hector.inertia.toml").write_text(
        '[links.base_link]\nmass = 1.477\n[links.base_link.elements.e.parts.body]\n'
        'box = { size = [0.4, 0.4, 0.1] }\n')
    common = ["--package-dir", f"example-robot-data={typed}"]
    assert main(["check", str(robot), *common, "-q", "--json", "out/c.json", "--sarif",
                 "out/c.sarif", "--write-baseline", "out/base.json"]) == 0
    assert main(["check", str(robot), *common, "-q", "--strict",
                 "--baseline", "out/base.json"]) == 0
    assert main(["fix", str(robot), *common, "--spec", "hector.inertia.toml",
                 "-o", "out/hector.urdf"]) == 0
    capsys.readouterr()
    assert json.loads(Path("out/c.json").read_text())["files"][0]["links"] == 1
    assert json.loads(Path("out/c.sarif").read_text())["version"] == "2.1.0"
    assert Path("out/base.json").is_file()
    fixed = Path("out/hector.urdf").read_text()
    assert 'mass value="1.477"' in fixed and "quadrotor_base" in fixed
    # the written robot is whole: its package:// meshes resolve through the same folder
    assert main(["check", "out/hector.urdf", *common, "-q", "--strict"]) == 0


def test_unknown_package_says_both_forms(project, monkeypatch):
    robot, _ = project
    with pytest.raises(UrdfError) as caught:
        urdfinertia.check(robot)
    message = str(caught.value)
    assert "$(find example-robot-data): package not found" in message
    assert "--package-dir example-robot-data=PATH" in message
    assert "package_dirs={'example-robot-data': PATH}" in message


def test_unresolved_mesh_says_both_forms(tmp_path):
    from urdfinertia.descriptions.paths import resolve_mesh_path

    with pytest.raises(MeshError) as caught:
        resolve_mesh_path("package://nowhere_pkg/m.stl", tmp_path)
    assert ("pass --package-dir nowhere_pkg=PATH (Python: package_dirs={'nowhere_pkg': "
            "PATH}) or set ROS_PACKAGE_PATH") in str(caught.value)
