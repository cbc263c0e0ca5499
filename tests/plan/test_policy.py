"""Which links ``fix`` recomputes by default, and what it keeps: the expected values are
written by hand (the README's policy table), never built by the functions under test."""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pytest

from urdfinertia.body.options import FixOptions
from urdfinertia.body.spec import parse_spec
from urdfinertia.cli import main
from urdfinertia.inertia import primitives
from urdfinertia.plan.fix import fix_file

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
    # at a constant 1000 kg/m^3 (--density); the default's mass prior: test_mass_prior.py
    c = {r.name: r for r in fix_file(path, FixOptions(density_prior=False)).links}["c"]
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
    # the link's mass from the prior, and what a constant 1000 kg/m^3 would have given
    assert "warning: total mass 7.2 kg -> " in err, err
    assert "mass prior: 1 link(s) with no mass: 6 kg at 1000 kg/m³" in err, err
    clean = write(tmp_path, robot(*CLEAN))
    assert main(["fix", str(clean), "-q", "-o", str(tmp_path / "o.urdf")]) == 0
    assert capsys.readouterr().err == ""  # quiet and nothing to warn about


def written(data: bytes, name: str) -> tuple[float, list[float], list[float]]:
    """Mass, CoM and the tensor's (ixx, iyy, izz, ixy, ixz, iyz) of link ``name`` as
    written in ``data`` (read back, not computed)."""
    span = inertial_span(data, name).decode()

    def attr(tag: str, key: str) -> str:
        m = re.search(rf"<{tag}\b[^>]*\b{key}=\"([^\"]*)\"", span)
        assert m is not None, (tag, key, span)
        return m.group(1)

    com = [float(x) for x in attr("origin", "xyz").split()]
    tensor = [float(attr("inertia", k)) for k in ("ixx", "iyy", "izz", "ixy", "ixz", "iyz")]
    return float(attr("mass", "value")), com, tensor


#: The box's tensor per kg, by hand: (b^2 + c^2) / 12 etc. for 0.1 x 0.2 x 0.3 m.
PER_KG = (0.13 / 12, 0.10 / 12, 0.05 / 12)


def test_all_recomputes_every_link_with_geometry(tmp_path):
    # --all: every link with geometry from its geometry, the written mass kept, the CoM the
    # box centre; the massless cover gets 1000 kg/m^3 x 0.006 m^3 = 6 kg
    text = robot(*CLEAN, link("c", BROKEN["triangle-inequality"]), joint("c", "b"),
                 link("cover"), joint("cover", "b", "fixed"))
    path = write(tmp_path, text)
    out = fix_file(path, FixOptions(recompute="all", density_prior=False)).output
    expected = {"base": 5.0, "a": 1.5, "b": 0.7, "c": 0.7, "cover": 6.0}
    for name, mass in expected.items():
        m, com, tensor = written(out, name)
        assert m == pytest.approx(mass, rel=1e-15) and com == [0.0, 0.0, 0.0]
        assert tensor[:3] == pytest.approx([mass * k for k in PER_KG], rel=1e-12)
        assert tensor[3:] == [0.0, 0.0, 0.0]
    assert main(["fix", "--all", str(path), "-q", "-o", str(tmp_path / "o.urdf"),
                 "--density", "1000"]) == 0
    assert (tmp_path / "o.urdf").read_bytes() == out


#: The README's policy table, one row per case: (link body, geometry, joint kind) ->
#: (status, decision, mass, CoM, (ixx, iyy, izz)) written by hand. None: kept byte for byte.
TABLE = {
    "plausible": ((inertial(0.7), True, "revolute"),
                  ("kept", "kept: plausible", None)),
    "missing inertial on a moving link": (("", True, "revolute"), (
        "recomputed", "recomputed: missing-inertial",
        (6.0, [0.0, 0.0, 0.0], (0.065, 0.05, 0.025)))),
    "zero tensor, mass and CoM kept": ((inertial(2.5, com="0.02 -0.03 0.05",
                                                 diag=("0", "0", "0")), True, "revolute"), (
        "recomputed", "recomputed: inertia-zero",
        (2.5, [0.02, -0.03, 0.05], (0.325 / 12, 0.25 / 12, 0.125 / 12)))),
    "CoM outside the geometry": ((inertial(0.7, com="3 0 0"), True, "revolute"), (
        "recomputed", "recomputed: com-outside-geometry",
        (0.7, [0.0, 0.0, 0.0], (0.091 / 12, 0.07 / 12, 0.035 / 12)))),
    "massless on a fixed joint": (("", True, "fixed"), (
        "untouched", "massless, on a fixed joint: left as it is", None)),
    "invalid, no geometry: minimal lift": ((BROKEN["triangle-inequality"], False, "revolute"), (
        "repaired", "repaired: triangle-inequality; no geometry to recompute from",
        (0.7, [0.0, 0.0, 0.0], (0.009, 0.001, 0.01)))),
}


@pytest.mark.parametrize("case", sorted(TABLE))
def test_the_readme_policy_table(tmp_path, case):
    (body, geometry, kind), (status, decision, values) = TABLE[case]
    path = write(tmp_path, robot(*CLEAN, link("c", body, geometry=geometry),
                                 joint("c", "b", kind)))
    # masses at a constant 1000 kg/m^3 (--density), to be written by hand
    result = fix_file(path, FixOptions(density_prior=False))
    c = result.link("c")
    assert (c.status, c.decision) == (status, decision)
    if values is None:
        assert result.output == path.read_bytes()
        return
    mass, com, diag = values
    m, written_com, tensor = written(result.output, "c")
    # round-off of the volume's product only (1000 x 0.1 x 0.2 x 0.3 is 6.000000000000001)
    assert m == pytest.approx(mass, rel=1e-15)
    assert written_com == pytest.approx(com, abs=1e-15)
    # the lift leaves a margin of 1e-9 of the largest moment, so that A + B >= C survives
    # the writing's rounding; the solid's tensors are exact to round-off
    assert tensor[:3] == pytest.approx(list(diag), rel=1e-8)
    assert tensor[3:] == pytest.approx([0.0, 0.0, 0.0], abs=1e-15)


def test_a_mesh_unit_slip_keeps_the_inertial(tmp_path):
    # the geometry in millimetres without scale: 0.7 kg in 6e6 m^3 is 1.2e-7 kg/m^3, and
    # x1e9 gives 117 kg/m^3: the geometry, not the inertial, is wrong
    path = write(tmp_path, robot(*CLEAN, link("c", inertial(0.7)), joint("c", "b"))
                 .replace('<box size="0.1 0.2 0.3"/></geometry></collision>\n  </link>\n'
                          '  <joint name="j_c"',
                          '<box size="100 200 300"/></geometry></collision>\n  </link>\n'
                          '  <joint name="j_c"'))
    result = fix_file(path, FixOptions())
    assert result.link("c").decision == ("kept: implausible density explained by the "
                                         "geometry: mesh in mm without scale 0.001?")
    assert result.output == path.read_bytes()


def test_a_root_without_inertial_says_how_it_would_be_recomputed(tmp_path):
    path = write(tmp_path, robot(*CLEAN, base=""))
    assert fix_file(path, FixOptions()).links[0].decision == (
        "root link without <inertial>: left as it is (a floating base is recomputed only "
        "when named)")


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
