"""Hostile and broken input: one test per documented case, run in-process via ``cli.main``.

Every failing case asserts the exit code, that stderr is exactly one line naming the file
and the cause, that the input is byte-identical afterwards and that nothing was written
next to it (no output, no temporary file).
"""

from __future__ import annotations

import os
import struct
from pathlib import Path

import numpy as np
import pytest
from support.privileges import file_modes_bind, run_cli_bound_by_file_modes

from urdfinertia import cli
from urdfinertia.descriptions import xml as xml_safety
from urdfinertia.errors import MeshError
from urdfinertia.mesh import limits
from urdfinertia.mesh.read import load as mesh_io

URDF = """<?xml version="1.0"?>
<robot name="r">
  <link name="base">
    <inertial>
      <origin xyz="0 0 0" rpy="0 0 0"/>
      <mass value="2"/>
      <inertia ixx="1" ixy="0" ixz="0" iyy="1" iyz="0" izz="1"/>
    </inertial>
    <collision>
      <origin xyz="0 0 0.1" rpy="0 0 0"/>
      <geometry><box size="0.1 0.2 0.3"/></geometry>
    </collision>
  </link>
  <link name="arm">
    <collision>
      <geometry><mesh filename="MESH" scale="1 1 1"/></geometry>
    </collision>
  </link>
  <joint name="j" type="fixed"><parent link="base"/><child link="arm"/></joint>
</robot>
"""


def cube_stl(size: float = 0.1) -> bytes:
    """A closed binary STL cube of side ``size`` (12 triangles, outward normals)."""
    import trimesh

    mesh = trimesh.creation.box((size, size, size))
    tri = mesh.vertices[mesh.faces].astype(np.float32)
    out = bytearray(b"\0" * 80 + struct.pack("<I", len(tri)))
    for t in tri:
        out += struct.pack("<3f", 0, 0, 0) + t.tobytes() + b"\0\0"
    return bytes(out)


def snapshot_names(folder: Path) -> list[str]:
    """Every path under ``folder`` (readable or not)."""
    return sorted(str(p.relative_to(folder)) for p in folder.rglob("*"))


def snapshot(folder: Path) -> dict[str, bytes]:
    """Every file under ``folder`` with its bytes (symlinks by their target text)."""
    out = {}
    for p in sorted(folder.rglob("*")):
        key = str(p.relative_to(folder))
        if p.is_symlink():
            out[key] = b"->" + os.readlink(p).encode()
        elif p.is_file():
            out[key] = p.read_bytes()
    return out


@pytest.fixture
def workdir(tmp_path, monkeypatch):
    """A URDF with a box link and a mesh link; the mesh cache is kept inside tmp_path."""
    monkeypatch.setenv("URDFINERTIA_CACHE_DIR", str(tmp_path / "cache"))
    monkeypatch.delenv("ROS_PACKAGE_PATH", raising=False)
    monkeypatch.delenv("AMENT_PREFIX_PATH", raising=False)
    robot = tmp_path / "robot"
    robot.mkdir()
    (robot / "cube.stl").write_bytes(cube_stl())
    (robot / "r.urdf").write_text(URDF.replace("MESH", "cube.stl"))
    return robot


def run(argv: list[str], capsys) -> tuple[int, str, str]:
    code = cli.main(argv)
    captured = capsys.readouterr()
    return code, captured.out, captured.err


def expect_refusal(folder: Path, urdf: Path, capsys, *needles: str, code: int = 2,
                   extra: tuple[str, ...] = ()) -> str:
    """Run ``fix URDF -o out.urdf --strict``; assert a one-line refusal and an untouched
    folder. ``--strict`` is all-or-nothing: without it, a problem of one element or link
    drops that element or leaves that link (tests/test_partly_broken.py); document-level
    and security refusals are the same either way (:func:`test_refused_without_strict`)."""
    before = snapshot(folder)
    out = folder / "out.urdf"
    rc, stdout, err = run(["fix", "--all", str(urdf), "-o", str(out), "-q", "--no-cache",
                           "--strict", *extra], capsys)
    assert rc == code, err
    lines = err.splitlines()
    assert len(lines) == 1, err
    assert lines[0].startswith("urdf-inertia: error: "), err
    assert "Traceback" not in err
    for needle in needles:
        assert needle in lines[0], (needle, lines[0])
    assert stdout == ""
    assert snapshot(folder) == before  # input byte-identical, nothing written
    return lines[0]


