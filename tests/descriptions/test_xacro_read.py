"""descriptions/xacro: reading xacro in-process, its errors, and the refusals on every file
xacro reads."""

from __future__ import annotations

import dataclasses
import shutil
from pathlib import Path

import pytest
from support.xacro_files import HEAD, clean_xacro_settings, write  # noqa: F401 - the fixture

from urdfinertia.cli import main
from urdfinertia.descriptions.formats import detect_format, read_description
from urdfinertia.descriptions.xacro.expand import configure, expand_xacro
from urdfinertia.errors import UrdfError

DATA = Path(__file__).parents[1] / "data" / "xacro"








def test_links_are_named_after_expansion_and_match_the_xacro_command():
    path = DATA / "franka_description/robots/fr3/fr3.urdf.xacro"
    configure({"arm_id": "panda"})
    robot, document = read_description(path)
    assert robot.format == "xacro"
    assert [link.name for link in robot.links] == ["panda_link0", "panda_link1"]
    link1 = robot.link("panda_link1").inertial
    assert link1.mass == pytest.approx(2.9273)
    assert link1.origin.xyz == pytest.approx((4.128e-06, -0.0181, -0.0386))
    assert link1.ixz == pytest.approx(1e-05)  # a YAML string "1e-05" passed through as text
    assert b"urdfinertia-src" not in document


def test_same_values_as_the_xacro_package_unhooked():
    """xacro's own entry point (no hooks; the fixture needs no $(find)) gives the same
    robot: the hooks change where files come from, never what the expansion means."""
    import xacro

    from urdfinertia.descriptions.urdf.read import robot_from_bytes

    path = DATA / "limbs/humanoid.urdf.xacro"
    reference = robot_from_bytes(xacro.process(str(path)).encode(), path)
    robot, _ = read_description(path)
    assert [link.name for link in robot.links] == [link.name for link in reference.links]
    def unlined(items):  # the two expansions lay out lines differently
        return [dataclasses.replace(x, line=None) for x in items if x is not None]

    for mine, theirs in zip(robot.links, reference.links, strict=True):
        assert unlined([mine.inertial]) == unlined([theirs.inertial])
        assert unlined(mine.collisions) == unlined(theirs.collisions)
    assert unlined(robot.joints) == unlined(reference.joints)


def test_find_uses_package_dir_over_the_walk_up(tmp_path):
    other = tmp_path / "elsewhere"
    shutil.copytree(DATA / "ur_description", other)
    (other / "config/physical_parameters.yaml").write_text(
        (other / "config/physical_parameters.yaml").read_text().replace("4.0 ", "5.5 "))
    path = DATA / "ur_description/urdf/ur.urdf.xacro"
    assert read_description(path)[0].link("base_link").inertial.mass == 4.0
    configure(package_dirs={"ur_description": other})
    assert read_description(path)[0].link("base_link").inertial.mass == 5.5


def test_xacro_arg_on_the_command_line(tmp_path, capsys):
    path = DATA / "ur_description/urdf/ur.urdf.xacro"
    assert main(["check", str(path), "--xacro-arg", "prefix:=left_", "-q"]) in (0, 1)
    out = capsys.readouterr().out
    assert "4 links" in out
    robot, _ = read_description(path)
    assert robot.links[0].name == "left_base_link"


@pytest.mark.parametrize(("body", "line", "cause"), [
    ('  <link name="a"><inertial><mass value="${nope}"/></inertial></link>\n', 3,
     "name 'nope' is not defined"),
    ('  <xacro:include filename="missing.xacro"/>\n', 3, "No such file"),
    ('  <xacro:property name="m" value="${1/0}"/>\n  <link name="${m}"/>\n', 4,
     "division by zero"),
    ('  <link name="$(find no_such_package_here)"/>\n', 3, "package not found"),
])
def test_a_xacro_error_is_one_line_naming_file_and_line(tmp_path, capsys, body, line, cause):
    path = write(tmp_path, "r.urdf.xacro", HEAD + body + "</robot>\n")
    with pytest.raises(UrdfError, match=cause) as exc:
        read_description(path)
    assert exc.value.file == str(path) and exc.value.line == line
    assert main(["check", str(path)]) == 2
    err = capsys.readouterr().err.strip()
    assert err.count("\n") == 0 and f"r.urdf.xacro:{line}:" in err and cause in err


def test_an_error_inside_a_macro_of_an_included_file_names_that_file(tmp_path):
    write(tmp_path, "lib/m.xacro", HEAD + '  <xacro:macro name="m" params="x">\n'
          '    <link name="${x * y}"/>\n  </xacro:macro>\n</robot>\n')
    path = write(tmp_path, "r.urdf.xacro", HEAD + '  <xacro:include filename="lib/m.xacro"/>\n'
                 '  <xacro:m x="2"/>\n</robot>\n')
    with pytest.raises(UrdfError, match="'y' is not defined") as exc:
        read_description(path)
    assert exc.value.file == str(tmp_path / "lib/m.xacro") and exc.value.line == 4


