"""MJCF writing: only inertial bytes change, the output compiles to the computed values with
explicit inertials only, ``fix`` is idempotent, included files are never written."""

from __future__ import annotations

import numpy as np
import pytest
from support.mjcf import body_inertia, compiled, strip_inertials

from urdfinertia.body.options import FixOptions
from urdfinertia.descriptions.formats import read_description
from urdfinertia.descriptions.mjcf.write import scan_bodies
from urdfinertia.errors import UrdfError
from urdfinertia.plan.fix import fix_file

mujoco = pytest.importorskip("mujoco")

STYLED = (
    '<?xml version="1.0" encoding="utf-8"?>\r\n'
    "<!-- a comment with <body name='not_a_body'> inside -->\r\n"
    "<mujoco model='styled'>\r\n"
    "\t<default><geom density='800'/></default>\r\n"
    "\t<worldbody>\r\n"
    "\t\t<geom type='plane' size='5 5 .1'/>\r\n"
    "\t\t<body name='kept' pos='0 0 1'>\r\n"
    "\t\t\t<freejoint/>\r\n"
    "\t\t\t<inertial pos='0 0 0' mass='3' diaginertia='1 1 1'/>\r\n"
    "\t\t\t<geom type='box' size='.1 .2 .3'   pos='0.05 0 0'/>\r\n"
    "\t\t\t<body>\r\n"
    "\t\t\t\t<joint axis='0 1 0'/>\r\n"
    "\t\t\t\t<geom type='capsule' fromto='0 0 0 0 0 -.4' size='.03'/>\r\n"
    "\t\t\t\t<![CDATA[ <body name='cdata'/> ]]>\r\n"
    "\t\t\t\t<body name=\"one_line\" pos=\"0 0 -.5\"><joint/><geom size=\".05\"/></body>\r\n"
    "\t\t\t</body>\r\n"
    "\t\t\t<body name='empty'/>\r\n"
    "\t\t</body>\r\n"
    "\t</worldbody>\r\n"
    "</mujoco>\r\n"
)


@pytest.fixture
def styled(tmp_path):
    path = tmp_path / "styled.xml"
    path.write_bytes(STYLED.encode())
    return path


def test_only_inertials_change_and_style_is_kept(styled):
    result = fix_file(styled, FixOptions(recompute="all"))
    assert result.changed
    assert strip_inertials(result.output) == strip_inertials(styled.read_bytes())
    spans = scan_bodies(result.output)
    assert set(spans) == {"kept", "body#2", "one_line", "empty"}
    # inserted inertials are indented with the file's tabs and CRLF, or stay on one line
    assert b"\t\t\t<body>\r\n\t\t\t\t<inertial pos=" in result.output
    assert b'pos="0 0 -.5"><inertial pos=' in result.output
    # the kept body keeps its mass byte for byte (and the default class density does not
    # clash with it); only the derived CoM and tensor change, in the element's own quotes
    assert b"\t\t\t<inertial pos='0.05 0 0' mass='3' diaginertia='0.13" in result.output


def test_fix_is_idempotent(styled, tmp_path):
    first = fix_file(styled, FixOptions(recompute="all"))
    again = tmp_path / "again.xml"
    again.write_bytes(first.output)
    assert fix_file(again, FixOptions(recompute="all")).output == first.output


def test_output_compiles_with_explicit_inertials_to_the_computed_values(styled, tmp_path):
    result = fix_file(styled, FixOptions(recompute="all", mass="density"))
    out = tmp_path / "out.xml"
    out.write_bytes(result.output.replace(b"<mujoco model='styled'>",
                                          b"<mujoco model='styled'><compiler "
                                          b"inertiafromgeom='false'/>"))
    model = compiled(out)
    for r in result.links:
        if r.assembly is None:
            continue
        mass, com, tensor = body_inertia(model, r.name)
        total = r.assembly.total
        assert mass == pytest.approx(total.mass, rel=1e-12)
        np.testing.assert_allclose(com, total.com, atol=1e-12)
        np.testing.assert_allclose(tensor, total.inertia, rtol=1e-9,
                                   atol=1e-12 * float(np.abs(tensor).max()))
    # and it is what MuJoCo itself derives from the geoms of the input
    derived = compiled(styled)
    for r in result.links:
        if r.assembly is not None and r.name != "kept":  # "kept" has an inertial
            np.testing.assert_allclose(body_inertia(derived, r.name)[0], r.assembly.total.mass,
                                       rtol=1e-9)