# --- XML: entities, DTDs, bombs -------------------------------------------------------

@pytest.fixture
def parser_must_not_run(monkeypatch):
    """Proof that a refusal happens before lxml sees the document."""

    def forbidden():
        raise AssertionError("the XML parser ran on a hostile document")

    monkeypatch.setattr(xml_safety, "safe_parser", forbidden)


SECRET = "TOP-SECRET-7f3a"

HOSTILE_XML = {
    "xxe_file": '<!DOCTYPE robot [<!ENTITY x SYSTEM "file://{secret}">]>\n'
                '<robot name="&x;"><link name="a"/></robot>',
    "xxe_url": '<!DOCTYPE robot [<!ENTITY x SYSTEM "http://127.0.0.1:9/x">]>\n'
               '<robot name="&x;"><link name="a"/></robot>',
    "parameter_entity": '<!DOCTYPE robot [<!ENTITY % p SYSTEM "file://{secret}"> %p;]>\n'
                        '<robot name="r"><link name="a"/></robot>',
    "external_dtd": '<!DOCTYPE robot SYSTEM "file://{secret}">\n'
                    '<robot name="&x;"><link name="a"/></robot>',
    "public_dtd": '<!DOCTYPE robot PUBLIC "-//x//y" "http://127.0.0.1:9/r.dtd">\n'
                  '<robot name="r"><link name="a"/></robot>',
    "billion_laughs": '<!DOCTYPE lolz [<!ENTITY lol "lol">'
                      + "".join(f'<!ENTITY lol{i} "{("&lol" + str(i - 1) + ";") * 10}">'
                                .replace("&lol0;", "&lol;") for i in range(1, 10))
                      + ']>\n<robot name="&lol9;"><link name="a"/></robot>',
    "lowercase_entity": '<!DOCTYPE robot [<!entity x SYSTEM "file://{secret}">]>\n'
                        '<robot name="r"/>',
}


@pytest.mark.parametrize("case", sorted(HOSTILE_XML))
def test_hostile_xml_refused_before_parsing(case, workdir, capsys, parser_must_not_run):
    secret = workdir.parent / "secret.txt"
    secret.write_text(SECRET)
    urdf = workdir / "evil.urdf"
    urdf.write_text('<?xml version="1.0"?>\n' + HOSTILE_XML[case].format(secret=secret))
    line = expect_refusal(workdir, urdf, capsys, "evil.urdf:")
    assert ("entity declarations are not allowed" in line
            or "external DTD references" in line), line
    assert SECRET not in line


def test_utf16_entity_bomb_refused(workdir, capsys, parser_must_not_run):
    """A UTF-16 document would hide '<!ENTITY' from a byte search: refused as UTF-16."""
    text = '<?xml version="1.0" encoding="UTF-16"?>\n' + HOSTILE_XML["billion_laughs"]
    urdf = workdir / "evil.urdf"
    urdf.write_bytes(text.encode("utf-16"))
    expect_refusal(workdir, urdf, capsys, "evil.urdf:", "UTF-16")


def test_utf16_without_bom_refused(workdir, capsys, parser_must_not_run):
    urdf = workdir / "evil.urdf"
    urdf.write_bytes('<robot name="r"/>'.encode("utf-16-le"))
    expect_refusal(workdir, urdf, capsys, "evil.urdf:", "not supported")


def test_latin1_document_refused_with_hint(workdir, capsys):
    urdf = workdir / "latin.urdf"
    urdf.write_bytes(b'<?xml version="1.0" encoding="ISO-8859-1"?>\n'
                     b'<robot name="r"><link name="caf\xe9"/></robot>')
    expect_refusal(workdir, urdf, capsys, "latin.urdf:", "convert the file to UTF-8")


def test_deep_nesting_refused(workdir, capsys):
    urdf = workdir / "deep.urdf"
    urdf.write_text("<robot>" + "<a>" * 5000 + "</a>" * 5000 + "</robot>")
    expect_refusal(workdir, urdf, capsys, "deep.urdf:1:", "nested deeper than 256")


