"""``urdf-inertia check``: one hand-made URDF per check, asserting the finding and exit code."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from urdfinertia.analysis.check import check_robot
from urdfinertia.cache.library import MeshLibrary
from urdfinertia.cli import main
from urdfinertia.descriptions.formats import read_description as read_urdf_lenient

BOX = 0.1  # m, side of the cube every test link is made of
CUBE_I = 1.0 / 12 * (BOX**2 + BOX**2)  # kg m^2 per kg: a solid cube's central moment


def inertial(mass="1", com="0 0 0", rpy="0 0 0", diag=None, off=("0", "0", "0")) -> str:
    d = diag or (repr(CUBE_I * float(mass)),) * 3
    return (f'<inertial><origin xyz="{com}" rpy="{rpy}"/><mass value="{mass}"/>'
            f'<inertia ixx="{d[0]}" ixy="{off[0]}" ixz="{off[1]}" iyy="{d[1]}" '
            f'iyz="{off[2]}" izz="{d[2]}"/></inertial>')


def link(name: str, body: str | None = "", geometry: bool = True) -> str:
    geo = (f'<collision><geometry><box size="{BOX} {BOX} {BOX}"/></geometry></collision>'
           if geometry else "")
    return f'<link name="{name}">{body or ""}{geo}</link>'


def joint(child: str, parent: str = "base", kind: str = "revolute") -> str:
    limit = '<limit lower="-1" upper="1" effort="1" velocity="1"/>' if kind != "fixed" else ""
    return (f'<joint name="j_{child}" type="{kind}"><parent link="{parent}"/>'
            f'<child link="{child}"/><axis xyz="0 0 1"/>{limit}</joint>')


def robot(*parts: str) -> str:
    return '<?xml version="1.0"?>\n<robot name="t">\n<link name="base"/>\n' + "\n".join(
        parts) + "\n</robot>\n"


def write(tmp_path: Path, text: str, name: str = "r.urdf") -> Path:
    path = tmp_path / name
    path.write_text(text)
    return path


def findings(path: Path, geometry: bool = True):
    rob, _ = read_urdf_lenient(path)
    return check_robot(rob, meshes=MeshLibrary() if geometry else None, geometry=geometry)


def codes(found, severity: str | None = None) -> set[tuple[str | None, str]]:
    return {(f.link, f.code) for f in found if severity is None or f.severity == severity}


def exit_code(path: Path, *extra: str) -> int:
    return main(["check", str(path), "-q", *extra])


# --- a clean robot -------------------------------------------------------------------
def test_clean_robot_has_no_problems(tmp_path):
    path = write(tmp_path, robot(link("arm", inertial()), joint("arm")))
    found = findings(path)
    assert [f for f in found if f.severity != "info"] == []
    assert exit_code(path, "--strict") == 0


def test_fix_output_passes_check(tmp_path):
    # Whatever fix writes must lint clean: a property linking the two commands.
    src = write(tmp_path, robot(link("arm", inertial(diag=("1", "1", "1"))), joint("arm"),
                                link("hand", inertial(mass="0.3", com="0.5 0 0")),
                                joint("hand", "arm")))
    out = tmp_path / "fixed.urdf"
    assert main(["fix", str(src), "-o", str(out), "-q"]) == 0
    assert exit_code(out, "--strict") == 0
    assert exit_code(src, "--strict") == 1


# --- missing inertial ------------------------------------------------------------------
def test_missing_inertial_on_moving_link_is_an_error(tmp_path):
    path = write(tmp_path, robot(link("arm", None), joint("arm")))
    assert codes(findings(path), "error") == {("arm", "missing-inertial")}
    assert exit_code(path) == 1


def test_missing_inertial_on_fixed_link_is_fine(tmp_path):
    path = write(tmp_path, robot(link("arm", inertial()), joint("arm"),
                                 link("sensor", None), joint("sensor", "arm", "fixed")))
    assert codes(findings(path), "error") == set()
    assert exit_code(path, "--strict") == 0


def test_missing_inertial_with_mass_fixed_to_it_is_a_warning(tmp_path):
    path = write(tmp_path, robot(link("arm", None), joint("arm"),
                                 link("shell", inertial(mass="2")),
                                 joint("shell", "arm", "fixed")))
    found = findings(path)
    assert ("arm", "missing-inertial-merged") in codes(found, "warning")
    assert exit_code(path) == 0
    assert exit_code(path, "--strict") == 1


# --- mass ----------------------------------------------------------------------------
@pytest.mark.parametrize("mass, code", [("nan", "mass-not-finite"), ("inf", "mass-not-finite"),
                                        ("-1", "mass-not-positive"),
                                        ("0", "mass-not-positive")])
def test_bad_mass_on_moving_link(tmp_path, mass, code):
    path = write(tmp_path, robot(link("arm", inertial(mass=mass, diag=("0.01",) * 3)),
                                 joint("arm")))
    assert ("arm", code) in codes(findings(path), "error")
    assert exit_code(path) == 1  # a finding, not an unreadable file (2)


def test_massless_fixed_frame_is_only_info(tmp_path):
    path = write(tmp_path, robot(link("arm", inertial()), joint("arm"),
                                 link("tool", inertial(mass="0", diag=("0", "0", "0")),
                                      geometry=False),
                                 joint("tool", "arm", "fixed")))
    found = findings(path)
    assert ("tool", "massless-frame") in codes(found, "info")
    assert exit_code(path, "--strict") == 0


# --- tensor ----------------------------------------------------------------------------
def test_non_finite_tensor(tmp_path):
    path = write(tmp_path, robot(link("arm", inertial(diag=("nan", "1e-3", "1e-3"))),
                                 joint("arm")))
    assert ("arm", "inertia-not-finite") in codes(findings(path), "error")
    assert exit_code(path) == 1


def test_not_positive_definite(tmp_path):
    # Products larger than the diagonal: eigenvalues -1, 1, 3 (x 1e-3).
    path = write(tmp_path, robot(link("arm", inertial(diag=("1e-3",) * 3,
                                                      off=("2e-3", "0", "0"))), joint("arm")))
    found = findings(path, geometry=False)
    (f,) = [f for f in found if f.code == "inertia-not-positive-definite"]
    assert f.severity == "error" and "-0.333 of" in f.message  # smallest / largest = -1/3
    assert exit_code(path, "--no-geometry") == 1


def test_triangle_inequality_reports_relative_excess(tmp_path):
    # Moments 1, 2, 4 (x 1e-3) rotated by rpy: A + B < C by (4 - 3) / 4 = 0.25 of C.
    path = write(tmp_path, robot(link("arm", inertial(diag=("1e-3", "2e-3", "4e-3"),
                                                      rpy="0.4 -0.3 1.2")), joint("arm")))
    (f,) = [f for f in findings(path, geometry=False) if f.code == "triangle-inequality"]
    assert f.severity == "error" and "by 0.25 of C" in f.message
    assert exit_code(path, "--no-geometry") == 1


def test_zero_tensor_with_mass_on_moving_link(tmp_path):
    path = write(tmp_path, robot(link("arm", inertial(diag=("0", "0", "0"))), joint("arm")))
    assert ("arm", "inertia-zero") in codes(findings(path), "error")
    assert exit_code(path) == 1


@pytest.mark.parametrize("value", ["1", "1e-6", "1e-8"])
def test_placeholder_tensor(tmp_path, value):
    path = write(tmp_path, robot(link("arm", inertial(diag=(value,) * 3)), joint("arm")))
    found = findings(path)
    assert ("arm", "placeholder-inertia") in codes(found, "warning")
    # Against a 0.1 m cube of 1 kg (trace 1/200), 1 is 600x too large, 1e-6 is 1/5000.
    assert ("arm", "inertia-vs-geometry") in codes(found, "warning")
    assert exit_code(path) == 0
    assert exit_code(path, "--strict") == 1


def test_inertia_vs_geometry_ratio_and_ceiling(tmp_path):
    # 0.5 kg m^2 per axis for 1 kg in a 0.1 m cube: far above the corner ceiling
    # 2 m max|corner - c|^2 = 2 * 3 * 0.05^2 = 0.015 kg m^2 (trace).
    path = write(tmp_path, robot(link("arm", inertial(diag=("0.5", "0.5", "0.6"))),
                                 joint("arm")))
    (f,) = [f for f in findings(path) if f.code == "inertia-vs-geometry"]
    assert "0.015 kg m^2 ceiling" in f.message and f.severity == "warning"


def test_tensor_within_a_factor_of_the_geometry_is_not_flagged(tmp_path):
    # A cube's corner ceiling is 3x its solid trace: 2x and 0.3x are both plausible.
    for k in (2.0, 0.3):
        path = write(tmp_path, robot(link("arm", inertial(diag=(repr(k * CUBE_I),) * 3)),
                                     joint("arm")))
        assert not any(f.code == "inertia-vs-geometry" for f in findings(path))


# --- geometry ----------------------------------------------------------------------------
def test_com_far_outside_the_geometry_box(tmp_path):
    path = write(tmp_path, robot(link("arm", inertial(com="0.2 0 0")), joint("arm")))
    (f,) = [f for f in findings(path) if f.code == "com-outside-geometry"]
    # The cube spans +-0.05: 0.15 m outside, over a diagonal of 0.1 sqrt(3).
    assert f.severity == "warning" and f"{0.15 / (0.1 * np.sqrt(3)):.3g} box" in f.message
    assert exit_code(path) == 0 and exit_code(path, "--strict") == 1


def test_com_a_unit_slip_away_is_an_error(tmp_path):
    path = write(tmp_path, robot(link("arm", inertial(com="30 0 0")), joint("arm")))
    assert ("arm", "com-far-outside-geometry") in codes(findings(path), "error")
    assert exit_code(path) == 1


def test_com_slightly_outside_is_fine(tmp_path):
    path = write(tmp_path, robot(link("arm", inertial(com="0.06 0 0")), joint("arm")))
    assert not any(f.code == "com-outside-geometry" for f in findings(path))


@pytest.mark.parametrize("mass, hint", [("1000", "mass in g?"), ("1e-6", "mesh in cm"),
                                        ("1e-9", "mesh in mm")])
def test_implausible_density(tmp_path, mass, hint):
    # 1000 kg in a 1e-3 m^3 cube: 1e6 kg/m^3, 1000x too dense; 1e-6 kg gives 1e-3 kg/m^3
    # (a cm mesh read as m has 1e6 times its volume); 1e-9 kg gives 1e-6 (mm: 1e9).
    path = write(tmp_path, robot(link("arm", inertial(mass=mass)), joint("arm")))
    (f,) = [f for f in findings(path) if f.code == "implausible-density"]
    assert f"{float(mass) / 1e-3:.3g} kg/m^3" in f.message and hint in f.message
    if mass != "1000":
        return  # a tensor of 1e-3 kg m^2 on a milligram is also a placeholder: recomputed
    # fix keeps the value (the geometry is not the body: a marker) and says why: --strict
    # does not fail on what fix keeps on purpose, and the JSON says so
    report = tmp_path / "r.json"
    assert main(["check", str(path), "-q", "--strict", "--json", str(report)]) == 0
    (row,) = [r for r in json.loads(report.read_text())["files"][0]["findings"]
              if r["code"] == "implausible-density"]
    assert row["kept"] and row["fix"].startswith("would be kept: ")


def test_missing_mesh_is_a_warning_not_a_crash(tmp_path, capsys):
    text = robot(link("arm", inertial()), joint("arm")).replace(
        f'<box size="{BOX} {BOX} {BOX}"/>', '<mesh filename="nowhere.stl"/>')
    path = write(tmp_path, text)
    assert ("arm", "mesh-unresolved") in codes(findings(path), "warning")
    # the geometry checks were asked for and could not be done: not verified, exit 1
    capsys.readouterr()
    assert exit_code(path) == 1
    out = capsys.readouterr().out
    assert "not verified: 1 mesh unresolved or unreadable in 1 link: pass --package-dir" \
        in out
    # a reference that does not resolve is a warning even when no mesh is read (issue 13)
    assert exit_code(path, "--no-geometry") == 0
    assert exit_code(path, "--no-geometry", "--strict") == 1


# --- lumping ------------------------------------------------------------------------------
def test_fixed_links_are_reported_as_lumped(tmp_path):
    path = write(tmp_path, robot(
        link("arm", inertial(mass="1")), joint("arm"),
        link("motor", inertial(mass="0.5", com="0.04 0 0")),
        '<joint name="jm" type="fixed"><parent link="arm"/><child link="motor"/>'
        '<origin xyz="0.2 0 0"/></joint>'))
    (f,) = [f for f in findings(path) if f.code == "lumped-mass"]
    # Merged CoM along x: (1 * 0 + 0.5 * (0.2 + 0.04)) / 1.5 = 0.08 m.
    assert f.link == "arm" and f.severity == "info"
    assert "1.5 kg" in f.message and "[0.08, 0.0, 0.0]" in f.message
    assert exit_code(path, "--strict") == 0


# --- CLI ------------------------------------------------------------------------------------
def test_unreadable_input_exits_2(tmp_path, capsys):
    bad = write(tmp_path, "<robot name='x'><link name='a'>", "bad.urdf")
    assert exit_code(bad) == 2
    captured = capsys.readouterr()
    (line,) = captured.err.splitlines()
    assert line.startswith("urdf-inertia: error: ") and "bad.urdf" in line
    assert exit_code(tmp_path / "absent.urdf") == 2
    captured = capsys.readouterr()
    (line,) = captured.err.splitlines()
    assert line.startswith("urdf-inertia: error: ") and "absent.urdf" in line
    assert sorted(p.name for p in tmp_path.iterdir()) == ["bad.urdf"]  # nothing written


def test_json_output_lists_findings_and_counts(tmp_path):
    path = write(tmp_path, robot(link("arm", None), joint("arm"),
                                 link("hand", inertial(diag=("1", "1", "1"))),
                                 joint("hand", "arm")))
    out = tmp_path / "f.json"
    assert main(["check", str(path), "-q", "--json", str(out)]) == 1
    doc = json.loads(out.read_text())
    (entry,) = doc["files"]
    assert doc["exit_code"] == 1
    assert entry["counts"]["error"] == 1
    assert {(f["link"], f["code"]) for f in entry["findings"]} >= {
        ("arm", "missing-inertial"), ("hand", "placeholder-inertia")}


# --- corpus ---------------------------------------------------------------------------------
@pytest.mark.corpus
def test_corpus_value_checks_agree_with_an_independent_reader(erd_dir):
    """Every example-robot-data URDF: no crash, and the triangle-inequality and placeholder
    findings equal what yourdfpy's independent parse of the same files gives."""
    yourdfpy = pytest.importorskip("yourdfpy")
    paths = sorted(erd_dir.rglob("*.urdf"))
    assert len(paths) > 60
    seen_triangle = seen_placeholder = 0
    for path in paths:
        rob, _ = read_urdf_lenient(path)
        found = check_robot(rob)
        assert all(f.severity in ("error", "warning", "info") for f in found)
        try:
            ref = yourdfpy.URDF.load(str(path), load_meshes=False, build_scene_graph=False,
                                     load_collision_meshes=False,
                                     build_collision_scene_graph=False)
        except KeyError:
            continue  # yourdfpy cannot read a <robot> without a name (ur3.urdf, no links)
        triangle, placeholder = set(), set()
        for lk in ref.robot.links:
            if lk.inertial is None or lk.inertial.inertia is None:
                continue
            rot = lk.inertial.origin[:3, :3] if lk.inertial.origin is not None else np.eye(3)
            t = rot @ np.asarray(lk.inertial.inertia) @ rot.T
            m = np.linalg.eigvalsh(t)
            if m[0] > 0 and m[2] - m[0] - m[1] > 1e-12 * m[2]:
                triangle.add(lk.name)
            raw = np.asarray(lk.inertial.inertia)
            d = np.diag(raw)
            if (not np.any(raw - np.diag(d)) and d[0] == d[1] == d[2]
                    and (d[0] == 1 or (0 < d[0] <= 1e-6
                                       and float(f"1e{round(np.log10(d[0]))}") == d[0]))):
                placeholder.add(lk.name)
        assert {f.link for f in found if f.code == "triangle-inequality"} == triangle, path
        flagged = {f.link: f for f in found if f.code == "placeholder-inertia"}
        assert placeholder <= set(flagged), path
        # the others are isotropic tensors no compact body of their mass has (the wider
        # placeholder rule), each saying so
        assert all("radius of gyration" in flagged[n].message
                   for n in set(flagged) - placeholder), path
        seen_triangle += len(triangle)
        seen_placeholder += len(placeholder)
    # The oracle must have had something to agree on, or the test proves nothing.
    assert seen_triangle > 0 and seen_placeholder > 0


