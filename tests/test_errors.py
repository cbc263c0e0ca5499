"""Error codes are attributes of the exceptions, set where the error is raised."""

from __future__ import annotations

import pytest

from urdfinertia.descriptions.paths import resolve_mesh_path
from urdfinertia.errors import MeshError, OutputError, UrdfError
from urdfinertia.mesh.read.load import load_mesh
from urdfinertia.plan.fix import problem_code


def test_class_default_and_instance_override():
    assert MeshError("x").code == "mesh-unreadable"
    assert MeshError("x", code="no-volume").code == "no-volume"
    assert UrdfError("x").code == "bad-description"
    assert OutputError("x").code == "output"
    # the message does not decide: a "limit" in the words is not a size limit
    assert problem_code(MeshError("speed limit exceeded")) == "mesh-unreadable"


@pytest.mark.parametrize(("uri", "code"), [
    ("missing.stl", "mesh-missing"),
    ("package://no_such_package_here/m.stl", "mesh-unresolved"),
    ("model://no_such_model_here/m.stl", "mesh-unresolved"),
    ("http://example.com/m.stl", "mesh-url"),
    ("file://host/m.stl", "mesh-url"),
])
def test_path_errors_carry_their_code(tmp_path, uri, code):
    with pytest.raises(MeshError) as info:
        resolve_mesh_path(uri, tmp_path)
    assert info.value.code == code


def test_mesh_reader_errors_carry_their_code(tmp_path):
    odd = tmp_path / "m.xyz"
    odd.write_bytes(b"x")
    with pytest.raises(MeshError) as info:
        load_mesh(odd, 10)
    assert info.value.code == "mesh-format"
    big = tmp_path / "big.stl"
    big.write_bytes(b"\0" * 80 + (1000).to_bytes(4, "little") + b"\0" * 50 * 1000)
    with pytest.raises(MeshError) as info:
        load_mesh(big, 10)
    assert info.value.code == "mesh-too-large"
