"""paths.py: where mesh URIs point."""

from pathlib import Path

import pytest

from urdfinertia.descriptions.paths import resolve_mesh_path
from urdfinertia.errors import MeshError


@pytest.fixture
def tree(tmp_path, monkeypatch):
    """ws/src/my_robot/{package.xml, urdf/r.urdf, meshes/a.stl} and other/pkgs/my_robot."""
    monkeypatch.delenv("ROS_PACKAGE_PATH", raising=False)
    monkeypatch.delenv("AMENT_PREFIX_PATH", raising=False)
    pkg = tmp_path / "ws" / "src" / "robot_folder"
    (pkg / "urdf").mkdir(parents=True)
    (pkg / "meshes").mkdir()
    (pkg / "package.xml").write_text("<package><name>my_robot</name></package>")
    (pkg / "meshes" / "a.stl").write_bytes(b"x")
    other = tmp_path / "other" / "my_robot" / "meshes"
    other.mkdir(parents=True)
    (other / "a.stl").write_bytes(b"y")
    return pkg


def test_relative_path(tree):
    assert resolve_mesh_path("../meshes/a.stl", tree / "urdf") == tree / "urdf/../meshes/a.stl"


def test_file_uri(tree):
    target = tree / "meshes" / "a.stl"
    assert resolve_mesh_path(f"file://{target}", tree / "urdf") == target


def test_package_found_by_walking_up_to_package_xml(tree):
    assert resolve_mesh_path("package://my_robot/meshes/a.stl", tree / "urdf") == (
        tree / "meshes" / "a.stl")


def test_package_dir_option_wins(tree, tmp_path):
    other = tmp_path / "other" / "my_robot"
    found = resolve_mesh_path("package://my_robot/meshes/a.stl", tree / "urdf",
                              {"my_robot": other})
    assert found == other / "meshes" / "a.stl"


def test_ros_package_path_before_walking_up(tree, tmp_path, monkeypatch):
    monkeypatch.setenv("ROS_PACKAGE_PATH", str(tmp_path / "other"))
    found = resolve_mesh_path("package://my_robot/meshes/a.stl", tree / "urdf")
    assert found.read_bytes() == b"y"


def test_ament_prefix_path(tree, tmp_path, monkeypatch):
    share = tmp_path / "install" / "share" / "my_robot" / "meshes"
    share.mkdir(parents=True)
    (share / "a.stl").write_bytes(b"z")
    monkeypatch.setenv("AMENT_PREFIX_PATH", str(tmp_path / "install"))
    assert resolve_mesh_path("package://my_robot/meshes/a.stl", tree / "urdf").read_bytes() == b"z"


def test_folder_named_like_the_package(tmp_path, monkeypatch):
    monkeypatch.delenv("ROS_PACKAGE_PATH", raising=False)
    monkeypatch.delenv("AMENT_PREFIX_PATH", raising=False)
    root = tmp_path / "example-robot-data" / "robots" / "r"
    (root / "urdf").mkdir(parents=True)
    (root / "meshes").mkdir()
    (root / "meshes" / "m.stl").write_bytes(b"m")
    uri = "package://example-robot-data/robots/r/meshes/m.stl"
    assert resolve_mesh_path(uri, root / "urdf").read_bytes() == b"m"
    # the empty-authority form "package:///NAME/..." seen in real files
    assert resolve_mesh_path(uri.replace("//", "///", 1), root / "urdf").read_bytes() == b"m"


def test_unknown_package_is_an_error_with_a_hint(tree):
    with pytest.raises(MeshError, match="--package-dir nope=PATH"):
        resolve_mesh_path("package://nope/a.stl", tree / "urdf")


def test_missing_file_names_the_uri(tree):
    with pytest.raises(MeshError, match="missing.stl"):
        resolve_mesh_path("package://my_robot/meshes/missing.stl", tree / "urdf")


@pytest.mark.parametrize("uri", ["http://example.com/a.stl", "https://x/a.stl", "ftp://x/a"])
def test_urls_are_never_fetched(tree, uri):
    with pytest.raises(MeshError, match="only files"):
        resolve_mesh_path(uri, Path(tree))


def test_real_paths_match_path_resolve(tmp_path, monkeypatch):
    import itertools
    import os

    from urdfinertia.descriptions.paths import RealPaths

    (tmp_path / "a" / "b" / "c").mkdir(parents=True)
    (tmp_path / "x" / "y").mkdir(parents=True)
    (tmp_path / "a" / "b" / "c" / "f.stl").write_bytes(b"x")
    os.symlink("../x", tmp_path / "a" / "lx")
    os.symlink("a/b", tmp_path / "lb")
    os.symlink("c/f.stl", tmp_path / "a" / "b" / "lf")
    os.symlink("loop2", tmp_path / "loop1")
    os.symlink("loop1", tmp_path / "loop2")
    monkeypatch.chdir(tmp_path)
    names = ["a", "b", "c", "lx", "lb", "y", "..", ".", "f.stl", "lf", "nope", "loop1"]
    real = RealPaths()  # one memo for every path, as in a run
    for n in (1, 2, 3):
        for parts in itertools.product(names, repeat=n):
            for text in (os.path.join(*parts), os.path.join(tmp_path, *parts)):
                try:
                    want: object = str(Path(text).resolve())
                except RuntimeError:
                    want = RuntimeError
                try:
                    got: object = real(text)
                except RuntimeError:
                    got = RuntimeError
                assert got == want, text
