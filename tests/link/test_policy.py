"""Which links ``fix`` recomputes by default, and what it keeps (issue 14)."""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pytest

from urdfinertia.cli import main
from urdfinertia.descriptions.formats import format_of, read_description, robot_from_bytes
from urdfinertia.inertia import primitives
from urdfinertia.link.fix import compute_link, fix_file
from urdfinertia.link.options import FixOptions
from urdfinertia.link.spec import parse_spec

SIZE = (0.1, 0.2, 0.3)  # m, the box every test link is made of
BOX_I = primitives.box(SIZE, 1.0).inertia / primitives.box(SIZE, 1.0).mass  # per kg


def inertial(mass: float | str = 2.0, com: str = "0 0 0", diag=None, off=(0, 0, 0)) -> str:
    d = diag if diag is not None else tuple(repr(float(mass) * float(BOX_I[k, k]))
                                            for k in range(3))
    return (f'<inertial><origin xyz="{com}" rpy="0 0 0"/><mass value="{mass}"/>'
            f'<inertia ixx="{d[0]}" ixy="{off[0]}" ixz="{off[1]}" iyy="{d[1]}" iyz="{off[2]}" '
            f'izz="{d[2]}"/></inertial>')


def link(name: str, body: str = "", xyz: str = "0 0 0", geometry: bool = True) -> str:
    geo = (f'<collision><origin xyz="{xyz}"/><geometry><box size="{" ".join(map(str, SIZE))}"/>'
           '</geometry></collision>') if geometry else ""
    return f'<link name="{name}">\n    {body}\n    {geo}\n  </link>'


def joint(child: str, parent: str = "base", kind: str = "revolute") -> str:
    limit = '<limit lower="-1" upper="1" effort="1" velocity="1"/>' if kind != "fixed" else ""
    return (f'<joint name="j_{child}" type="{kind}"><parent link="{parent}"/>'
            f'<child link="{child}"/><axis xyz="0 0 1"/>{limit}</joint>')


def robot(*parts: str, base: str = inertial(5.0)) -> str:
    return ('<?xml version="1.0"?>\n<robot name="t">\n  ' + link("base", base) + "\n  "
            + "\n  ".join(parts) + "\n</robot>\n")


CLEAN = [link("a", inertial(1.5)), joint("a"), link("b", inertial(0.7)), joint("b", "a")]


def write(tmp_path: Path, text: str) -> Path:
    path = tmp_path / "r.urdf"
    path.write_text(text)
    return path


def inertial_span(data: bytes, name: str) -> bytes:
    m = re.search(rb'<link name="' + name.encode() + rb'">.*?</link>', data, re.DOTALL)
    assert m is not None
    return m.group(0)


def test_a_clean_robot_is_byte_identical(tmp_path):
    path = write(tmp_path, robot(*CLEAN))
    result = fix_file(path, FixOptions())
    assert result.output == path.read_bytes()
    assert {r.status for r in result.links} == {"kept"}
    assert all(r.decision == "kept: plausible" for r in result.links)


BROKEN = {
    # NaN and negative values are refused by the strict reader before any policy applies
    "mass-not-positive": inertial(0.0, diag=("0.001", "0.001", "0.001")),
    "inertia-zero": inertial(0.7, diag=("0", "0", "0")),
    "inertia-not-positive-definite": inertial(0.7, diag=("0.001", "0.001", "0.001"),
                                              off=("0.002", "0", "0")),
    "triangle-inequality": inertial(0.7, diag=("0.001", "0.001", "0.01")),
    "placeholder-inertia": inertial(0.7, diag=("1", "1", "1")),
    "com-outside-geometry": inertial(0.7, com="3 0 0"),
    "inertia-vs-geometry": inertial(0.7, diag=("5", "5", "5"), off=("0.1", "0", "0")),
}


@pytest.mark.parametrize("code", sorted(BROKEN))
def test_each_broken_inertial_is_recomputed_and_only_it(tmp_path, code):
    text = robot(*CLEAN, link("c", BROKEN[code]), joint("c", "b"))
    path = write(tmp_path, text)
    result = fix_file(path, FixOptions())
    by_name = {r.name: r for r in result.links}
    assert by_name["c"].status == "recomputed"
    assert code in by_name["c"].decision
    for name in ("base", "a", "b"):
        assert by_name[name].status == "kept"
        assert inertial_span(result.output, name) == inertial_span(path.read_bytes(), name)
    # the output passes check
    out = tmp_path / "out.urdf"
    out.write_bytes(result.output)
    assert main(["check", str(out), "-q"]) == 0


