"""Start tags of the offending elements: line and column, multi-line tags included."""

from __future__ import annotations

from pathlib import Path

from urdfinertia.analysis.locate import Location, locate_all
from urdfinertia.descriptions.formats import read_description as read_urdf_lenient
from urdfinertia.findings import Finding
from urdfinertia.rules import Rule

INERTIAL = ('<inertial><mass value="1"/><inertia ixx="1" ixy="0" ixz="0" iyy="1" iyz="0" '
            'izz="3"/></inertial>')
DOC = ('<?xml version="1.0"?>\n'
       '<!-- <link name="a"> in a comment comes first -->\n'
       '<robot name="r">\n'
       '  <link name="base"/>\n'
       '    <link\n'
       "       name='a'>\n"
       f'      {INERTIAL}\n'
       '  </link>\n'
       f'  <link name="b">{INERTIAL}</link>\n'
       '  <joint name="j" type="fixed"><parent link="base"/><child link="a"/></joint>\n'
       '  <joint name="k" type="fixed"><parent link="base"/><child link="b"/></joint>\n'
       '</robot>\n')


def locate(tmp_path: Path, findings: list[Finding], text: str = DOC) -> list[Location]:
    path = tmp_path / "r.urdf"
    path.write_text(text)
    robot, _ = read_urdf_lenient(path)
    return locate_all(robot, path.read_bytes(), findings)


def test_link_and_inertial_start_tags(tmp_path):
    found = locate(tmp_path, [
        Finding(Rule.MISSING_INERTIAL, "a", "m"),  # element: link
        Finding(Rule.TRIANGLE_INEQUALITY, "a", "m"),  # element: inertial
        Finding(Rule.TRIANGLE_INEQUALITY, "b", "m"),
        Finding(Rule.ENGINE_MISSING, None, "m"),  # element: robot
    ])
    # lxml would say line 6 for link a (where its start tag ends); the tag starts on line 5
    assert found[0] == Location(5, 5)
    assert found[1] == Location(7, 7)
    line9 = DOC.splitlines()[8]
    assert found[2] == Location(9, line9.index("<inertial") + 1)
    assert found[3] == Location(3, 1)


def test_column_counts_characters_not_bytes(tmp_path):
    text = DOC.replace('<link name="b">', '<!--é--><link name="b">')
    found = locate(tmp_path, [Finding(Rule.LUMPED_MASS, "b", "m")], text)
    line9 = text.splitlines()[8]
    assert found[0] == Location(9, line9.index("<link") + 1)


def test_unknown_link_points_at_the_root(tmp_path):
    assert locate(tmp_path, [Finding(Rule.ENGINE_REFUSED, "zz", "m")]) == [
        Location(3, 1)]
