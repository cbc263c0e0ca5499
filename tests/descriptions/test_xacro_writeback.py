"""fix --write-back on xacro sources: what is written where, what is reported, and that
the edited sources expand to the fixed URDF (closed forms give the expected values)."""

from __future__ import annotations

import shutil
from pathlib import Path

import pytest
import yaml

from urdfinertia.cli import main
from urdfinertia.descriptions.xacro import apply as apply_module
from urdfinertia.descriptions.xacro.apply import apply_plan, verification_mismatch
from urdfinertia.descriptions.xacro.expand import configure, current_settings, expand_xacro
from urdfinertia.descriptions.xacro.trace import elements, link_inertials
from urdfinertia.descriptions.xacro.writeback import plan_write_back
from urdfinertia.errors import UrdfError

DATA = Path(__file__).parents[1] / "data" / "xacro"


@pytest.fixture(autouse=True)
def _reset_settings():
    configure()
    yield
    configure()


def run_write_back(tmp_path: Path, fixture: str, main_file: str, *extra: str):
    """Copy a fixture, fix it with --write-back; (folder, report, fixed URDF, originals)."""
    root = tmp_path / fixture
    shutil.copytree(DATA / fixture, root)
    originals = {p: p.read_bytes() for p in root.rglob("*") if p.is_file()}
    before = expand_xacro(root / main_file).document
    report, fixed = tmp_path / "report.yaml", tmp_path / "fixed.urdf"
    code = main(["fix", "--all", str(root / main_file), "--write-back", "--write-back-report",
                 str(report), "-o", str(fixed), "-q", *extra])
    assert code == 0
    return root, yaml.safe_load(report.read_text()), fixed.read_bytes(), originals, before


def statuses(report: dict) -> dict[str, str]:
    out = {r["link"]: "reported" for r in report["reported"]}
    out.update({w["link"]: "written" for w in report["written"]})
    out.update({name: "unchanged" for name in report["unchanged"]})
    return out


def changed_files(root: Path, originals: dict[Path, bytes]) -> set[str]:
    return {str(p.relative_to(root)) for p, data in originals.items() if p.read_bytes() != data}


def check_reexpansion(main_file: Path, before: bytes, fixed: bytes, written: set[str]):
    """The edited sources expand to the fixed values for the written links, to the old
    ones for every other link, and to the same bytes outside those inertials."""
    again = expand_xacro(main_file).document
    want, got, old = (link_inertials(elements(d)) for d in (fixed, again, before))
    for name in got:
        source = want if name in written else old
        for slot, value in got[name].slots.items():
            expected = source[name].slots[slot].text
            assert (None if value.text is None else float(value.text)) == (
                None if expected is None else float(expected)), (name, slot)
    assert verification_mismatch(before, fixed, again, written) is None


def box_moments(mass, x, y, z):
    return (mass * (y * y + z * z) / 12, mass * (x * x + z * z) / 12,
            mass * (x * x + y * y) / 12)


def test_ur_style_yaml_physical_parameters(tmp_path):
    root, report, fixed, originals, before = run_write_back(
        tmp_path, "ur_description", "urdf/ur.urdf.xacro")
    assert statuses(report) == {"base_link": "reported", "shoulder_link": "written",
                                "upper_arm_link": "written", "forearm_link": "written"}
    # only the YAML changed, comments and layout kept: a byte splice of each scalar
    assert changed_files(root, originals) == {"config/physical_parameters.yaml"}
    text = (root / "config/physical_parameters.yaml").read_text()
    old = originals[root / "config/physical_parameters.yaml"].decode()
    assert text.count("\n") == old.count("\n") and "# from CAD" in text and "# measured" in text
    ixx, iyy, izz = box_moments(8.058, 0.5, 0.12, 0.12)
    upper = yaml.safe_load(text)["inertia_parameters"]["tensor"]["upper_arm"]
    assert upper["ixx"] == pytest.approx(ixx, rel=1e-12)
    assert upper["iyy"] == pytest.approx(iyy, rel=1e-12)
    assert upper["izz"] == pytest.approx(izz, rel=1e-12)
    cog = yaml.safe_load(text)["inertia_parameters"]["center_of_mass"]["forearm_cog"]
    assert (cog["x"], cog["y"], cog["z"]) == (-0.19, 0.0, 0.03)
    assert "base_mass: 4.0          # measured" in text  # mass is kept (--mass keep)
    # the base's moments are computed by the cylinder_inertial macro: reported with it
    base = next(r for r in report["reported"] if r["link"] == "base_link")
    ixx_note = next(v for v in base["values"] if v["value"] == "ixx")
    assert "0.0833333 * mass" in ixx_note["written_as"]
    assert ixx_note["source"].endswith("urdf/inc/inertials.xacro:8")
    assert "computed" in ixx_note["why_not_written"]
    check_reexpansion(root / "urdf/ur.urdf.xacro", before, fixed,
                      {"shoulder_link", "upper_arm_link", "forearm_link"})


