"""Kept values keep their bytes: ``fix`` changes only the text of what it derived.

On real robots (example-robot-data: panda and UR5 in URDF, Cassie in SDFormat) and a
hand-made MJCF, the input and the output are compared attribute by attribute (element
text by element text for SDFormat): every byte outside the inertials is the same, and
inside each link's inertial only the attributes of a derived value differ.
"""

from __future__ import annotations

import sys
from pathlib import Path

import pytest

from urdfinertia.body.options import FixOptions
from urdfinertia.descriptions.formats import NewInertial, format_of, read_description
from urdfinertia.descriptions.mjcf.write import scan_bodies
from urdfinertia.descriptions.sdf.write import link_nodes
from urdfinertia.descriptions.splice import attribute_spans, child_tags, next_tag
from urdfinertia.descriptions.urdf.write import scan_links
from urdfinertia.inertia.massprops import MassProperties
from urdfinertia.plan.fix import fix_file

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
from support.corpus import example_robot_data_dir  # noqa: E402

#: The (element, attribute) texts each derived value may change in a URDF inertial.
URDF_ATTRS = {"mass": {(b"mass", "value")}, "com": {(b"origin", "xyz")},
              "tensor": {(b"inertia", k) for k in ("ixx", "ixy", "ixz", "iyy", "iyz", "izz")}
              | {(b"origin", "rpy")}}


def urdf_changes(before: bytes, after: bytes, span_in, span_out) -> set[tuple[bytes, str]]:
    """(element, attribute) pairs whose text differs between two URDF inertials."""
    tags_in = child_tags(before, *span_in)
    tags_out = child_tags(after, *span_out)
    assert tags_in.keys() == tags_out.keys()
    changed = set()
    for name, tag in tags_in.items():
        a, b = attribute_spans(before, tag), attribute_spans(after, tags_out[name])
        assert a.keys() <= b.keys()
        for attr in b:
            old = before[a[attr][1]:a[attr][2]] if attr in a else None
            if old != after[b[attr][1]:b[attr][2]]:
                changed.add((name, attr))
    return changed


def skeleton(data: bytes, span: tuple[int, int], blank: set[tuple[bytes, str]]) -> bytes:
    """The inertial's bytes with the values of the ``blank`` attributes left out."""
    cuts = []
    for name, tag in child_tags(data, *span).items():
        for attr, (_, start, end) in attribute_spans(data, tag).items():
            if (name, attr) in blank:
                cuts.append((start, end))
    out, pos = bytearray(), span[0]
    for start, end in sorted(cuts):
        out += data[pos:start]
        pos = end
    return bytes(out + data[pos:span[1]])


def outside(data: bytes, spans: list[tuple[int, int]]) -> bytes:
    out, pos = bytearray(), 0
    for start, end in sorted(spans):
        out += data[pos:start] + b"<>"
        pos = end
    return bytes(out + data[pos:])


def robot_path(rel: str) -> Path:
    root = example_robot_data_dir()
    if root is None or not (root / "robots" / rel).is_file():
        pytest.skip("example-robot-data is not installed")
    return root / "robots" / rel


@pytest.mark.parametrize("rel", ["panda_description/urdf/panda.urdf",
                                 "ur_description/urdf/ur5_robot.urdf"])
def test_urdf_only_derived_attributes_change(rel):
    path = robot_path(rel)
    result = fix_file(path, FixOptions())
    before, after = result.original, result.output
    spans_in, spans_out = scan_links(before), scan_links(after)
    partial = 0
    for r in result.links:
        if r.assembly is None:
            if spans_in[r.name].inertial is None:
                continue
            assert before[slice(*spans_in[r.name].inertial)] == \
                after[slice(*spans_out[r.name].inertial)]
            continue
        allowed = set().union(*(URDF_ATTRS[v] for v in r.derived))
        changed = urdf_changes(before, after, spans_in[r.name].inertial,
                               spans_out[r.name].inertial)
        assert changed <= allowed, (r.name, r.derived, changed - allowed)
        assert changed, r.name  # a derived value is written
        # and every other byte of the inertial (order, quotes, spacing, comments) stays
        assert skeleton(before, spans_in[r.name].inertial, allowed) == \
            skeleton(after, spans_out[r.name].inertial, allowed), r.name
        partial += set(r.derived) != {"mass", "com", "tensor"}
    assert partial >= 3  # the robots have links with kept values (panda: 3 tensors)
    assert outside(before, [s.inertial for s in spans_in.values() if s.inertial]) == \
        outside(after, [s.inertial for s in spans_out.values() if s.inertial])