def test_missing_inertial_on_a_moving_link_is_computed(tmp_path):
    path = write(tmp_path, robot(*CLEAN, link("c"), joint("c", "b")))
    c = {r.name: r for r in fix_file(path, FixOptions()).links}["c"]
    assert c.status == "recomputed" and "missing-inertial" in c.decision
    assert c.assembly.total.mass == pytest.approx(1000 * np.prod(SIZE))


def test_mass_and_com_kept_and_tensor_is_the_solids_own_at_the_kept_com(tmp_path):
    # a zero tensor (UR's controllers ship these): mass and CoM inside the box are kept;
    # the tensor is the box's central tensor at that mass, not moved by the parallel axis
    com = np.array([0.02, -0.03, 0.05])
    body = inertial(2.5, com=" ".join(repr(float(x)) for x in com), diag=("0", "0", "0"))
    path = write(tmp_path, robot(*CLEAN, link("c", body, xyz="0.01 0 0"), joint("c", "b")))
    c = {r.name: r for r in fix_file(path, FixOptions()).links}["c"]
    total = c.assembly.total
    assert total.mass == 2.5
    np.testing.assert_array_equal(total.com, com)
    np.testing.assert_allclose(total.inertia, 2.5 * BOX_I, rtol=1e-12)
    assert c.kept == ("mass", "com") and c.derived == ("tensor",)
    offset = np.linalg.norm(com - [0.01, 0, 0]) / np.linalg.norm(SIZE)
    assert c.error_bar.basis == "offset" and c.error_bar.offset == pytest.approx(offset)


def test_a_com_outside_the_geometry_is_derived(tmp_path):
    path = write(tmp_path, robot(*CLEAN, link("c", inertial(0.7, com="3 0 0")),
                                 joint("c", "b")))
    c = {r.name: r for r in fix_file(path, FixOptions()).links}["c"]
    assert c.kept == ("mass",) and c.derived == ("com", "tensor")
    np.testing.assert_allclose(c.assembly.total.com, 0, atol=1e-15)
    assert c.error_bar.basis == "model"


@pytest.mark.parametrize("body", ["", '<inertial><mass value="0"/>'
                                      '<inertia ixx="0" ixy="0" ixz="0" iyy="0" iyz="0" izz="0"/>'
                                      '</inertial>'])
def test_a_massless_fixed_joint_child_stays_massless(tmp_path, body):
    path = write(tmp_path, robot(*CLEAN, link("cover", body), joint("cover", "b", "fixed")))
    result = fix_file(path, FixOptions())
    cover = {r.name: r for r in result.links}["cover"]
    assert cover.assembly is None
    assert cover.decision == "massless, on a fixed joint: left as it is"
    assert result.output == path.read_bytes()
    # --all gives it mass, as before the policy
    assert fix_file(path, FixOptions(recompute="all")).output != path.read_bytes()


def test_a_token_mass_frame_on_a_fixed_joint_keeps_its_zero_tensor(tmp_path):
    """so101's gripper_frame_link: 1e-9 kg with a zero tensor and no geometry. MuJoCo takes
    it as written and refuses a tiny made-up tensor, so it is left as it is."""
    frame = link("tip", inertial("1e-09", diag=("0", "0", "0")), geometry=False)
    path = write(tmp_path, robot(*CLEAN, frame, joint("tip", "b", "fixed")))
    result = fix_file(path, FixOptions())
    tip = {r.name: r for r in result.links}["tip"]
    assert tip.assembly is None and tip.decision.startswith("frame on a fixed joint")
    assert result.output == path.read_bytes()
    # the same link on a moving joint is a body: it gets the minimal repair
    moving = write(tmp_path, robot(*CLEAN, frame, joint("tip", "b")))
    tip = {r.name: r for r in fix_file(moving, FixOptions()).links}["tip"]
    assert tip.status == "repaired"


def test_a_root_without_inertial_is_left_and_reported(tmp_path):
    path = write(tmp_path, robot(*CLEAN, base=""))
    base = fix_file(path, FixOptions()).links[0]
    assert base.assembly is None and base.decision.startswith("root link without <inertial>")
    assert {r.name for r in fix_file(path, FixOptions(recompute="links", links=("base",))
                                     ).links if r.status == "recomputed"} == {"base"}


