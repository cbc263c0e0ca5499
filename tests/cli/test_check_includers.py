"""``check --includers``: a changed xacro include is checked through the robots including it.

The repositories are copies of the xacro test packages: ``nested`` (rover.urdf.xacro
includes parts/body.xacro, which includes parts/sensors/head.xacro) and ``ur_description``
(ur.urdf.xacro includes ``$(find ur_description)/urdf/ur_macro.xacro``, which includes
inc/inertials.xacro).
"""

from __future__ import annotations

import shutil
from pathlib import Path

import pytest

from urdfinertia.cli import main
from urdfinertia.descriptions.xacro.includers import checked_through, includers

DATA = Path(__file__).resolve().parents[1] / "data" / "xacro"


@pytest.fixture
def repo(tmp_path, monkeypatch):
    monkeypatch.delenv("ROS_PACKAGE_PATH", raising=False)
    monkeypatch.delenv("AMENT_PREFIX_PATH", raising=False)
    shutil.copytree(DATA / "nested", tmp_path / "nested")
    shutil.copytree(DATA / "ur_description", tmp_path / "src" / "ur_description")
    # a second robot built on the same body, and a macro file no robot includes
    (tmp_path / "nested" / "twin.urdf.xacro").write_text(
        '<?xml version="1.0"?>\n<robot xmlns:xacro="http://www.ros.org/wiki/xacro" '
        'name="twin">\n  <xacro:include filename="parts/body.xacro"/>\n  <xacro:body/>\n'
        '</robot>\n')
    (tmp_path / "nested" / "unused.xacro").write_text(
        '<robot xmlns:xacro="http://www.ros.org/wiki/xacro"><xacro:macro name="u">'
        '<link name="u"/></xacro:macro></robot>')
    monkeypatch.chdir(tmp_path)
    return tmp_path


def test_an_include_is_replaced_by_its_top_level_robots(repo):
    head = Path("nested/parts/sensors/head.xacro")
    # through body.xacro, which is itself an include (no robot): both tops, not body
    assert includers(head, repo) == [repo / "nested" / "rover.urdf.xacro",
                                     repo / "nested" / "twin.urdf.xacro"]
    paths, done = checked_through([head, Path("nested/rover.urdf.xacro")], repo)
    # given as relative paths, named relative; rover given too: listed once
    assert paths == [Path("nested/rover.urdf.xacro"), Path("nested/twin.urdf.xacro")]
    assert [r.include for r in done] == [head]


def test_find_and_nested_includes_of_a_package(repo):
    inertials = Path("src/ur_description/urdf/inc/inertials.xacro")
    assert includers(inertials, repo) == [repo / "src/ur_description/urdf/ur.urdf.xacro"]


def test_robots_and_lone_macro_files_stay_themselves(repo):
    given = [Path("nested/rover.urdf.xacro"), Path("nested/unused.xacro")]
    assert checked_through(given, repo) == (given, [])


def test_cli_checks_the_robot_not_the_empty_include(repo, capsys):
    code = main(["check", "--includers", "-q", "nested/parts/sensors/head.xacro"])
    out = capsys.readouterr()
    assert code == 0, out.err
    assert out.err.splitlines() == [
        "nested/parts/sensors/head.xacro: no links of its own: checked through "
        "nested/rover.urdf.xacro, nested/twin.urdf.xacro"]
    lines = out.out.splitlines()
    assert [line.split(":")[0] for line in lines] == ["nested/rover.urdf.xacro",
                                                      "nested/twin.urdf.xacro"]
    assert all(" 0 links" not in line for line in lines)
    # without the flag: the include alone, which has no links
    assert main(["check", "-q", "nested/parts/sensors/head.xacro"]) == 0
    assert "head.xacro: 0 links" in capsys.readouterr().out