def test_oversized_urdf_refused_before_parsing(workdir, capsys, parser_must_not_run,
                                               monkeypatch):
    monkeypatch.setattr(xml_safety, "MAX_DOCUMENT_BYTES", 100)
    urdf = workdir / "r.urdf"
    expect_refusal(workdir, urdf, capsys, "r.urdf:", "larger than the limit of 100 bytes")


# --- broken documents ------------------------------------------------------------------

def test_malformed_xml_names_line(workdir, capsys):
    urdf = workdir / "bad.urdf"
    urdf.write_text('<robot name="r">\n<link name="a">\n</robot>\n')
    expect_refusal(workdir, urdf, capsys, "bad.urdf:3:", "malformed XML")


def test_not_a_robot(workdir, capsys):
    urdf = workdir / "sdf.urdf"
    urdf.write_text('<scene version="1.6"><model name="m"/></scene>')  # no format's root
    expect_refusal(workdir, urdf, capsys, "sdf.urdf:1:", "expected <robot>")


def test_duplicate_link_names(workdir, capsys):
    urdf = workdir / "dup.urdf"
    urdf.write_text('<robot name="r">\n<link name="a"/>\n<link name="a"/>\n</robot>')
    expect_refusal(workdir, urdf, capsys, "dup.urdf:3:", "duplicate link name 'a'")


def test_missing_urdf(workdir, capsys):
    expect_refusal(workdir, workdir / "nope.urdf", capsys, "nope.urdf:", "cannot read")


def test_urdf_is_a_folder(workdir, capsys):
    folder = workdir / "folder.urdf"
    folder.mkdir()
    rc, _, err = run(["fix", "--all", str(folder), "-q", "--no-cache"], capsys)
    assert rc == 2 and len(err.splitlines()) == 1, err


BAD_NUMBERS = [
    # (original text, replacement, expected words)
    ('size="0.1 0.2 0.3"', 'size="nan 0.2 0.3"', "not a number"),
    ('size="0.1 0.2 0.3"', 'size="inf 0.2 0.3"', "not a number"),
    ('size="0.1 0.2 0.3"', 'size="1e999 0.2 0.3"', "not finite"),
    ('size="0.1 0.2 0.3"', 'size="-0.1 0.2 0.3"', "must be positive"),
    ('size="0.1 0.2 0.3"', 'size=""', "needs 3 numbers"),
    ('size="0.1 0.2 0.3"', 'size="0.1 0.2"', "needs 3 numbers"),
    ('size="0.1 0.2 0.3"', 'size="0.1 0.2 0x3"', "not a number"),
    ('size="0.1 0.2 0.3"', 'size="0.1 0.2 3_0"', "not a number"),
    ('scale="1 1 1"', 'scale="1 nan 1"', "not a number"),
    ('scale="1 1 1"', 'scale="1 -inf 1"', "not a number"),
    ('scale="1 1 1"', 'scale=""', "needs 3 numbers"),
    ('<origin xyz="0 0 0.1"', '<origin xyz="0 0 NaN"', "not a number"),
    ('<origin xyz="0 0 0.1"', '<origin xyz="0 0 "', "needs 3 numbers"),
    ('rpy="0 0 0"/>\n      <geometry><box', 'rpy="0 inf 0"/>\n      <geometry><box',
     "not a number"),
    # an inertial value that is no number at all is read past: --strict refuses it
    ('<mass value="2"/>', '<mass value=""/>', "needs 1 number"),
    ('ixz="0"', 'ixz=""', "needs 1 number"),
]
#: Inertial values that are numbers no simulator takes: read as written and judged (one
#: reading), so even ``--strict`` writes the file, with the link recomputed and valid.
JUDGED_NUMBERS = [
    ('<mass value="2"/>', '<mass value="nan"/>'),
    ('<mass value="2"/>', '<mass value="-2"/>'),
    ('ixx="1"', 'ixx="-1"'),
    ('ixy="0"', 'ixy="1e400"'),
    ('<inertial>\n      <origin xyz="0 0 0"', '<inertial>\n      <origin xyz="0 nan 0"'),
]


@pytest.mark.parametrize(("old", "new", "words"), BAD_NUMBERS,
                         ids=[f"{i}-{b[1][:20]}" for i, b in enumerate(BAD_NUMBERS)])
