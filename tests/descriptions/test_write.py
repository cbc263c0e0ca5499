"""urdf_write.py: only <inertial> bytes change, numbers round-trip, fix is idempotent."""

from pathlib import Path

import numpy as np
import pytest
from support.diffs import assert_only_inertials_differ

from urdfinertia.body.options import FixOptions
from urdfinertia.descriptions.urdf.read import robot_from_bytes
from urdfinertia.descriptions.urdf.write import format_float, patch_inertials, scan_links
from urdfinertia.inertia import primitives
from urdfinertia.plan.fix import fix_file

DATA = Path(__file__).resolve().parents[1] / "data"


def test_styled_file_changes_only_inertials(tmp_path):
    src = DATA / "styled.urdf"
    result = fix_file(src, FixOptions(recompute="all"))
    assert result.changed
    assert_only_inertials_differ(src.read_bytes(), result.output)
    # the inserted inertial uses the file's tab indentation
    assert b"\n\t\t<inertial>\n\t\t\t<origin" in result.output
    # the link inside CDATA is not a link
    assert "not_a_link" not in scan_links(result.output)


def test_output_reparses_with_the_written_values():
    result = fix_file(DATA / "styled.urdf", FixOptions(recompute="all"))
    robot = robot_from_bytes(result.output, "out.urdf")
    for r in result.links:
        if r.assembly is None:
            continue
        written = robot.link(r.name).inertial
        assert written is not None
        assert written.mass == r.assembly.total.mass
        np.testing.assert_allclose(written.tensor(), r.assembly.total.inertia,
                                   rtol=1e-15, atol=1e-12 * r.assembly.total.inertia.max())


def test_fix_is_idempotent(tmp_path):
    first = fix_file(DATA / "styled.urdf", FixOptions(recompute="all"))
    out = tmp_path / "once.urdf"
    out.write_bytes(first.output)
    second = fix_file(out, FixOptions(recompute="all"))
    assert second.output == first.output


def test_crlf_files_keep_crlf(tmp_path):
    text = (DATA / "styled.urdf").read_bytes().replace(b"\n", b"\r\n")
    path = tmp_path / "crlf.urdf"
    path.write_bytes(text)
    out = fix_file(path, FixOptions(recompute="all")).output
    assert out.count(b"\n") == out.count(b"\r\n")


@pytest.mark.parametrize("value", [1e-7, 1.2345678901234567e-9, 0.1, 123456.789, 2.0, -3.5e-12])
def test_format_float_round_trips(value):
    text = format_float(value)
    assert float(text) == value
    assert not text.endswith(".0")


def test_negative_zero_is_written_as_zero():
    assert format_float(-0.0) == "0"


def test_tiny_tensor_keeps_precision():
    body = primitives.box([0.002, 0.003, 0.001], 1000.0)  # 6e-9 kg, ~1e-14 kg m^2
    doc = b'<robot name="r">\n  <link name="l">\n    <origin/>\n  </link>\n</robot>\n'
    out = patch_inertials(doc, {"l": (body, 0.004)})
    robot = robot_from_bytes(out, "x.urdf")
    np.testing.assert_array_equal(robot.link("l").inertial.tensor(), body.inertia)


def test_real_robot_round_trip(erd_dir):
    src = erd_dir / "robots" / "ur_description" / "urdf" / "ur5_robot.urdf"
    result = fix_file(src, FixOptions(recompute="all"))
    assert result.changed
    assert_only_inertials_differ(src.read_bytes(), result.output)


def test_self_closing_link_is_expanded():
    body = primitives.sphere(0.1, 1000.0)
    doc = b'<robot name="r">\n  <link name="l" />\n  <link name="m"/>\n</robot>\n'
    out = patch_inertials(doc, {"l": (body, 0.1)})
    assert out.startswith(b'<robot name="r">\n  <link name="l" >\n    <inertial>\n      <origin')
    assert out.endswith(b'    </inertial>\n  </link>\n  <link name="m"/>\n</robot>\n')
    assert robot_from_bytes(out, "x.urdf").link("l").inertial.mass == body.mass


def test_character_references_in_link_names():
    body = primitives.sphere(0.1, 1000.0)
    doc = b'<robot name="r">\n  <link name="&#65;b&#x43;&amp;"/>\n</robot>\n'
    name = robot_from_bytes(doc, "x.urdf").links[0].name
    assert name == "AbC&"
    out = patch_inertials(doc, {name: (body, 0.1)})
    assert robot_from_bytes(out, "x.urdf").link(name).inertial.mass == body.mass


def test_references_decode_in_one_pass_like_lxml():
    body = primitives.sphere(0.1, 1000.0)
    doc = b'<robot name="r">\n  <link name="a&#38;lt;b&amp;gt;"/>\n</robot>\n'
    name = robot_from_bytes(doc, "x.urdf").links[0].name
    assert name == "a&lt;b&gt;"  # what lxml reports
    out = patch_inertials(doc, {name: (body, 0.1)})
    assert robot_from_bytes(out, "x.urdf").link(name).inertial.mass == body.mass