def test_franka_style_inertial_yaml_with_xyz_strings(tmp_path):
    configure({"arm_id": "panda"})  # for the expansion before (the command sets its own)
    root, report, fixed, originals, before = run_write_back(
        tmp_path, "franka_description", "robots/fr3/fr3.urdf.xacro",
        "--xacro-arg", "arm_id:=panda")
    assert statuses(report) == {"panda_link0": "written", "panda_link1": "written"}
    assert changed_files(root, originals) == {"robots/fr3/inertials.yaml"}
    data = yaml.safe_load((root / "robots/fr3/inertials.yaml").read_text())
    assert data["link0"]["origin"]["xyz"] == "-0.02 0 0.07"  # tokens of a string scalar
    ixx, iyy, izz = box_moments(2.3966, 0.2, 0.16, 0.14)
    assert data["link0"]["inertia"]["xx"] == pytest.approx(ixx, rel=1e-12)
    assert data["link0"]["inertia"]["zz"] == pytest.approx(izz, rel=1e-12)
    assert data["link1"]["inertia"]["xz"] == 0  # was the string "1e-05"
    assert "# CoM in the link frame" in (root / "robots/fr3/inertials.yaml").read_text()
    check_reexpansion(root / "robots/fr3/fr3.urdf.xacro", before, fixed,
                      {"panda_link0", "panda_link1"})


def test_limb_macros_call_sites_shared_values_and_expressions(tmp_path):
    root, report, fixed, originals, before = run_write_back(
        tmp_path, "limbs", "humanoid.urdf.xacro")
    assert statuses(report) == {
        "torso": "reported",  # CoM z is ${torso_h/2}
        "left_arm": "written", "right_arm": "written",  # different literals per call
        "left_leg": "written", "right_leg": "written",  # the same literal at two calls
        "left_hand": "reported", "right_hand": "reported",  # one macro literal, two uses
        "front_wheel": "reported", "rear_wheel": "reported",  # property used by both
        "tail": "written",  # a property used once, literals in the <inertial>
    }
    text = (root / "humanoid.urdf.xacro").read_text()
    leg = box_moments(3.0, 0.1, 0.1, 0.5)
    line = next(x for x in text.splitlines() if 'side="right" y="-0.08"' in x)
    attrs = dict(part.split("=") for part in line.replace("/>", "").split()[1:])
    assert float(attrs["ixx"].strip('"')) == pytest.approx(leg[0], rel=1e-12)
    assert float(attrs["izz"].strip('"')) == pytest.approx(leg[2], rel=1e-12)
    assert attrs["com_z"] == '"-0.25"' and attrs["mass"] == '"3.0"'
    tail = box_moments(0.3, 0.3, 0.05, 0.05)
    assert f'<xacro:property name="tail_ixx" value="{tail[0]!r}"/>' in text
    assert '<xacro:property name="wheel_i" value="0.001"/>' in text  # shared: untouched
    assert 'name="hand" params="side izz:=0.0002"' in text
    assert "${torso_h/2}" in text
    torso = next(r for r in report["reported"] if r["link"] == "torso")
    assert torso["values"][0]["written_as"] == 'xyz="0 0 ${torso_h/2}"'
    wheel = next(r for r in report["reported"] if r["link"] == "front_wheel")
    assert "rear_wheel" in wheel["why"] and "shared" in wheel["why"]
    written = {n for n, s in statuses(report).items() if s == "written"}
    check_reexpansion(root / "humanoid.urdf.xacro", before, fixed, written)


def test_a_property_also_used_outside_the_inertial_is_reported(tmp_path):
    # with --mass density the tail's mass changes; its property is also a joint effort
    root, report, fixed, _, before = run_write_back(
        tmp_path, "limbs", "humanoid.urdf.xacro", "--mass", "density")
    tail = next(r for r in report["reported"] if r["link"] == "tail")
    assert "joint 'tail_joint' limit@effort" in tail["why"]
    assert '<xacro:property name="tail_mass" value="0.3"/>' in (
        root / "humanoid.urdf.xacro").read_text()
    written = {n for n, s in statuses(report).items() if s == "written"}
    check_reexpansion(root / "humanoid.urdf.xacro", before, fixed, written)


def test_nested_includes_literal_inertials_and_an_added_one(tmp_path):
    root, report, fixed, originals, before = run_write_back(
        tmp_path, "nested", "rover.urdf.xacro")
    assert statuses(report) == {"chassis": "written", "mast": "written", "camera": "written"}
    assert changed_files(root, originals) == {"parts/body.xacro", "parts/sensors/head.xacro"}
    where = {w["link"]: w["where"] for w in report["written"]}
    assert where["chassis"].startswith("literal <inertial> at ") and \
        where["chassis"].endswith("parts/body.xacro:11")
    assert "inserted" in where["camera"]
    body = (root / "parts/body.xacro").read_text()
    assert '        <origin xyz="0 0 0.05" rpy="0 0 0"/>\n        <mass value="12"/>' in body
    assert "<!-- no <origin>: the CoM is at the link origin -->" in body
    # outside the spliced elements every byte is the original's
    old = originals[root / "parts/body.xacro"].decode()
    assert body.split("<inertial>")[0] == old.split("<inertial>")[0]
    assert body.split("</inertial>")[1] == old.split("</inertial>")[1]
    check_reexpansion(root / "rover.urdf.xacro", before, fixed, {"chassis", "mast", "camera"})