def test_bad_numbers(old, new, words, workdir, capsys):
    urdf = workdir / "r.urdf"
    text = urdf.read_text()
    assert old in text
    urdf.write_text(text.replace(old, new, 1))
    line = expect_refusal(workdir, urdf, capsys, "r.urdf:", words)
    assert "link '" in line  # every one of these sits inside a link


@pytest.mark.parametrize(("old", "new"), JUDGED_NUMBERS,
                         ids=[f"{i}-{b[1][:20]}" for i, b in enumerate(JUDGED_NUMBERS)])
def test_invalid_inertial_numbers_are_judged_and_repaired(old, new, workdir, capsys):
    from urdfinertia.descriptions.formats import read_description
    from urdfinertia.descriptions.inertial import RawInertial

    urdf = workdir / "r.urdf"
    text = urdf.read_text()
    assert old in text
    urdf.write_text(text.replace(old, new, 1))
    out = workdir / "out.urdf"
    rc, _, err = run(["fix", "--all", str(urdf), "-o", str(out), "-q", "--no-cache",
                      "--strict"], capsys)
    assert rc == 0, err
    assert "Traceback" not in err
    robot, _ = read_description(out)
    for link in robot.links:
        if link.inertial is not None:
            raw = RawInertial.from_inertial(link.inertial)
            assert raw.mass_properties() is not None, link.name  # valid, finite


ZERO_SIZE = [
    '<box size="0 0.2 0.3"/>',
    '<cylinder radius="0" length="1"/>',
    '<cylinder radius="0.1" length="0"/>',
    '<sphere radius="0"/>',
    '<sphere radius="-0"/>',
    '<mesh filename="cube.stl" scale="1 0 1"/>',
]


@pytest.mark.parametrize("shape", ZERO_SIZE)
def test_zero_size_primitives(shape, workdir, capsys):
    urdf = workdir / "r.urdf"
    urdf.write_text(urdf.read_text().replace('<box size="0.1 0.2 0.3"/>', shape))
    line = expect_refusal(workdir, urdf, capsys, "r.urdf:", "link 'base'")
    assert "positive" in line or "zero" in line, line


# --- meshes ----------------------------------------------------------------------------

def with_mesh(workdir: Path, filename: str) -> Path:
    urdf = workdir / "r.urdf"
    urdf.write_text(URDF.replace("MESH", filename))
    return urdf


def test_missing_mesh(workdir, capsys):
    urdf = with_mesh(workdir, "gone.stl")
    expect_refusal(workdir, urdf, capsys, "r.urdf:", "link 'arm'", "mesh file not found",
                   "gone.stl")


def test_mesh_content_error_names_urdf_file_and_line(workdir, capsys):
    (workdir / "bad.obj").write_bytes(b"v 0 0 0\nv 1 0 0\nf 1 2 99\n")
    urdf = with_mesh(workdir, "bad.obj")
    # 0-based index of the <geometry> line == 1-based line of the <collision> above it
    line_no = URDF.splitlines().index('      <geometry><mesh filename="MESH" scale="1 1 1"/>'
                                      '</geometry>')
    expect_refusal(workdir, urdf, capsys, f"r.urdf:{line_no}: link 'arm'", "bad.obj")


def test_mesh_is_a_fifo_never_opened(workdir, capsys):
    """Opening a FIFO for reading blocks until a writer appears: it must be refused."""
    os.mkfifo(workdir / "pipe.stl")
    urdf = with_mesh(workdir, "pipe.stl")
    expect_refusal(workdir, urdf, capsys, "link 'arm'", "not a regular file")


def test_mesh_is_a_folder(workdir, capsys):
    (workdir / "dir.stl").mkdir()
    urdf = with_mesh(workdir, "dir.stl")
    expect_refusal(workdir, urdf, capsys, "link 'arm'", "not a regular file")


def test_unreadable_mesh(workdir):
    """A mesh of mode 0: one line naming the link and the cause, nothing written. Run in a
    child bound by file modes, so that it holds as root too (support.privileges)."""
    assert file_modes_bind(), "the child could not be bound by file modes"
    mesh = workdir / "cube.stl"
    urdf = with_mesh(workdir, "cube.stl")
    mesh.chmod(0)
    try:
        before = snapshot_names(workdir)
        done = run_cli_bound_by_file_modes(
            ["fix", "--all", str(urdf), "-o", str(workdir / "out.urdf"), "-q", "--no-cache",
             "--strict"], cwd=workdir)
    finally:
        mesh.chmod(0o644)
    assert done.returncode == 2, done.stderr
    lines = done.stderr.splitlines()
    assert len(lines) == 1, done.stderr
    assert "link 'arm'" in lines[0] and "cannot read mesh" in lines[0], lines[0]
    assert "Traceback" not in done.stderr and done.stdout == ""
    assert snapshot_names(workdir) == before  # no output, no temporary file


