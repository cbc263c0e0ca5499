"""``model://NAME/...`` mesh URIs: --package-dir, Gazebo's search paths, model.config above."""

from __future__ import annotations

import pytest

from urdfinertia.descriptions.paths import resolve_mesh_path
from urdfinertia.errors import MeshError


@pytest.fixture()
def models(tmp_path):
    mesh = tmp_path / "models" / "cup" / "meshes" / "cup.stl"
    mesh.parent.mkdir(parents=True)
    mesh.write_bytes(b"solid x\nendsolid x\n")
    (tmp_path / "models" / "cup" / "model.config").write_text("<model/>")
    return tmp_path


def test_found_by_walking_up_to_model_config(models, monkeypatch):
    for var in ("GZ_SIM_RESOURCE_PATH", "IGN_GAZEBO_RESOURCE_PATH", "SDF_PATH",
                "GAZEBO_MODEL_PATH"):
        monkeypatch.delenv(var, raising=False)
    sdf_dir = models / "models" / "cup"
    assert resolve_mesh_path("model://cup/meshes/cup.stl", sdf_dir) == (
        sdf_dir.resolve() / "meshes" / "cup.stl")


def test_found_on_gazebo_resource_path(models, tmp_path, monkeypatch):
    monkeypatch.setenv("GZ_SIM_RESOURCE_PATH", str(models / "models"))
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    found = resolve_mesh_path("model://cup/meshes/cup.stl", elsewhere)
    assert found == models / "models" / "cup" / "meshes" / "cup.stl"


def test_package_dir_wins_and_unknown_model_says_how(models, tmp_path, monkeypatch):
    monkeypatch.delenv("GZ_SIM_RESOURCE_PATH", raising=False)
    found = resolve_mesh_path("model://cup/meshes/cup.stl", tmp_path,
                              {"cup": models / "models" / "cup"})
    assert found.name == "cup.stl"
    with pytest.raises(MeshError, match="--package-dir nowhere=PATH"):
        resolve_mesh_path("model://nowhere/x.stl", tmp_path)