def test_sdf_only_derived_texts_change():
    path = robot_path("cassie_description/robots/cassie.sdf")
    result = fix_file(path, FixOptions())
    before, after = result.original, result.output
    nodes_in, nodes_out = link_nodes(before), link_nodes(after)
    partial = 0
    for r in result.links:
        if r.assembly is None or set(r.derived) == {"mass", "com", "tensor"}:
            continue
        partial += 1
        old = nodes_in[r.name].kids(b"inertial")[0]
        new = nodes_out[r.name].kids(b"inertial")[0]

        def text(data, node, *path):  # noqa: ANN001, ANN202
            for tag in path:
                node = node.kids(tag)[0]
            return data[node.start_end:data.rfind(b"</", node.start_end, node.end)]

        if "mass" not in r.derived:
            assert text(before, old, b"mass") == text(after, new, b"mass")
        if "tensor" not in r.derived:
            assert text(before, old, b"inertia") == text(after, new, b"inertia")
        pose_in, pose_out = text(before, old, b"pose").split(), text(after, new, b"pose").split()
        if "com" not in r.derived:
            assert pose_in[:3] == pose_out[:3]
        else:
            assert pose_in[:3] != pose_out[:3]
    # Cassie's derived links with kept values (its marker "reference" links are kept whole)
    assert partial >= 2


MJCF = b"""<mujoco>
  <worldbody>
    <body name="a">
      <freejoint/>
      <inertial pos='1.0e-02 0 0' mass='2.50' quat='1 0 0 0' diaginertia='1 2 3'/>
      <geom type="box" size=".1 .2 .3"/>
    </body>
  </worldbody>
</mujoco>
"""


@pytest.mark.parametrize(("derived", "expected"), [
    ({"tensor"}, b"<inertial pos='1.0e-02 0 0' mass='2.50' diaginertia='0.5 0.6 0.7'/>"),
    ({"mass", "tensor"}, b"<inertial pos='1.0e-02 0 0' mass='4' diaginertia='0.5 0.6 0.7'/>"),
    ({"com"}, b"<inertial pos='0.25 0 0' mass='2.50' quat='1 0 0 0' diaginertia='1 2 3'/>"),
])
def test_mjcf_only_derived_attributes_change(derived, expected):
    import numpy as np

    props = MassProperties(4.0, np.array([0.25, 0.0, 0.0]), np.diag([0.5, 0.6, 0.7]))
    robot, data = read_description_bytes(MJCF)
    out = format_of(robot).patch(data, {"a": NewInertial(props, 1.0, frozenset(derived))})
    start, end = scan_bodies(out)["a"].inertial
    assert out[start:end] == expected
    assert out.replace(expected, b"") == data.replace(data[slice(
        *scan_bodies(data)["a"].inertial)], b"")


def read_description_bytes(data: bytes):  # noqa: ANN201
    import tempfile

    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "m.xml"
        path.write_bytes(data)
        return read_description(path)


def test_urdf_rotated_origin_gets_zero_angles_with_a_derived_tensor(tmp_path):
    import numpy as np

    text = (b'<robot name="r"><link name="a"><inertial>\n'
            b'  <origin rpy="0 0 1.5707963" xyz="1.0517e-02 0 0"/>\n'
            b'  <mass value="1.0517e-02"/>\n'
            b'  <inertia ixx="1" ixy="0" ixz="0" iyy="1" iyz="0" izz="1"/>\n'
            b'</inertial></link></robot>\n')
    path = tmp_path / "r.urdf"
    path.write_bytes(text)
    robot, data = read_description(path)
    props = MassProperties(1.0517e-02, np.array([1.0517e-02, 0, 0]), np.diag([1e-3, 2e-3, 3e-3]))
    out = format_of(robot).patch(data, {"a": NewInertial(props, 1.0, frozenset({"tensor"}))})
    assert out == text.replace(b'rpy="0 0 1.5707963"', b'rpy="0 0 0"').replace(
        b'ixx="1" ixy="0" ixz="0" iyy="1" iyz="0" izz="1"',
        b'ixx="0.001" ixy="0" ixz="0" iyy="0.002" iyz="0" izz="0.003"')
    assert next_tag(out, 0) is not None


def test_repair_only_changes_only_the_tensor_text(tmp_path):
    from urdfinertia.plan.repair_only import repair_file

    text = (b'<robot name="r"><link name="a"><inertial>\n'
            b'  <origin rpy="0 0 0" xyz="1.0517e-02 0 0"/>\n'
            b'  <mass value="1.0517e-02"/>\n'
            b'  <inertia ixx="1e-3" ixy="0" ixz="0" iyy="1e-3" iyz="0" izz="5e-3"/>\n'
            b'</inertial></link></robot>\n')
    path = tmp_path / "r.urdf"
    path.write_bytes(text)
    out = repair_file(path).output
    lines_in, lines_out = text.splitlines(), out.splitlines()
    assert [i for i, (a, b) in enumerate(zip(lines_in, lines_out, strict=True)) if a != b] \
        == [3]  # the <inertia> line only (A + B < C lifted)