def test_unreadable_mesh_reported(workdir, capsys, monkeypatch):
    """Whatever the user id: an OSError while reading becomes one MeshError line."""
    real_open = open

    def deny(file, *args, **kwargs):
        if str(file).endswith("cube.stl"):
            raise PermissionError(13, "Permission denied")
        return real_open(file, *args, **kwargs)

    monkeypatch.setattr("builtins.open", deny)
    urdf = with_mesh(workdir, "cube.stl")
    expect_refusal(workdir, urdf, capsys, "link 'arm'", "Permission denied")


def test_unsupported_mesh_format(workdir, capsys):
    (workdir / "part.3ds").write_bytes(b"MM\x00\x00")
    urdf = with_mesh(workdir, "part.3ds")
    expect_refusal(workdir, urdf, capsys, "link 'arm'", "unsupported mesh format '.3ds'")


CORRUPT = {
    "stl": b"\x00" * 80 + struct.pack("<I", 3) + b"\x01" * 17,
    "stl_ascii": b"solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0\nendloop\nendfacet\n",
    "obj": b"v 0 0 0\nv 1 0 0\nf 1 2 99\n",
    "ply": b"ply\nformat binary_little_endian 1.0\nelement vertex 9\nproperty float x\n"
           b"end_header\n\x01\x02",
    "off": b"OFF\n3 1 0\n0 0 0\n1 0 0\n",
    "glb": b"glTF\x02\x00\x00\x00\xff\xff\x00\x00garbage",
    "gltf": b'{"asset": {"version": "2.0"}, "meshes": [{"primitives": [{"attributes": '
            b'{"POSITION": 7}}]}]}',
    "dae": b'<?xml version="1.0"?><COLLADA><library_geometries><geometry>'
           b"<mesh><source/></mesh></geometry></library_geometries>",
}


@pytest.mark.parametrize("kind", sorted(CORRUPT))
def test_corrupt_mesh_bytes(kind, workdir, capsys):
    suffix = kind.split("_")[0]
    (workdir / f"bad.{suffix}").write_bytes(CORRUPT[kind])
    urdf = with_mesh(workdir, f"bad.{suffix}")
    line = expect_refusal(workdir, urdf, capsys, "link 'arm'", f"bad.{suffix}")
    assert "mesh" in line


@pytest.mark.parametrize("seed", range(6))
@pytest.mark.parametrize("suffix", ["stl", "obj", "dae", "glb", "ply", "off"])
def test_random_bytes_as_mesh(suffix, seed, workdir, capsys):
    """Noise of every supported type: a documented MeshError, never a crash."""
    rng = np.random.default_rng(seed)
    (workdir / f"noise.{suffix}").write_bytes(rng.bytes(int(rng.integers(0, 3000))))
    urdf = with_mesh(workdir, f"noise.{suffix}")
    expect_refusal(workdir, urdf, capsys, "link 'arm'", f"noise.{suffix}")


@pytest.mark.parametrize("uri", [
    "http://127.0.0.1:9/cube.stl",
    "https://example.invalid/cube.stl",
    "ftp://example.invalid/cube.stl",
    "file://example.invalid/cube.stl",
    "data:model/stl;base64,AAAA",
])
def test_mesh_urls_refused(uri, workdir, capsys, monkeypatch):
    def no_load(*args, **kwargs):
        raise AssertionError("a URL reached the mesh loader")

    monkeypatch.setattr("trimesh.load", no_load)
    urdf = with_mesh(workdir, uri)
    line = expect_refusal(workdir, urdf, capsys, "link 'arm'")
    assert "only files are read" in line or "only local files are read" in line, line


def test_unresolvable_package(workdir, capsys):
    urdf = with_mesh(workdir, "package://no_such_pkg/meshes/cube.stl")
    expect_refusal(workdir, urdf, capsys, "link 'arm'", "cannot resolve package 'no_such_pkg'",
                   "--package-dir no_such_pkg=PATH")


