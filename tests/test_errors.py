"""Every error carries the rule of its problem, set where the error is raised."""

from __future__ import annotations

import pytest

from urdfinertia.descriptions.paths import resolve_mesh_path
from urdfinertia.errors import MeshError, OutputError, UrdfError
from urdfinertia.mesh.read.load import load_mesh
from urdfinertia.rules import Rule


def test_class_default_and_instance_override():
    assert MeshError("x").rule == Rule.GEOMETRY_UNREADABLE
    assert MeshError("x", rule=Rule.MESH_NO_VOLUME).code == "mesh-no-volume"
    assert UrdfError("x").rule == Rule.DESCRIPTION_UNREADABLE
    assert OutputError("x").rule == Rule.OUTPUT_FAILED
    # the message does not decide: a "limit" in the words is not a size limit
    assert MeshError("speed limit exceeded").rule == Rule.GEOMETRY_UNREADABLE


@pytest.mark.parametrize(("uri", "rule"), [
    ("missing.stl", Rule.MESH_UNRESOLVED),
    ("package://no_such_package_here/m.stl", Rule.MESH_UNRESOLVED),
    ("model://no_such_model_here/m.stl", Rule.MESH_UNRESOLVED),
    ("http://example.com/m.stl", Rule.MESH_REFUSED),
    ("file://host/m.stl", Rule.MESH_REFUSED),
])
def test_path_errors_carry_their_rule(tmp_path, uri, rule):
    with pytest.raises(MeshError) as info:
        resolve_mesh_path(uri, tmp_path)
    assert info.value.rule == rule


def test_mesh_reader_errors_carry_their_rule(tmp_path):
    odd = tmp_path / "m.xyz"
    odd.write_bytes(b"x")
    with pytest.raises(MeshError) as info:
        load_mesh(odd, 10)
    assert info.value.rule == Rule.GEOMETRY_UNREADABLE
    big = tmp_path / "big.stl"
    big.write_bytes(b"\0" * 80 + (1000).to_bytes(4, "little") + b"\0" * 50 * 1000)
    with pytest.raises(MeshError) as info:
        load_mesh(big, 10)
    assert info.value.rule == Rule.MESH_TOO_LARGE
