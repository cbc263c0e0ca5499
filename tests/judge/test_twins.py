"""Copies and mirror twins (``judge.twins``, judged with the robot in ``judge.robot``) on a
hand-made robot, and the name pairing."""

from __future__ import annotations

from pathlib import Path

import pytest

from urdfinertia.analysis.check import check_description
from urdfinertia.body.options import FixOptions
from urdfinertia.cache.library import MeshLibrary
from urdfinertia.descriptions.formats import read_description
from urdfinertia.judge.twins import twin_names
from urdfinertia.plan.fix import verdicts


def twin_findings(robot, meshes, options):  # noqa: ANN001, ANN201
    """The copy and twin findings of the robot's judgement, in link order."""
    found = verdicts(robot, options, meshes)
    return [f for r in found.links for f in r.findings
            if f.code in ("inertial-copied", "twins-disagree")]

TWINS = Path(__file__).resolve().parents[1] / "data" / "slips" / "twins.urdf"


@pytest.mark.parametrize(("name", "other"), [
    ("left_hip", "right_hip"), ("hip_l", "hip_r"), ("LHipPitch", "RHipPitch"),
    ("leg_left_1_link", "leg_right_1_link"), ("r_ankle_1", "l_ankle_1"),
    ("LF_FOOT", "RF_FOOT"), ("leftarm", "rightarm"), ("Right_thumb", "Left_thumb"),
])
def test_names_pair_left_and_right(name, other):
    assert other in twin_names(name)
    assert name in twin_names(other)


def test_names_without_a_side_have_no_twin():
    assert twin_names("base_link") == []
    assert twin_names("elbow") == []


@pytest.fixture(scope="module")
def findings():
    robot, _ = read_description(TWINS)
    return twin_findings(robot, MeshLibrary(), FixOptions())


def test_a_copy_is_named_with_its_source(findings):
    copies = [f for f in findings if f.code == "inertial-copied"]
    assert [f.link for f in copies] == ["left_foot"]
    assert "equals left_shin's (byte for byte)" in copies[0].message
    assert "copied from left_shin?" in copies[0].message
    assert copies[0].rule.id == "UI602"


def test_a_copy_is_derived_at_its_source_density():
    """The copy's values are derived from its own geometry at the density of the link it
    was copied from (the sibling's construction), the source is kept."""
    robot, _ = read_description(TWINS)
    found = {r.name: r for r in verdicts(robot, FixOptions(), MeshLibrary()).links}
    copy, source = found["left_foot"], found["left_shin"]
    assert copy.action == "recompute" and "inertial-copied" in copy.grounds
    assert copy.assembly is not None and copy.assembly.mass_source.kind == "density"
    rho = source.before.mass / sum(p.part.volume for p in
                                   found_parts(robot, "left_shin"))
    assert copy.assembly.mass_source.value == pytest.approx(rho, rel=1e-9)
    assert source.status == "kept"


def found_parts(robot, name):  # noqa: ANN001, ANN201
    from urdfinertia.plan.policy import every_link

    r = {x.name: x for x in verdicts(robot, every_link(FixOptions()), MeshLibrary()).links}
    return r[name].assembly.parts


def test_twins_that_disagree_say_which_side_agrees(findings):
    twins = [f for f in findings if f.code == "twins-disagree"]
    assert [f.link for f in twins] == ["right_thigh"]
    message = twins[0].message
    assert message.startswith("mirror twin of left_thigh")
    assert "mass 1.2 kg against 3" in message
    assert "left_thigh's agrees with the geometry" in message
    assert twins[0].rule.id == "UI603"


def test_agreeing_twins_and_identical_links_are_quiet(tmp_path):
    # right_thigh given left_thigh's values mirrored: twins that agree; two links sharing
    # one inertial over the same geometry: no copy
    text = TWINS.read_text()
    text = text.replace('<mass value="1.2"/>', '<mass value="3.0"/>').replace(
        'ixx="0.0094" ixy="0" ixz="0" iyy="0.0094" iyz="0" izz="0.00041"',
        'ixx="0.0235" ixy="0" ixz="0" iyy="0.0235" iyz="0" izz="0.0045"')
    text = text.replace('<origin xyz="0.03 0 -0.02" rpy="0 0 0"/>\n      <geometry><box '
                        'size="0.2 0.08 0.04"/>',
                        '<origin xyz="0 0 -0.15" rpy="0 0 0"/>\n      <geometry><box '
                        'size="0.07 0.06 0.3"/>')
    path = tmp_path / "agree.urdf"
    path.write_text(text)
    robot, _ = read_description(path)
    assert twin_findings(robot, MeshLibrary(), FixOptions()) == []


def test_check_reports_them_and_no_slips_turns_them_off():
    robot, _ = read_description(TWINS)
    codes = {f.code for f in check_description(robot, meshes=MeshLibrary()).findings}
    assert {"inertial-copied", "twins-disagree"} <= codes
    off = check_description(robot, meshes=MeshLibrary(), options=FixOptions(slips=False))
    assert not {"inertial-copied", "twins-disagree"} & {f.code for f in off.findings}