def test_invalid_package_name(workdir, capsys):
    urdf = with_mesh(workdir, "package://../cube.stl")
    expect_refusal(workdir, urdf, capsys, "link 'arm'", "valid ROS package")


def test_collada_xxe_refused_before_collada_runs(workdir, capsys, monkeypatch):
    secret = workdir.parent / "secret.txt"
    secret.write_text(SECRET)

    def no_load(*args, **kwargs):
        raise AssertionError("a hostile COLLADA file reached the parser")

    monkeypatch.setattr("trimesh.load", no_load)
    dae = (f'<?xml version="1.0"?>\n<!DOCTYPE c [<!ENTITY x SYSTEM "file://{secret}">]>\n'
           '<COLLADA><asset><unit meter="&x;"/></asset></COLLADA>')
    (workdir / "evil.dae").write_text(dae)
    urdf = with_mesh(workdir, "evil.dae")
    line = expect_refusal(workdir, urdf, capsys, "link 'arm'", "entity declarations")
    assert SECRET not in line


def test_mesh_over_face_limit_names_limit_and_option(workdir, capsys, monkeypatch):
    def no_load(*args, **kwargs):
        raise AssertionError("an over-limit binary STL was parsed")

    monkeypatch.setattr("trimesh.load", no_load)
    urdf = with_mesh(workdir, "cube.stl")
    expect_refusal(workdir, urdf, capsys, "link 'arm'", "12 faces", "limit 10",
                   "--max-faces", extra=("--max-faces", "10"))


def test_mesh_over_byte_limit_refused_before_reading(workdir, capsys, monkeypatch):
    """A file larger than the byte budget is refused on its size alone."""
    monkeypatch.setattr(limits, "BASE_MESH_BYTES", 0)

    def no_open(*args, **kwargs):
        raise AssertionError("an over-size mesh was opened")

    monkeypatch.setattr(mesh_io, "declared_faces", no_open)
    (workdir / "big.obj").write_bytes(b"# padding\n" * 100)  # 1000 bytes, no faces
    urdf = with_mesh(workdir, "big.obj")
    expect_refusal(workdir, urdf, capsys, "link 'arm'", "1000 bytes", "limit 800 bytes",
                   "--max-faces", extra=("--max-faces", "2"))


def test_ascii_stl_faces_counted_before_parsing(workdir, capsys, monkeypatch):
    import trimesh

    ascii_stl = trimesh.creation.box((0.1, 0.1, 0.1)).export(file_type="stl_ascii")
    (workdir / "a.stl").write_bytes(ascii_stl.encode() if isinstance(ascii_stl, str)
                                    else ascii_stl)

    def no_load(*args, **kwargs):
        raise AssertionError("an over-limit ASCII STL was parsed")

    monkeypatch.setattr("trimesh.load", no_load)
    urdf = with_mesh(workdir, "a.stl")
    expect_refusal(workdir, urdf, capsys, "12 faces", "limit 11", extra=("--max-faces", "11"))


def test_instancing_bomb_refused(workdir, capsys):
    """A small GLB instancing one mesh many times is counted with every instance."""
    import trimesh

    box = trimesh.creation.box((0.01, 0.01, 0.01))
    scene = trimesh.Scene()
    for i in range(50):
        scene.add_geometry(box, geom_name="box", node_name=f"n{i}",
                           transform=trimesh.transformations.translation_matrix([i, 0, 0]))
    (workdir / "many.glb").write_bytes(scene.export(file_type="glb"))
    urdf = with_mesh(workdir, "many.glb")
    expect_refusal(workdir, urdf, capsys, "link 'arm'", "600 faces", "limit 100",
                   extra=("--max-faces", "100"))


def test_load_mesh_refuses_fifo_directly(tmp_path):
    os.mkfifo(tmp_path / "p.stl")
    with pytest.raises(MeshError, match="not a regular file"):
        mesh_io.load_mesh(tmp_path / "p.stl")


# --- outputs ---------------------------------------------------------------------------

def test_output_folder_missing(workdir, capsys):
    before = snapshot(workdir)
    out = workdir / "no" / "such" / "out.urdf"
    rc, _, err = run(["fix", "--all", str(workdir / "r.urdf"), "-o", str(out), "-q", "--no-cache"],
                     capsys)
    assert rc == 2 and len(err.splitlines()) == 1, err
    assert "out.urdf" in err and "cannot write" in err
    assert snapshot(workdir) == before