def test_in_place_on_xacro_writes_back_and_prints_no_urdf(tmp_path, capsys):
    root = tmp_path / "nested"
    shutil.copytree(DATA / "nested", root)
    assert main(["fix", "--all", str(root / "rover.urdf.xacro"), "--in-place"]) == 0
    out = capsys.readouterr().out
    assert "write-back: 3 link(s) written back, 0 reported, 0 unchanged" in out
    assert "<robot" not in out
    assert (root / "parts/body.xacro.bak").read_bytes() == (
        DATA / "nested/parts/body.xacro").read_bytes()


def test_write_back_on_urdf_input_is_refused(tmp_path, capsys):
    path = tmp_path / "r.urdf"
    text = ('<robot name="r"><link name="a"><collision><geometry><box size="1 1 1"/>'
            "</geometry></collision></link></robot>")
    path.write_text(text)
    assert main(["fix", "--all", str(path), "--write-back", "-q"]) == 2
    captured = capsys.readouterr()
    (line,) = captured.err.splitlines()
    assert line.startswith("urdf-inertia: error: ") and "r.urdf" in line
    assert "--write-back applies to xacro input" in line
    assert captured.out == ""  # no document on stdout either
    assert path.read_text() == text and sorted(p.name for p in tmp_path.iterdir()) == ["r.urdf"]


def prepared(tmp_path: Path):
    from urdfinertia.body.options import FixOptions
    from urdfinertia.descriptions.formats import read_description
    from urdfinertia.plan.fix import fix_robot

    root = tmp_path / "limbs"
    shutil.copytree(DATA / "limbs", root)
    path = root / "humanoid.urdf.xacro"
    robot, document = read_description(path)
    result = fix_robot(robot, document, FixOptions(recompute="all"))
    exp = expand_xacro(path)
    plan = plan_write_back(path, exp, result.output, current_settings())
    return path, exp, result.output, plan


def test_a_plan_that_does_not_reproduce_the_fix_writes_nothing(tmp_path):
    path, exp, fixed, plan = prepared(tmp_path)
    original = path.read_bytes()
    start = original.index(b'effort="40"') + len(b'effort="')
    plan.edits.append((exp.sources[0], start, start + 2, b"41"))  # a non-inertial byte
    with pytest.raises(UrdfError, match="nothing written.*effort") as exc:
        apply_plan(path, exp, fixed, plan, current_settings())
    assert "left_shoulder" not in str(exc.value) or "limit" in str(exc.value)
    assert path.read_bytes() == original
    assert not path.with_name(path.name + ".bak").exists()


def test_a_failed_check_from_disk_restores_every_source(tmp_path, monkeypatch):
    path, exp, fixed, plan = prepared(tmp_path)
    original = path.read_bytes()
    calls = []

    def stale(*args, **kwargs):  # the second expansion (from disk) disagrees
        calls.append(kwargs.get("overrides"))
        return exp if len(calls) > 1 else expand_xacro(*args, **kwargs)

    monkeypatch.setattr(apply_module, "expand_xacro", stale)
    with pytest.raises(UrdfError, match="sources restored: link '.*'"):
        apply_plan(path, exp, fixed, plan, current_settings())
    assert path.read_bytes() == original


def test_the_library_writes_back_the_same_sources_as_the_cli(tmp_path):
    import urdfinertia

    cli_root, _, _, originals, _ = run_write_back(tmp_path / "cli", "ur_description",
                                                  "urdf/ur.urdf.xacro")
    lib_root = tmp_path / "lib" / "ur_description"
    shutil.copytree(DATA / "ur_description", lib_root)
    result = urdfinertia.fix(lib_root / "urdf/ur.urdf.xacro", recompute="all")
    report = tmp_path / "lib" / "report.yaml"
    plan = urdfinertia.write_back(result, report=report)
    assert {o.status for o in plan.outcomes} >= {"written"}
    changed = changed_files(cli_root, originals)
    assert changed  # the CLI edited sources: the library must have edited the same bytes
    for rel in changed:
        assert (lib_root / rel).read_bytes() == (cli_root / rel).read_bytes(), rel
    assert yaml.safe_load(report.read_text())["written"]


def test_xacro_args_are_options_of_the_call_only(tmp_path):
    import urdfinertia

    path = DATA / "ur_description" / "urdf" / "ur.urdf.xacro"
    result = urdfinertia.fix(path, recompute="all", xacro_args={"prefix": "left_"})
    assert all(r.name.startswith("left_") for r in result.links)
    assert current_settings().args == ()  # nothing leaks into later reads
    again = urdfinertia.fix(path, recompute="all")
    assert not any(r.name.startswith("left_") for r in again.links)
    # the same as the command line's --xacro-arg
    out = tmp_path / "cli.urdf"
    assert main(["fix", "--all", str(path), "--xacro-arg", "prefix:=left_", "-q",
                 "-o", str(out)]) == 0
    assert out.read_bytes() == result.save(tmp_path / "lib.urdf").path.read_bytes()
