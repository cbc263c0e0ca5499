"""urdf_read.py and xml_safety.py: what the reader accepts and refuses."""

from __future__ import annotations

import io
import re

import pytest
from lxml import etree

from urdfinertia.descriptions.model import Box, Capsule, Mesh
from urdfinertia.descriptions.urdf.read import MAX_MAGNITUDE, parse_xml, read_urdf, robot_from_bytes
from urdfinertia.descriptions.xml import safe_parser
from urdfinertia.errors import UrdfError
from urdfinertia.hostile import hostile_xml_cause, hostile_xml_stream_cause
from urdfinertia.rules import Rule


def robot(body: str, inertial: str = ""):
    doc = f'<robot name="r"><link name="a">{inertial}{body}</link></robot>'
    return robot_from_bytes(doc.encode(), "t.urdf")


def box(size: str):
    return robot(f'<collision><geometry><box size="{size}"/></geometry></collision>')


@pytest.mark.parametrize(("text", "value"), [
    ("1 2 3", (1.0, 2.0, 3.0)),
    ("+1 2.5e-3 .5", (1.0, 0.0025, 0.5)),
    ("1. 2E2 3e+0", (1.0, 200.0, 3.0)),
    ("\t1\n 2\r\n3  ", (1.0, 2.0, 3.0)),
])
def test_numbers_accepted(text, value):
    assert box(text).links[0].collisions[0].shape == Box(value)


def only_problem(r, rule: Rule | None = None):
    """The reader's one finding (of ``rule``, when given)."""
    found = [f for f in r.findings if rule is None or f.rule == rule]
    assert len(found) == 1, r.findings
    return found[0]


@pytest.mark.parametrize("text", [
    "1 2 nan", "1 2 inf", "1 2 -Infinity", "1 2 0x1p3", "1 2 1_000", "1 2 \u0663",
    "1 2 3.0f", "1 2 e3", "1 2 -", "1 2 1e", "1, 2, 3, 4", "1 2,",
])
def test_non_numbers_drop_the_element(text):
    r = box(text)
    assert r.links[0].collisions == ()
    p = only_problem(r)
    assert re.search("is not a number|needs 3 numbers", p.message), p
    assert (p.link, p.line, p.element, p.rule) == ("a", 1, "collision[0]",
                                                    Rule.VECTOR_UNPARSEABLE)


@pytest.mark.parametrize(("text", "value"), [
    ("1,2,3", (1.0, 2.0, 3.0)), ("1.57, 1.30 1.57", (1.57, 1.3, 1.57)),
])
def test_commas_between_numbers_read_with_a_note(text, value):
    """One reading only (urdfdom's neighbours take it): read, with a finding."""
    r = box(text)
    assert r.links[0].collisions[0].shape == Box(value)
    assert only_problem(r).rule == Rule.VECTOR_COMMAS


@pytest.mark.parametrize("text", ["1e400 1 1", f"{MAX_MAGNITUDE * 10:g} 1 1"])
def test_out_of_range_drops_the_element(text):
    r = box(text)
    assert r.links[0].collisions == () and "out of range" in only_problem(r).message


@pytest.mark.parametrize(("m", "i"), [("1e-320", "1"), ("1", "5e-324"), ("-4e-310", "1")])
def test_a_subnormal_value_is_out_of_range(m, i):
    """Found by fuzzing: a kept mass of 1e-320 kg gave a written tensor of principal
    moments (0, 3.5e-323, 3.5e-323), not positive definite. A subnormal is what an
    underflow leaves, never a stated quantity: read as written, it is no value to compute
    with, and the verdict does not keep it."""
    from urdfinertia.body.options import FixOptions
    from urdfinertia.descriptions.inertial import RawInertial
    from urdfinertia.plan.fix import verdicts

    r = robot('<collision><geometry><box size="0.1 0.1 0.1"/></geometry></collision>',
              INERTIAL.format(m=m, i=i))
    raw = RawInertial.from_inertial(r.links[0].inertial)
    assert not (raw.mass_ok and raw.tensor_in_range)
    (link,) = verdicts(r, FixOptions()).links
    assert link.action != "keep" and link.after is not None and link.after.is_physical()
    assert robot("", INERTIAL.format(m="2.3e-308", i="1e-300")).links[0].inertial.mass > 0


def test_largest_magnitude_accepted():
    assert box(f"{MAX_MAGNITUDE:g} 1 1").links[0].collisions[0].shape.size[0] == MAX_MAGNITUDE


def test_long_value_shortened_in_message():
    assert len(only_problem(box("1 2 " + "9" * 5000 + "x")).describe("t.urdf")) < 300


def test_negative_mesh_scale_is_mirroring_not_an_error():
    r = robot('<visual><geometry><mesh filename="m.stl" scale="-1 1 1"/></geometry></visual>')
    assert r.links[0].visuals[0].shape == Mesh("m.stl", (-1.0, 1.0, 1.0))


def test_capsule_of_zero_length_is_a_sphere():
    r = robot('<collision><geometry><capsule radius="0.1" length="0"/></geometry></collision>')
    assert r.links[0].collisions[0].shape == Capsule(0.1, 0.0)


INERTIAL = ('<inertial><mass value="{m}"/>'
            '<inertia ixx="{i}" ixy="-5" ixz="0" iyy="1" iyz="0" izz="1"/></inertial>')