def test_total_mass_change_is_warned(tmp_path, capsys):
    path = write(tmp_path, robot(*CLEAN, link("c"), joint("c", "b")))
    assert main(["fix", str(path), "-q", "-o", str(tmp_path / "o.urdf")]) == 0
    err = capsys.readouterr().err
    assert "warning: total mass 7.2 kg -> 13.2 kg" in err, err
    clean = write(tmp_path, robot(*CLEAN))
    assert main(["fix", str(clean), "-q", "-o", str(tmp_path / "o.urdf")]) == 0
    assert capsys.readouterr().err == ""  # quiet and nothing to warn about


def test_all_equals_the_pre_policy_computation(tmp_path):
    # --all is every link through compute_link and the patch, as before the policy
    text = robot(*CLEAN, link("c", BROKEN["triangle-inequality"]), joint("c", "b"),
                 link("cover"), joint("cover", "b", "fixed"))
    path = write(tmp_path, text)
    options = FixOptions(recompute="all")
    robot_, data = read_description(path)
    old = [compute_link(lk, options, None, path.parent) for lk in robot_.links]  # type: ignore
    expected = format_of(robot_).patch(data, {r.name: (r.assembly.total, r.size)
                                              for r in old if r.assembly is not None})
    # the same values; the bytes differ only where a kept value keeps its own text
    got = fix_file(path, options).output
    for want, have in zip(robot_from_bytes(expected, path).links,
                          robot_from_bytes(got, path).links, strict=True):
        assert (want.inertial is None) == (have.inertial is None)
        if want.inertial is not None:
            assert have.inertial.mass == want.inertial.mass
            assert have.inertial.origin.xyz == want.inertial.origin.xyz
            assert np.array_equal(have.inertial.tensor_in_link(),
                                  want.inertial.tensor_in_link())
    assert main(["fix", "--all", str(path), "-q", "-o", str(tmp_path / "o.urdf")]) == 0
    assert (tmp_path / "o.urdf").read_bytes() == got


def test_links_named_in_a_spec_are_always_recomputed(tmp_path):
    path = write(tmp_path, robot(*CLEAN))
    spec = parse_spec("[links.a.elements.e.parts.p]\ncollision = 0\ndensity = 500\n",
                      tmp_path / "s.toml")
    result = fix_file(path, FixOptions(spec=spec))
    by = {r.name: r for r in result.links}
    assert by["a"].status == "recomputed" and by["a"].decision == "recomputed: named in the spec"
    assert by["a"].assembly.total.mass == pytest.approx(500 * np.prod(SIZE))
    assert by["b"].status == "kept"


def test_invalid_without_geometry_is_repaired(tmp_path):
    body = inertial(0.7, diag=("0.001", "0.001", "0.01"))
    path = write(tmp_path, robot(*CLEAN, link("c", body, geometry=False), joint("c", "b")))
    c = {r.name: r for r in fix_file(path, FixOptions()).links}["c"]
    assert c.status == "repaired" and c.decision.startswith("repaired: triangle-inequality")
    assert c.assembly.total.is_physical() and c.assembly.total.mass == 0.7


def test_check_and_compare_show_the_decision(tmp_path, capsys):
    path = write(tmp_path, robot(*CLEAN, link("c", BROKEN["placeholder-inertia"]),
                                 joint("c", "b")))
    main(["check", str(path)])
    out = capsys.readouterr().out
    assert "would be recomputed: placeholder-inertia" in out
    main(["compare", str(path), "--all", "-q", "--json", str(tmp_path / "c.json")])
    text = (tmp_path / "c.json").read_text()
    assert '"fix": "would be kept: plausible"' in text
    assert '"fix": "would be recomputed: placeholder-inertia' in text


def test_comments_inside_a_rewritten_inertial_are_kept(tmp_path):
    body = ('<inertial>\n      <!-- measured on the scale -->\n      <mass value="0.7"/>\n'
            '      <!-- from CAD -->\n      <inertia ixx="1" ixy="0" ixz="0" iyy="1" iyz="0" '
            'izz="1"/>\n      <!-- end -->\n    </inertial>')
    path = write(tmp_path, robot(*CLEAN, link("c", body), joint("c", "b")))
    out = fix_file(path, FixOptions()).output.decode()
    span = inertial_span(out.encode(), "c").decode()
    assert span.index("<!-- measured on the scale -->") < span.index("<mass")
    assert span.index("<mass") < span.index("<!-- from CAD -->") < span.index("<inertia ")
    assert span.index("<inertia ") < span.index("<!-- end -->") < span.index("</inertial>")
