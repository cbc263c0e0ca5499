"""total_mass.py: target masses for the robot and its subtrees (fix --total-mass, spec keys).

The fixture's links: ``base`` 2 kg kept, ``upper`` (0.1 x 0.1 x 0.4 m box) and ``hand``
(0.1 m cube) derived at the default 1000 kg/m^3 (4 kg and 1 kg), ``finger`` 0.1 kg kept.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

import urdfinertia
from urdfinertia.body.options import FixOptions
from urdfinertia.body.spec import parse_spec
from urdfinertia.cli import main
from urdfinertia.errors import SpecError
from urdfinertia.plan.fix import fix_file
from urdfinertia.plan.total_mass import MassTargetError

DATA = Path(__file__).resolve().parents[1] / "data" / "total_mass"
ARM = DATA / "arm.urdf"
#: Products and sums of a few closed forms: only round-off separates the two sides.
RTOL = 1e-12


def _masses(result) -> dict[str, float]:
    return {r.name: r.after.mass for r in result.links}


def test_derived_masses_scale_and_kept_ones_stay() -> None:
    plain = fix_file(ARM)
    result = fix_file(ARM, FixOptions(total_mass=4.6))
    m, p = _masses(result), _masses(plain)
    # kept 2.1 kg; the derived (the mass prior's, 5 kg at 1000 kg/m^3) must become 2.5 kg
    derived = p["upper"] + p["hand"]
    assert 2.5 < derived < 7.1
    k = 2.5 / derived
    assert m["base"] == 2.0 and m["finger"] == 0.1
    assert m["upper"] == pytest.approx(k * p["upper"], rel=RTOL)
    assert m["hand"] == pytest.approx(k * p["hand"], rel=RTOL)
    assert sum(m.values()) == pytest.approx(4.6, rel=RTOL)
    # the tensor scales with the mass, the CoM stays
    for name in ("upper", "hand"):
        old, new = plain.link(name).after, result.link(name).after
        np.testing.assert_allclose(new.inertia, k * old.inertia, rtol=RTOL)
        np.testing.assert_allclose(new.com, old.com, atol=1e-15)
    # at a constant density (--density) the derived 5 kg scale by 0.5
    water = _masses(fix_file(ARM, FixOptions(total_mass=4.6, density_prior=False)))
    assert water["upper"] == pytest.approx(2.0, rel=RTOL)
    assert water["hand"] == pytest.approx(0.5, rel=RTOL)
    # kept links keep their bytes: the written base and finger are untouched
    assert result.output.count(b'<mass value="2.0"/>') == 1
    assert result.output.count(b'<mass value="0.1"/>') == 1
    (target,) = result.targets
    assert (target.before, target.target) == (2.1, 4.6)
    assert target.unscaled == pytest.approx(2.1 + derived, rel=RTOL)
    assert target.after == pytest.approx(4.6, rel=RTOL)
    assert set(target.scaled) == {"upper", "hand"}


def test_scale_kept_scales_every_mass() -> None:
    # at a constant 1000 kg/m^3 the derived links weigh 5 kg: 7.1 kg -> 3.55 kg, a half
    result = fix_file(ARM, FixOptions(total_mass=3.55, scale_kept=True, density_prior=False))
    m = _masses(result)
    assert m["base"] == pytest.approx(1.0, rel=RTOL)
    assert m["finger"] == pytest.approx(0.05, rel=RTOL)
    np.testing.assert_allclose(result.link("base").after.inertia,
                               np.eye(3) * 0.5 * 0.00333333333, rtol=RTOL)
    again = fix_file(ARM, FixOptions(total_mass=3.55, scale_kept=True))
    reread = urdfinertia.fix(_write(again.output), total_mass=3.55, scale_kept=True)
    assert sum(_masses(reread).values()) == pytest.approx(3.55, rel=1e-9)


def _write(data: bytes) -> Path:
    import tempfile

    path = Path(tempfile.mkdtemp()) / "arm.urdf"
    path.write_bytes(data)
    return path


@pytest.mark.parametrize("target", [2.1, 1.0])
def test_refused_when_kept_masses_reach_the_target(target: float) -> None:
    with pytest.raises(MassTargetError, match="kept masses alone weigh 2.1 kg"):
        fix_file(ARM, FixOptions(total_mass=target))


def test_refused_when_nothing_can_be_scaled(tmp_path: Path) -> None:
    urdf = tmp_path / "kept.urdf"
    text = ARM.read_text()
    start, end = text.index('<link name="upper">'), text.index('<link name="finger">')
    urdf.write_text(text[:start] + '<link name="upper"/><link name="hand"/>' + text[end:])
    with pytest.raises(MassTargetError, match="no derived mass to scale .*--scale-kept"):
        fix_file(urdf, FixOptions(total_mass=5.0))


def test_cli_refusal_writes_nothing(tmp_path: Path, capsys) -> None:
    out = tmp_path / "out.urdf"
    assert main(["fix", str(ARM), "-o", str(out), "--total-mass", "2"]) == 2
    assert not out.exists()
    assert "kept masses alone weigh 2.1 kg" in capsys.readouterr().err


def test_cli_summary_and_json(tmp_path: Path, capsys) -> None:
    out, js = tmp_path / "out.urdf", tmp_path / "out.json"
    assert main(["fix", str(ARM), "-o", str(out), "--total-mass", "4.6", "--json",
                 str(js), "--density", "1000"]) == 0
    err = capsys.readouterr().err
    assert "total mass target 4.6 kg: before 2.1 kg, after 4.6 kg" in err
    doc = json.loads(js.read_text())
    assert doc["total_mass"]["target"] == 4.6
    assert doc["total_mass"]["after"] == pytest.approx(4.6, rel=RTOL)
    assert doc["mass_targets"][0]["factor"] == pytest.approx(0.5, rel=RTOL)
    reread = urdfinertia.check(out, geometry=False)
    assert reread is not None
    written = fix_file(out)  # the written file weighs the target
    assert sum(r.before.mass for r in written.links) == pytest.approx(4.6, rel=1e-9)


@pytest.mark.parametrize("argv", [["--total-mass", "-1"], ["--total-mass", "nan"],
                                  ["--scale-kept"]])
def test_cli_bad_arguments(argv: list[str], tmp_path: Path) -> None:
    out = tmp_path / "out.urdf"
    try:
        code = main(["fix", str(ARM), "-o", str(out), *argv])
    except SystemExit as exc:  # argparse's refusal
        code = exc.code
    assert code == 2 and not out.exists()


SUBTREE_SPEC = """
total_mass = 4.6
[subtree.hand]
mass = 0.35
"""


def test_subtree_target_then_total(tmp_path: Path) -> None:
    spec = parse_spec(SUBTREE_SPEC, tmp_path / "spec.toml")
    result = fix_file(ARM, FixOptions(spec=spec))
    m = _masses(result)
    # the hand subtree (hand + kept 0.1 kg finger) weighs 0.35 kg: hand 1 kg -> 0.25 kg
    assert m["hand"] == pytest.approx(0.25, rel=RTOL)
    assert m["hand"] + m["finger"] == pytest.approx(0.35, rel=RTOL)
    # then the robot: base 2 + hand subtree 0.35 fixed, upper 4 kg -> 2.25 kg
    assert m["upper"] == pytest.approx(2.25, rel=RTOL)
    assert sum(m.values()) == pytest.approx(4.6, rel=RTOL)
    assert [t.name for t in result.targets] == ["hand", None]
    # the option's target overrides the spec's whole-robot one
    over = fix_file(ARM, FixOptions(spec=spec, total_mass=5.0))
    assert sum(_masses(over).values()) == pytest.approx(5.0, rel=RTOL)


def test_subtree_below_its_kept_masses_is_refused(tmp_path: Path) -> None:
    spec = parse_spec("[subtree.hand]\nmass = 0.05\n", tmp_path / "spec.toml")
    with pytest.raises(MassTargetError, match="subtree 'hand': the kept masses alone "
                                              "weigh 0.1 kg"):
        fix_file(ARM, FixOptions(spec=spec))


@pytest.mark.parametrize(("text", "message"), [
    ("[subtree.hnd]\nmass = 1\n", r"subtree.hnd: the URDF 'arm' has no link 'hnd' "
                                  r"\(did you mean hand\?\)"),
    ("total_mas = 1\n", r"total_mas: unknown key \(did you mean 'total_mass'\?"),
    ("[subtree.hand]\nmas = 1\n", r"subtree.hand.mas: unknown key \(did you mean 'mass'\?"),
    ("[subtree.hand]\n", r"subtree.hand.mass: missing"),
    ("total_mass = -2\n", r"total_mass: must be a positive number \(kg\)"),
])
def test_spec_target_errors(text: str, message: str, tmp_path: Path) -> None:
    with pytest.raises(SpecError, match=message):
        fix_file(ARM, FixOptions(spec=parse_spec(text, tmp_path / "spec.toml")))


def test_explain_agrees_with_fix() -> None:
    """One answer: a single link's verdict carries the target's scaling too."""
    from urdfinertia.descriptions.formats import read_description
    from urdfinertia.plan.fix import link_verdict

    robot, _ = read_description(ARM)
    options = FixOptions(total_mass=4.6)
    one = link_verdict(robot, "upper", options)
    assert one.after.mass == pytest.approx(fix_file(ARM, options).link("upper").after.mass,
                                           rel=RTOL)


def test_cli_refuses_a_total_for_many_robots(tmp_path: Path, capsys) -> None:
    assert main(["fix", str(ARM), str(ARM), "-o", str(tmp_path / "out"),
                 "--total-mass", "3"]) == 2
    assert "--total-mass takes a single description" in capsys.readouterr().err
    assert not (tmp_path / "out").exists()


def test_spec_link_with_a_point_scales_whole(tmp_path: Path) -> None:
    """A spec link derived from a box and a point: both parts scale by the one factor."""
    spec = parse_spec("""