def test_zero_mass_placeholder_accepted():
    assert robot("", INERTIAL.format(m="0", i="1")).links[0].inertial.mass == 0.0


def test_negative_product_of_inertia_accepted():
    """Off-diagonal entries may be negative: only diagonal moments are signed."""
    assert robot("", INERTIAL.format(m="1", i="1")).links[0].inertial.ixy == -5.0


@pytest.mark.parametrize(("m", "i"), [("-1", "1"), ("1", "-0.5"), ("nan", "1"),
                                      ("1", "inf"), ("1e308", "1"), ("abc", "1")])
def test_an_inertial_is_read_as_written(m, i):
    """One reading: values no simulator takes are read as written (the judgement's to
    find), a text that is no number as NaN with a finding."""
    r = robot("", INERTIAL.format(m=m, i=i))
    inertial = r.links[0].inertial
    assert inertial is not None
    expected_mass = float("nan") if m == "abc" else float(m)
    assert (inertial.mass == expected_mass) or (inertial.mass != inertial.mass
                                               and expected_mass != expected_mass)
    assert inertial.ixx == float(i) or (inertial.ixx != inertial.ixx and i == "nan")
    found = [f.rule for f in r.findings]
    assert found == ([Rule.VECTOR_UNPARSEABLE] if m == "abc" else [])


def test_namespaced_root_refused():
    with pytest.raises(UrdfError, match="expected <robot>"):
        parse_xml(b'<robot xmlns="urn:x"><link name="a"/></robot>', "t.urdf")


def test_read_urdf_returns_original_bytes(tmp_path):
    data = b'<?xml version="1.0" encoding="UTF-8"?>\n<robot name="r"><link name="a"/></robot>'
    (tmp_path / "r.urdf").write_bytes(data)
    model, raw = read_urdf(tmp_path / "r.urdf")
    assert raw == data and model.links[0].name == "a"


# --- xml_safety ------------------------------------------------------------------------

@pytest.mark.parametrize(("doc", "words"), [
    (b'<!DOCTYPE r [<!ENTITY a "b">]><r/>', "entity declarations"),
    (b'<!DOCTYPE r [<!ENTITY % a "b">]><r/>', "entity declarations"),
    (b'<!DOCTYPE r SYSTEM "x.dtd"><r/>', "external DTD"),
    (b'<!DOCTYPE r PUBLIC "p" "x.dtd"><r/>', "external DTD"),
    (b"\xff\xfe<\x00r\x00/\x00>\x00", "UTF-16"),
    (b"\x00\x00\xfe\xff", "UTF-32"),
])
def test_hostile_xml_cause(doc, words):
    assert words in hostile_xml_cause(doc)


@pytest.mark.parametrize("doc", [
    b'<?xml version="1.0"?><robot name="r"/>',
    b"<!DOCTYPE robot><robot/>",
    b'<robot><!-- the word ENTITY in a comment --><link name="ENTITY"/></robot>',
])
def test_harmless_xml_passes(doc):
    assert hostile_xml_cause(doc) is None


@pytest.mark.parametrize("chunk", [7, 8, 9, 13, 64, 4096])
def test_stream_scan_finds_declaration_across_chunk_boundaries(chunk):
    doc = b"<?xml version='1.0'?>" + b" " * 50 + b'<!DOCTYPE c [<!ENTITY x "y">]><c/>'
    assert "entity" in hostile_xml_stream_cause(io.BytesIO(doc), chunk_size=chunk)
    assert hostile_xml_stream_cause(io.BytesIO(doc.replace(b"!ENTITY", b"!-- x")),
                                    chunk_size=chunk) is None


def test_safe_parser_reads_nothing_even_without_the_precheck(tmp_path):
    """Defence in depth: the parser itself neither loads a DTD nor expands an entity."""
    secret = tmp_path / "secret.dtd"
    secret.write_text('<!ENTITY x "TOP-SECRET">')
    leaked = tmp_path / "leak.txt"
    leaked.write_text("TOP-SECRET")
    for doc in (f'<!DOCTYPE robot SYSTEM "{secret}"><robot name="&x;"/>',
                f'<!DOCTYPE robot [<!ENTITY x SYSTEM "file://{leaked}">]><robot name="&x;"/>'):
        try:
            root = etree.fromstring(doc.encode(), parser=safe_parser())
        except etree.XMLSyntaxError:
            continue  # refusing is as good as not reading
        assert b"TOP-SECRET" not in etree.tostring(root)


def test_entity_bomb_refused_by_the_parser_too():
    lol = '<!ENTITY lol "lol">' + "".join(
        f'<!ENTITY lol{i} "{(f"&lol{i - 1};" if i > 1 else "&lol;") * 10}">'
        for i in range(1, 10))
    doc = f'<!DOCTYPE r [{lol}]><robot name="&lol9;"/>'.encode()
    try:
        root = etree.fromstring(doc, parser=safe_parser())
    except etree.XMLSyntaxError:
        return
    assert len(etree.tostring(root)) < 10_000  # never expanded


def test_deep_nesting_message():
    depth = 300
    doc = b"<robot>" + b"<a>" * depth + b"</a>" * depth + b"</robot>"
    with pytest.raises(UrdfError, match="nested deeper than 256 levels"):
        parse_xml(doc, "t.urdf")