def test_output_parent_is_a_file(workdir, capsys):
    (workdir / "plain").write_bytes(b"not a folder")
    before = snapshot(workdir)
    rc, _, err = run(["fix", "--all", str(workdir / "r.urdf"), "-o",
                      str(workdir / "plain" / "o.urdf"), "-q", "--no-cache"], capsys)
    assert rc == 2 and len(err.splitlines()) == 1, err
    assert "o.urdf" in err and "cannot write" in err
    assert snapshot(workdir) == before


def test_output_folder_read_only(workdir):
    """An output folder of mode 0o555: one line, exit 2, the folder stays empty and the
    input unchanged. Run in a child bound by file modes (root included)."""
    assert file_modes_bind(), "the child could not be bound by file modes"
    ro = workdir / "ro"
    ro.mkdir()
    urdf_before = (workdir / "r.urdf").read_bytes()
    ro.chmod(0o555)
    try:
        done = run_cli_bound_by_file_modes(
            ["fix", "--all", str(workdir / "r.urdf"), "-o", str(ro / "o.urdf"), "-q",
             "--no-cache"], cwd=workdir)
    finally:
        ro.chmod(0o755)
    assert done.returncode == 2, done.stderr
    lines = done.stderr.splitlines()
    assert len(lines) == 1 and "cannot write" in lines[0] and "o.urdf" in lines[0], done.stderr
    assert not list(ro.iterdir())
    assert (workdir / "r.urdf").read_bytes() == urdf_before


def test_failed_run_keeps_existing_output(workdir, capsys):
    """An existing output is only replaced on success."""
    out = workdir / "out.urdf"
    out.write_bytes(b"previous result")
    urdf = with_mesh(workdir, "gone.stl")
    expect_refusal(workdir, urdf, capsys, "mesh file not found")
    assert out.read_bytes() == b"previous result"


def test_failed_in_place_leaves_input_and_no_backup(workdir, capsys):
    urdf = with_mesh(workdir, "gone.stl")
    before = snapshot(workdir)
    rc, _, err = run(["fix", "--all", str(urdf), "--in-place", "-q", "--no-cache", "--strict"],
                     capsys)
    assert rc == 2 and len(err.splitlines()) == 1
    assert snapshot(workdir) == before


def test_in_place_through_symlink_writes_target(workdir, capsys):
    real = workdir / "real"
    real.mkdir()
    (real / "cube.stl").write_bytes(cube_stl())
    (real / "r.urdf").write_text(URDF.replace("MESH", "cube.stl"))
    original = (real / "r.urdf").read_bytes()
    link = workdir / "link.urdf"
    link.symlink_to(real / "r.urdf")
    rc, _, err = run(["fix", "--all", str(link), "--in-place", "-q", "--no-cache"], capsys)
    assert rc == 0, err
    assert link.is_symlink() and os.readlink(link) == str(real / "r.urdf")
    assert (real / "r.urdf").read_bytes() != original
    assert (real / "r.urdf.bak").read_bytes() == original
    assert not (workdir / "link.urdf.bak").exists()


def test_output_symlink_writes_target(workdir, capsys):
    target = workdir / "target.urdf"
    target.write_bytes(b"old")
    out = workdir / "out.urdf"
    out.symlink_to(target)
    rc, _, err = run(["fix", "--all", str(workdir / "r.urdf"), "-o", str(out), "-q", "--no-cache"],
                     capsys)
    assert rc == 0, err
    assert out.is_symlink()
    assert target.read_bytes().startswith(b"<?xml")


def test_output_same_as_input_refused(workdir, capsys):
    urdf = workdir / "r.urdf"
    before = snapshot(workdir)
    rc, _, err = run(["fix", "--all", str(urdf), "-o", str(urdf), "-q", "--no-cache"], capsys)
    assert rc == 2 and "use --in-place" in err
    assert snapshot(workdir) == before


def test_spec_that_does_not_parse(workdir, capsys):
    pytest.importorskip("urdfinertia.body.spec")
    spec = workdir / "spec.toml"
    spec.write_text("[link.base\nmass = ")
    expect_refusal(workdir, workdir / "r.urdf", capsys, "spec.toml", "TOML",
                   extra=("--spec", str(spec)))