# --- issue 13: check lints what it can read, it does not refuse ---------------------------

LINT_URDF = """<?xml version="1.0"?>
<robot name="r">
  <link name="a">
    <inertial><mass value="MASS"/>
      <inertia ixx="0.1" ixy="0" ixz="0" iyy="0.2" iyz="0" izz="0.25"/></inertial>
    <collision><origin xyz="0 0 0" rpy="0, 0 0"/><geometry><box size="0.1 0.2 0.3"/>
    </geometry></collision>
    <collision><geometry><sphere radius="0"/></geometry></collision>
    <visual><geometry><mesh filename="meshes/gone.stl"/></geometry></visual>
  </link>
</robot>
"""


@pytest.mark.parametrize(("mass", "code"), [("6e9", "mass-absurd"),
                                            ("-2", "mass-not-positive"),
                                            ("nan", "mass-not-finite")])
def test_check_judges_any_readable_value(mass, code, tmp_path, capsys):
    from urdfinertia.cli import main

    urdf = tmp_path / "r.urdf"
    urdf.write_text(LINT_URDF.replace("MASS", mass))
    report = tmp_path / "r.json"
    assert main(["check", str(urdf), "--no-geometry", "--json", str(report)]) == 1
    capsys.readouterr()
    findings = json.loads(report.read_text())["files"][0]["findings"]
    by_code = {f["code"]: f for f in findings}
    assert by_code[code]["severity"] == "error"
    # what other loaders fail on, each with its line
    assert by_code["vector-commas"]["line"] == 6
    assert by_code["zero-size-primitive"]["line"] == 8
    assert by_code["mesh-unresolved"]["line"] == 9
