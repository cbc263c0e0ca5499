"""Robots as they really come: one bad element never sinks a robot (issue 13).

One case per cause seen in 316 real URDFs. Each starts from ``tests/data/broken/clean.urdf``
(links base, arm, hand, tool), damages it the way real files are damaged, runs ``fix`` and
asserts: the exit code, the output is written, a dropped element is named with its file and
line, and every link is written exactly as the clean file's fix writes it (the damaged
element is dropped, so the rest of its link is what the clean file has).
"""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import pytest

from urdfinertia import cli
from urdfinertia.descriptions.urdf.write import scan_links

DATA = Path(__file__).parent / "data" / "broken"
BAD = "<!-- BAD ELEMENT -->"


@pytest.fixture
def folder(tmp_path, monkeypatch) -> Path:
    monkeypatch.setenv("URDFINERTIA_CACHE_DIR", str(tmp_path / "cache"))
    robot = tmp_path / "robot"
    robot.mkdir()
    for name in ("clean.urdf", "cube.stl", "flat.stl"):
        shutil.copy(DATA / name, robot / name)
    return robot


def fix(urdf: Path, capsys, *extra: str) -> tuple[int, str, Path]:
    out = urdf.with_name(urdf.stem + ".out.urdf")
    # a constant density: the mass prior reads the whole robot's size and layout, which a
    # dropped element elsewhere changes by design (the prior's own tests: test_mass_prior)
    code = cli.main(["fix", "--all", str(urdf), "-o", str(out), "-q", "--no-cache",
                     "--density", "1000", *extra])
    return code, capsys.readouterr().err, out


def inertials(document: bytes) -> dict[str, bytes]:
    """Each link's <inertial> text in a document (b"" for a link without one)."""
    spans = scan_links(document)
    return {name: document[s.inertial[0]:s.inertial[1]] if s.inertial else b""
            for name, s in spans.items()}


@pytest.fixture
def clean_inertials(folder, capsys) -> dict[str, bytes]:
    code, err, out = fix(folder / "clean.urdf", capsys)
    assert code == 0, err
    found = inertials(out.read_bytes())
    assert all(found[name] for name in ("base", "arm", "hand")) and found["tool"] == b""
    return found


def line_of(text: str, needle: str) -> int:
    return text[:text.index(needle)].count("\n") + 1


# (id, element added to link 'arm', cause words)
DROPPED = [
    ("zero-radius sphere", '<collision><geometry><sphere radius="0.00"/></geometry>'
                           "</collision>", "must be positive"),
    ("negative box size", '<collision><geometry><box size="0.1 -0.1 0.1"/></geometry>'
                          "</collision>", "must be positive"),
    ("4 numbers for 3", '<collision><origin xyz="0 0 0 1"/><geometry><box size="1 1 1"/>'
                        "</geometry></collision>", "needs 3 numbers"),
    ("optenv in an origin", '<collision><origin xyz="0 0 $(optenv Z 0)"/><geometry>'
                            '<box size="1 1 1"/></geometry></collision>', "unexpanded"),
    ("unexpanded mesh path", '<collision><geometry><mesh filename="$(arg tool_mesh_dir)/x.stl"'
                             "/></geometry></collision>", "unexpanded substitution"),
    ("mesh not shipped", '<collision><geometry><mesh filename="meshes/not_shipped.stl"/>'
                         "</geometry></collision>", "mesh file not found"),
    ("flat marker mesh", '<collision><geometry><mesh filename="flat.stl"/></geometry>'
                         "</collision>", "no volume"),
    ("plane", '<collision><geometry><plane normal="0 0 1"/></geometry></collision>',
     "unsupported geometry <plane>"),
    ("unknown shape", '<collision><geometry><torus r="1"/></geometry></collision>',
     "unsupported geometry <torus>"),
    ("two shapes", '<collision><geometry><box size="1 1 1"/><sphere radius="1"/></geometry>'
                   "</collision>", "exactly one shape"),
]


@pytest.mark.parametrize(("element", "words"), [d[1:] for d in DROPPED],
                         ids=[d[0] for d in DROPPED])
def test_a_bad_element_is_dropped_and_the_rest_computed(element, words, folder, capsys,
                                                        clean_inertials):
    text = (folder / "clean.urdf").read_text().replace(BAD, element)
    urdf = folder / "r.urdf"
    urdf.write_text(text)
    code, err, out = fix(urdf, capsys)
    # a mesh that is not there leaves the link unverified: exit 1, as check's
    assert code == (1 if "not_shipped" in element else 0), err
    line = line_of(text, element)
    assert f"r.urdf:{line}: link 'arm' collision[2]: " in err, err
    assert words in err and "(element dropped; UI" in err, err
    assert inertials(out.read_bytes()) == clean_inertials
    assert urdf.read_text() == text  # the input is never modified
    # --strict: all or nothing, the same element named in one line
    code, err, _ = fix(urdf, capsys, "--strict")
    assert code == 2 and len(err.splitlines()) == 1 and f"r.urdf:{line}:" in err, err