def test_bodies_of_included_files_are_left_and_said_so(tmp_path):
    (tmp_path / "arm.xml").write_text(
        '<mujoco><body name="arm"><joint/><geom type="box" size=".1 .1 .1"/></body></mujoco>')
    main = tmp_path / "main.xml"
    main.write_text('<mujoco><worldbody><body name="base"><geom size=".1"/>'
                    '<include file="arm.xml"/></body></worldbody></mujoco>')
    result = fix_file(main, FixOptions(recompute="all"))
    by_name = {r.name: r for r in result.links}
    # fix cannot write the included file: the link is left, not said to be recomputed
    arm = by_name["arm"]
    assert (arm.status, arm.assembly) == ("left", None)
    assert arm.reason == "defined in included file arm.xml, which is not written"
    assert [r.name for r in result.left] == ["arm"]
    assert by_name["base"].status == "recomputed"
    assert result.output.count(b"<inertial") == 1
    out = tmp_path / "out.xml"
    out.write_bytes(result.output)
    compiled(out)  # the output still compiles, its include resolved


def test_included_files_pass_the_same_security_checks(tmp_path):
    (tmp_path / "evil.xml").write_text(
        '<?xml version="1.0"?><!DOCTYPE m [<!ENTITY x "y">]><mujoco>&x;</mujoco>')
    main = tmp_path / "main.xml"
    main.write_text('<mujoco><include file="evil.xml"/></mujoco>')
    with pytest.raises(UrdfError, match="entity"):
        read_description(main)
    (tmp_path / "loop.xml").write_text('<mujoco><include file="loop.xml"/></mujoco>')
    with pytest.raises(UrdfError, match="includes itself"):
        read_description(tmp_path / "loop.xml")
    (tmp_path / "url.xml").write_text('<mujoco><include file="http://x/y.xml"/></mujoco>')
    with pytest.raises(UrdfError, match="only local files"):
        read_description(tmp_path / "url.xml")


def test_an_include_that_is_a_link_loop_or_a_fifo_is_refused_with_its_line(tmp_path):
    """Found by fuzzing: ``Path.resolve`` raised RuntimeError on a symbolic-link loop and
    ``Path.is_file`` OSError on a name too long (exit 3); a FIFO would have blocked."""
    import os

    os.symlink(tmp_path / "b.xml", tmp_path / "a.xml")
    os.symlink(tmp_path / "a.xml", tmp_path / "b.xml")
    os.mkfifo(tmp_path / "pipe.xml")
    for target, cause in (("a.xml", "included file not found"),
                          ("pipe.xml", "is not a regular file"),
                          ("x" * 5000 + ".xml", "included file not found")):  # ENAMETOOLONG
        main = tmp_path / f"main_{len(target)}_{target[:5]}.xml"
        main.write_text(f'<mujoco>\n<include file="{target}"/></mujoco>')
        with pytest.raises(UrdfError, match=cause) as found:
            read_description(main)
        assert found.value.line == 2


def test_lenient_reading_keeps_non_finite_inertials_for_check(tmp_path):
    path = tmp_path / "nan.xml"
    path.write_text('<mujoco><worldbody><body name="b"><joint/><geom size=".1"/>'
                    '<inertial pos="0 0 0" mass="nan" diaginertia="1 1 1"/></body>'
                    "</worldbody></mujoco>")
    robot, _ = read_description(path)
    assert np.isnan(robot.link("b").inertial.mass)  # one reading, as written
    assert robot.findings == ()


def test_a_body_that_cannot_be_computed_is_left_as_written(tmp_path, capsys):
    from urdfinertia.cli import main

    path = tmp_path / "partial.xml"
    path.write_text('<mujoco><asset><mesh name="gone" file="gone.stl"/></asset><worldbody>'
                    '<body name="ok"><joint/><geom type="box" size=".1 .1 .1"/></body>'
                    '<body name="bad"><joint/><geom type="mesh" mesh="gone"/>'
                    '<inertial pos="0 0 0" mass="1" diaginertia="1 1 1"/></body>'
                    "</worldbody></mujoco>")
    result = fix_file(path, FixOptions(recompute="all"))
    status = {r.name: r.status for r in result.links}
    assert status == {"ok": "recomputed", "bad": "left"}
    assert "gone.stl" in result.left[0].reason
    assert b'<inertial pos="0 0 0" mass="1" diaginertia="1 1 1"/>' in result.output
    out = tmp_path / "out.xml"
    assert main(["fix", "--all", str(path), "-o", str(out), "-q"]) == 1
    assert "link 'bad'" in capsys.readouterr().err
    assert out.read_bytes() == result.output