# --- error reporting -------------------------------------------------------------------

def test_internal_error_is_one_line_exit_3(workdir, capsys, monkeypatch):
    def boom(*args, **kwargs):
        raise ZeroDivisionError("went\nwrong")

    monkeypatch.setattr("urdfinertia.cli.fix.fix_file", boom)
    before = snapshot(workdir)
    rc, out, err = run(["fix", "--all", str(workdir / "r.urdf"), "-q", "--no-cache"], capsys)
    assert rc == 3 and out == ""
    assert snapshot(workdir) == before
    assert err.splitlines() == ["urdf-inertia: internal error: ZeroDivisionError: went wrong "
                                "(this is a bug; rerun with --debug for the traceback)"]


def test_debug_shows_traceback(workdir, capsys):
    urdf = with_mesh(workdir, "gone.stl")
    before = snapshot(workdir)
    rc, out, err = run(["fix", "--all", str(urdf), "-q", "--no-cache", "--debug", "--strict"],
                       capsys)
    assert rc == 2 and out == ""  # nothing on stdout, nothing written
    assert snapshot(workdir) == before
    assert "mesh file not found" in err.splitlines()[-1]
    assert "Traceback" in err
    assert err.splitlines()[-1].startswith("urdf-inertia: error: ")


def test_usage_error_is_one_line(capsys):
    with pytest.raises(SystemExit) as exc:
        cli.main(["fix", "--all", "--max-faces", "many", "x.urdf"])
    assert exc.value.code == 2
    err = capsys.readouterr().err
    assert len(err.splitlines()) == 1 and err.startswith("urdf-inertia: error: ")
    assert "--max-faces" in err and "'many'" in err  # names the option and the bad value


# --- determinism -----------------------------------------------------------------------

def test_same_input_gives_identical_bytes(workdir, capsys):
    outputs = []
    for i in range(3):
        out = workdir / f"out{i}.urdf"
        rc, _, err = run(["fix", "--all", str(workdir / "r.urdf"), "-o", str(out), "-q",
                          "--no-cache"], capsys)
        assert rc == 0, err
        outputs.append(out.read_bytes())
    assert outputs[0] != (workdir / "r.urdf").read_bytes()
    assert outputs[0] == outputs[1] == outputs[2]


@pytest.mark.parametrize("chunk", [5, 7, 64, 1 << 20])
def test_face_count_scan_is_exact_across_chunk_boundaries(chunk, monkeypatch):
    import io

    import trimesh

    monkeypatch.setattr(mesh_io, "_CHUNK", chunk)
    box = trimesh.creation.box((1, 1, 1))
    for suffix, data in [
        (".stl", box.export(file_type="stl_ascii")),
        (".obj", box.export(file_type="obj")),
        (".dae", box.export(file_type="dae")),
        (".ply", box.export(file_type="ply")),
        (".off", box.export(file_type="off")),
        (".stl", box.export(file_type="stl")),
    ]:
        raw = data.encode() if isinstance(data, str) else data
        assert mesh_io.declared_faces(io.BytesIO(raw), suffix, len(raw)) == 12, suffix


def test_many_comments_and_no_declaration_read_in_linear_time(tmp_path):
    """The prolog's declaration finder must not backtrack over comments and indentation: a
    file with a leading comment, no ``<?xml`` and indented comments in its body took 5 s
    with 2 of them and never ended with 6 (a MuJoCo include of the Franka kitchen does this).
    Run in a child so that a regression fails on the timeout instead of hanging the suite."""
    import subprocess
    import sys

    body = "".join(f"  <!-- part {i} -->\n{' ' * 24}<link name='l{i}'/>\n" for i in range(400))
    path = tmp_path / "commented.urdf"
    path.write_text(f"<!-- licence -->\n<robot name='r'>\n{body}</robot>\n", encoding="utf-8")
    code = ("import sys; from urdfinertia.descriptions.xml import parse_document; "
            "root = parse_document(open(sys.argv[1], 'rb').read(), sys.argv[1], ('robot',)); "
            "print(len(root.findall('link')))")
    done = subprocess.run([sys.executable, "-c", code, str(path)], capture_output=True,
                          text=True, timeout=30)
    assert done.returncode == 0, done.stderr
    assert done.stdout.strip() == "400"