def test_a_link_with_no_usable_geometry_is_left_and_listed(folder, capsys, clean_inertials):
    text = (folder / "clean.urdf").read_text().replace(
        '<sphere radius="0.04"/>', '<mesh filename="meshes/not_shipped.stl"/>')
    urdf = folder / "r.urdf"
    urdf.write_text(text)
    report = folder / "r.json"
    code, err, out = fix(urdf, capsys, "--json", str(report))
    assert code == 1, err
    hand_line = line_of(text, '<link name="hand">')
    inertial_line = hand_line + 1
    assert "left as it was: " in err
    assert f"r.urdf:{inertial_line}: link 'hand': no usable geometry" in err
    assert "not_shipped.stl" in err and "1 of 4 links left as they were" in err
    written = inertials(out.read_bytes())
    original = inertials(urdf.read_bytes())
    assert written["hand"] == original["hand"]  # exactly as it was
    assert {k: v for k, v in written.items() if k != "hand"} == \
        {k: v for k, v in clean_inertials.items() if k != "hand"}
    doc = json.loads(report.read_text())
    assert doc["exit_code"] == 1
    assert doc["links_left"] == [{"link": "hand", "line": inertial_line,
                                  "reason": doc["links_left"][0]["reason"]}]
    (hand,) = [link for link in doc["links"] if link["link"] == "hand"]
    assert hand["status"] == "left"
    assert [f["code"] for f in hand["findings"] if f["element"]] == ["mesh-unresolved"]


DOCUMENT = [
    ("xml version 0.0", lambda t: t.replace('version="1.0"', 'version="0.0"'), "version"),
    ("declaration after whitespace", lambda t: "\n  " + t, "not at the very start"),
    ("declaration after a BOM and newline", lambda t: "\ufeff\n" + t, "not at the very start"),
    ("declaration after a licence comment", lambda t: "<!-- licence\n -->\n" + t,
     "not at the very start"),
    ("undeclared prefixes", lambda t: t.replace(
        '<limit lower', '<drake:limit drake:x="1" lower').replace(
        "</robot>", '<drake:collision_filter_group drake:name="g"/>\n</robot>'),
     "undeclared namespace prefix"),
    ("trailing content", lambda t: t + "</robot>\n<junk/>", "after the root element"),
    ("comma in a joint origin", lambda t: t.replace('xyz="0 0 0.5"', 'xyz="0, 0, 0.5"'),
     "commas"),
    ("4 numbers in a joint origin", lambda t: t.replace('xyz="0 0 0.5"', 'xyz="0 0 0.5 1"'),
     "needs 3 numbers"),
]


@pytest.mark.parametrize(("damage", "words"), [d[1:] for d in DOCUMENT],
                         ids=[d[0] for d in DOCUMENT])
def test_what_urdfdom_reads_is_read(damage, words, folder, capsys, clean_inertials):
    text = damage((folder / "clean.urdf").read_text())
    urdf = folder / "r.urdf"
    urdf.write_bytes(text.encode("utf-8"))
    code, err, out = fix(urdf, capsys)
    assert code == 0, err
    assert words in err and "urdf-inertia: warning: " in err, err
    assert inertials(out.read_bytes()) == clean_inertials
    # the bytes around the inertials are the input's own (prefixes, junk and all)
    assert out.read_bytes().startswith(text.encode("utf-8")[:20])


@pytest.mark.parametrize("document", [
    b"not xml at all", b'<?xml version="1.0"?>\n<robot name="r"><link name="a">',
    b'<robot name="r"><link name="a"/></robot>'.replace(b"</robot>", b""),
])
def test_not_xml_or_truncated_inside_the_root_stays_an_error(document, folder, capsys):
    urdf = folder / "r.urdf"
    urdf.write_bytes(document)
    code, err, out = fix(urdf, capsys)
    assert code == 2 and len(err.splitlines()) == 1 and not out.exists(), err


def test_relative_mesh_references_follow_the_output(folder, capsys, tmp_path):
    elsewhere = tmp_path / "elsewhere" / "deeper"
    elsewhere.mkdir(parents=True)
    out = elsewhere / "r.urdf"
    code = cli.main(["fix", "--all", str(folder / "clean.urdf"), "-o", str(out), "-q",
                     "--no-cache"])
    err = capsys.readouterr().err
    assert code == 0 and "1 relative mesh reference(s) rewritten" in err, err
    assert b'filename="../../robot/cube.stl"' in out.read_bytes()
    # the output resolves to the same mesh: fixing it again gives the same inertials
    again = tmp_path / "again.urdf"
    assert cli.main(["fix", "--all", str(out), "-o", str(again), "-q", "--no-cache",
                     "--keep-mesh-paths"]) == 0
    assert inertials(again.read_bytes()) == inertials(out.read_bytes())
    kept = elsewhere / "kept.urdf"
    assert cli.main(["fix", "--all", str(folder / "clean.urdf"), "-o", str(kept), "-q",
                     "--no-cache", "--keep-mesh-paths"]) == 0
    assert b'filename="cube.stl"' in kept.read_bytes()