total_mass = 3.1
[links.upper.elements.body.parts.shell]
collision = 0
[links.upper.elements.body.parts.motor]
point = { xyz = [0, 0, 0.1], mass = 1.0 }
""", tmp_path / "spec.toml")
    plain = fix_file(ARM, FixOptions(spec=parse_spec(
        "[links.upper.elements.body.parts.shell]\ncollision = 0\n"
        "[links.upper.elements.body.parts.motor]\npoint = { xyz = [0, 0, 0.1], mass = 1.0 }\n",
        tmp_path / "plain.toml")))
    result = fix_file(ARM, FixOptions(spec=spec))
    # kept 2.1 kg; derived upper (4 kg box at 1000 kg/m^3 + 1 kg point) and hand (the mass
    # prior's) -> 1.0 kg: one factor for all
    k = 1.0 / (plain.link("upper").after.mass + plain.link("hand").after.mass)
    old, new = plain.link("upper"), result.link("upper")
    assert new.after.mass == pytest.approx(5.0 * k, rel=RTOL)
    np.testing.assert_allclose(new.after.inertia, k * old.after.inertia, rtol=1e-12)
    np.testing.assert_allclose(new.after.com, old.after.com, rtol=1e-12)
    assert [p.mass_properties.mass for p in new.assembly.parts] == pytest.approx(
        [4.0 * k, 1.0 * k], rel=RTOL)


@pytest.mark.parametrize("argv", [["--total-mass", "4.6"],
                                  ["--total-mass", "3.55", "--scale-kept"]])
def test_fix_of_the_fixed_file_changes_nothing(argv: list[str], tmp_path: Path) -> None:
    """A target already met is no refusal: the fixed file's masses are kept, not scaled."""
    once, twice = tmp_path / "once.urdf", tmp_path / "twice.urdf"
    assert main(["fix", str(ARM), "-o", str(once), "-q", *argv]) == 0
    assert main(["fix", str(once), "-o", str(twice), "-q", *argv]) == 0
    assert twice.read_bytes() == once.read_bytes()
