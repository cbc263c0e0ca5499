"""descriptions/formats.py: the registry picks a document's format and reads it."""

from pathlib import Path

import pytest

from urdfinertia.descriptions import formats
from urdfinertia.descriptions.formats import (
    DescriptionFormat,
    detect_format,
    read_description,
    register_format,
    root_name,
)
from urdfinertia.errors import UrdfError

URDF = b'<?xml version="1.0"?>\n<robot name="r"><link name="a"/></robot>\n'


@pytest.mark.parametrize(("data", "root"), [
    (URDF, "robot"),
    (b"\xef\xbb\xbf<robot/>", "robot"),
    (b"  \n<!-- a comment <sdf> -->\n<!DOCTYPE x>\n<sdf version='1.9'/>", "sdf"),
    (b"<?xml version='1.0'?><xacro:robot xmlns:xacro='x'/>", "robot"),
    (b"<mujoco model='m'>", "mujoco"),
    (b"not xml at all", None),
])
def test_root_name_skips_the_prolog(data, root):
    assert root_name(data) == root


def test_urdf_is_registered_and_read(tmp_path):
    path = tmp_path / "r.urdf"
    path.write_bytes(URDF)
    robot, data = read_description(path)
    assert robot.format == "urdf" and data == URDF and robot.link("a").name == "a"
    assert formats.format_of(robot).name == "urdf"


def test_a_claiming_format_wins_over_a_plain_one_of_the_same_root(tmp_path, monkeypatch):
    monkeypatch.setattr(formats, "_FORMATS", dict(formats._FORMATS))
    seen = []

    def read(data: bytes, path: Path):
        seen.append(path)
        return formats._FORMATS["urdf"].read(data, path)

    register_format(DescriptionFormat(
        name="special", roots=("robot",), suffixes=(".special",), read=read,
        patch=lambda data, new: data,
        claims=lambda data, path: b"special" in data))
    assert detect_format(URDF, Path("r.urdf")).name == "urdf"
    claimed = URDF.replace(b'name="r"', b'name="special"')
    assert detect_format(claimed, Path("r.urdf")).name == "special"
    # a root no format knows falls back to the suffix
    assert detect_format(b"<other/>", Path("x.special")).name == "special"
    path = tmp_path / "s.urdf"
    path.write_bytes(claimed)
    read_description(path)
    assert seen == [path]


def test_an_unknown_document_is_named_by_the_urdf_reader(tmp_path):
    path = tmp_path / "x.txt"
    path.write_bytes(b"<something/>")
    with pytest.raises(UrdfError, match="root element is <something>"):
        read_description(path)


def test_an_unreadable_file_is_a_one_line_error(tmp_path):
    with pytest.raises(UrdfError, match="cannot read"):
        read_description(tmp_path / "missing.urdf")


def test_usd_is_a_description_by_its_suffix():
    """USD has no XML root element: its suffixes alone make a file a description (the
    hook and the Action pass every *.usd* file with --skip-unknown-formats)."""
    from urdfinertia.descriptions.formats import is_description

    layer = b"#usda 1.0\n(\n    defaultPrim = \"robot\"\n)\n"
    for suffix in (".usd", ".usda", ".usdc", ".usdz"):
        assert is_description(layer, Path(f"robot{suffix}"))
    assert not is_description(layer, Path("robot.txt"))
    assert not is_description(b"<package><name>x</name></package>", Path("package.xml"))