@pytest.mark.parametrize(("included", "cause"), [
    ('<?xml version="1.0"?>\n<!DOCTYPE r [<!ENTITY x "boom">]>\n<robot/>\n',
     "entity declarations are not allowed"),
    ('<?xml version="1.0"?>\n<!DOCTYPE r SYSTEM "http://example.com/r.dtd">\n<robot/>\n',
     "external DTD"),
])
def test_hostile_included_files_are_refused_before_parsing(tmp_path, included, cause):
    write(tmp_path, "evil.xacro", included)
    path = write(tmp_path, "r.urdf.xacro", HEAD + '  <xacro:include filename="evil.xacro"/>\n'
                 "</robot>\n")
    with pytest.raises(UrdfError, match=cause) as exc:
        read_description(path)
    assert exc.value.file.endswith("evil.xacro")


@pytest.mark.parametrize("body", [
    '  <xacro:include filename="http://example.com/evil.xacro"/>\n',
    '  <xacro:property name="p" value="${xacro.load_yaml(\'https://example.com/p.yaml\')}"/>\n'
    '  <link name="${p}"/>\n',
])
def test_urls_are_never_read(tmp_path, body):
    path = write(tmp_path, "r.urdf.xacro", HEAD + body + "</robot>\n")
    with pytest.raises(UrdfError, match="only local files, not URLs") as exc:
        read_description(path)
    # a property is evaluated where it is used (xacro's lazy evaluation): line 3 or 4
    assert exc.value.file == str(path) and exc.value.line in (3, 4)
    assert "<input>" not in str(exc.value)


def test_a_hostile_main_file_is_refused(tmp_path):
    path = write(tmp_path, "r.urdf.xacro",
                 '<?xml version="1.0"?>\n<!DOCTYPE robot [<!ENTITY a "b">]>\n' + HEAD[22:]
                 + "</robot>\n")
    with pytest.raises(UrdfError, match="entity declarations"):
        read_description(path)


def test_include_recursion_is_an_error_not_a_crash(tmp_path):
    path = write(tmp_path, "r.urdf.xacro", HEAD + '  <xacro:include filename="r.urdf.xacro"/>\n'
                 "</robot>\n")
    with pytest.raises(UrdfError, match="recursion|evaluates more than"):
        read_description(path)


def test_a_urdf_that_only_declares_the_namespace_stays_a_urdf(tmp_path):
    text = HEAD + '  <link name="a"/>\n</robot>\n'
    assert detect_format(text.encode(), tmp_path / "r.urdf").name == "urdf"
    assert detect_format(text.encode(), tmp_path / "r.xacro").name == "xacro"
    used = HEAD + '  <xacro:property name="n" value="a"/>\n  <link name="${n}"/>\n</robot>\n'
    assert detect_format(used.encode(), tmp_path / "r.urdf").name == "xacro"


def test_urdf_reader_errors_point_at_the_xacro_source(tmp_path):
    # a duplicate link name is one of the few things the URDF reader still refuses
    path = write(tmp_path, "r.urdf.xacro", HEAD + '  <xacro:property name="n" value="a"/>\n'
                 '  <link name="${n}"/>\n  <link name="b"/>\n  <link name="${n}"/>\n'
                 "</robot>\n")
    with pytest.raises(UrdfError, match="duplicate") as exc:
        read_description(path)
    assert exc.value.file == str(path) and exc.value.line == 6


def test_expansion_overrides_do_not_touch_the_disk(tmp_path):
    root = tmp_path / "ur_description"
    shutil.copytree(DATA / "ur_description", root)
    yaml_path = root / "config/physical_parameters.yaml"
    before = yaml_path.read_bytes()
    exp = expand_xacro(root / "urdf/ur.urdf.xacro",
                       overrides={yaml_path: before.replace(b"4.0 ", b"6.25 ")})
    assert b'<mass value="6.25"/>' in exp.document
    assert yaml_path.read_bytes() == before
    assert yaml_path.resolve() in exp.sources


@pytest.mark.parametrize("command", [["compare"], ["explain", "--link", "left_leg"]])
def test_other_commands_read_xacro(command, capsys):
    path = DATA / "limbs/humanoid.urdf.xacro"
    code = main([command[0], str(path), *command[1:]])
    assert code in (0, 1)
    assert "left_leg" in capsys.readouterr().out


def test_package_uri_includes_resolve_through_the_package_lookup(tmp_path):
    write(tmp_path, "pkg/package.xml", "<package><name>my_robot</name></package>")
    write(tmp_path, "pkg/urdf/part.xacro", HEAD + '  <link name="from_package"/>\n</robot>\n')
    path = write(tmp_path, "pkg/robots/r.urdf.xacro",
                 HEAD + '  <xacro:include filename="package://my_robot/urdf/part.xacro"/>\n'
                 "</robot>\n")
    robot, _ = read_description(path)
    assert [link.name for link in robot.links] == ["from_package"]


def test_xacro_code_in_comments_of_a_generated_urdf_keeps_it_a_urdf(tmp_path):
    text = (HEAD + '  <!-- <limit soft_lower_limit="${-15.0 * deg}"/> -->\n'
            '  <link name="a"/>\n</robot>\n')
    assert detect_format(text.encode(), tmp_path / "talos.urdf").name == "urdf"
