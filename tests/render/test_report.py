"""report.py and cli_report.py: the HTML report's data, figures, table and file."""

from __future__ import annotations

import json
import math
import re
from pathlib import Path

import numpy as np
import pytest
from lxml import html as lxml_html

from urdfinertia.body.options import FixOptions
from urdfinertia.cli import main
from urdfinertia.inertia import primitives
from urdfinertia.render.compare_plot import error_series
from urdfinertia.render.report import (
    COLORS,
    ERROR_PANELS,
    collect,
    error_figures,
    render_html,
    scene_figure,
)
from urdfinertia.render.report_figures import SOURCE_NAMES
from urdfinertia.render.report_table import position, vec

#: A 0.2 x 0.1 x 0.05 m box of 2 kg, for the link whose written inertial is right.
GOOD = primitives.box((0.2, 0.1, 0.05), 1.0).with_mass(2.0)
IXX, IYY, IZZ = (float(x) for x in np.diag(GOOD.inertia))
EVIL = "evil</script><img src=x onerror=alert(1)>"

HAND_URDF = f"""<robot name="hand">
  <link name="base">
    <inertial><origin xyz="0 0 0.025"/><mass value="2"/>
      <inertia ixx="{IXX!r}" ixy="0" ixz="0" iyy="{IYY!r}" iyz="0" izz="{IZZ!r}"/>
    </inertial>
    <collision><origin xyz="0 0 0.025"/><geometry><box size="0.2 0.1 0.05"/></geometry>
    </collision>
  </link>
  <link name="not_definite">
    <inertial><mass value="1"/><inertia ixx="0.01" ixy="0.5" ixz="0" iyy="0.01" iyz="0"
      izz="0.01"/></inertial>
    <collision><geometry><sphere radius="0.05"/></geometry></collision>
  </link>
  <link name="triangle">
    <inertial><mass value="1"/><inertia ixx="0.001" ixy="0" ixz="0" iyy="0.001" iyz="0"
      izz="0.005"/></inertial>
    <collision><geometry><cylinder radius="0.03" length="0.2"/></geometry></collision>
  </link>
  <link name="not_a_number">
    <inertial><mass value="nan"/><inertia ixx="1" ixy="0" ixz="0" iyy="1" iyz="0" izz="1"/>
    </inertial>
    <visual><geometry><box size="0.1 0.1 0.1"/></geometry></visual>
  </link>
  <link name="{EVIL.replace('<', '&lt;').replace('>', '&gt;')}"/>
  <joint name="j1" type="revolute"><parent link="base"/><child link="not_definite"/>
    <origin xyz="0 0 0.3"/></joint>
  <joint name="j2" type="revolute"><parent link="not_definite"/><child link="triangle"/>
    <origin xyz="0.2 0 0" rpy="0 1.5707963267948966 0"/></joint>
  <joint name="j3" type="fixed"><parent link="triangle"/><child link="not_a_number"/>
    <origin xyz="0 0 0.3"/></joint>
  <joint name="j4" type="fixed"><parent link="base"/>
    <child link="{EVIL.replace('<', '&lt;').replace('>', '&gt;')}"/></joint>
</robot>"""


@pytest.fixture(scope="module")
def hand_urdf(tmp_path_factory) -> Path:
    path = tmp_path_factory.mktemp("hand") / "hand.urdf"
    path.write_text(HAND_URDF)
    return path


@pytest.fixture(scope="module")
def hand_data(hand_urdf):
    return collect(hand_urdf, FixOptions())


@pytest.fixture(scope="module")
def hand_html(hand_data) -> str:
    return render_html(hand_data)


def rows_by_name(data):
    return {r.name: r for r in data.rows}


# --- collected data -----------------------------------------------------------------------
def test_a_right_inertial_is_kept_and_matches_the_geometry(hand_data):
    # the report shows what fix writes: a right inertial is kept, so it has no recomputed
    # box; compare's geometry side still matches it
    base = rows_by_name(hand_data)["base"]
    (existing,) = base.boxes
    assert existing.source == "kept"  # as written, and fix keeps it
    np.testing.assert_allclose(np.sort(existing.lengths), [0.05, 0.1, 0.2], rtol=1e-9)
    np.testing.assert_allclose(existing.center, [0.0, 0.0, 0.025], atol=1e-12)
    assert base.recomputed is None and base.fix.action == "keep"
    assert base.comparison.verdict == "ok"
    np.testing.assert_allclose(base.comparison.b.com, existing.center, atol=1e-12)


def test_boxes_sit_at_the_zero_configuration(hand_data):
    triangle = rows_by_name(hand_data)["triangle"]
    recomputed = next(b for b in triangle.boxes if b.source == "recomputed")
    # The cylinder's CoM is its frame origin: base -> +0.3 z -> +0.2 x.
    np.testing.assert_allclose(recomputed.center, [0.2, 0.0, 0.3], atol=1e-12)
    # Its long axis (0.2 m, along the cylinder's z) is turned onto world x by pitch pi/2.
    long_axis = recomputed.axes[:, int(np.argmax(recomputed.lengths))]
    np.testing.assert_allclose(np.abs(long_axis), [1.0, 0.0, 0.0], atol=1e-9)


def test_invalid_existing_inertials_have_no_box_but_a_reason(hand_data):
    rows = rows_by_name(hand_data)
    for name, reason in (("not_definite", "positive semi-definite"),
                         ("not_a_number", "non-finite")):
        row = rows[name]
        assert row.existing is None and reason in row.existing_note
        assert [b.source for b in row.boxes] == ["recomputed"]
        assert row.comparison.verdict == "invalid"


def test_a_tensor_breaking_the_triangle_inequality_gets_a_flagged_box(hand_data):
    row = rows_by_name(hand_data)["triangle"]
    existing = next(b for b in row.boxes if b.source == "existing")
    assert existing.clipped and np.min(existing.lengths) == 0.0
    assert row.comparison.verdict == "invalid"


def test_a_link_without_anything_has_no_box(hand_data):
    assert rows_by_name(hand_data)[EVIL].boxes == ()


# --- figures ------------------------------------------------------------------------------
def test_scene_figure_holds_every_box_and_every_link_geometry(hand_data):
    fig = scene_figure(hand_data)
    n_boxes = {s: sum(b.source == s for r in hand_data.rows for b in r.boxes)
               for s in ("existing", "recomputed", "kept")}
    # recomputed: what fix writes for the three links it changes; their inertials as
    # written where valid (triangle); kept: the base's, which fix keeps
    assert n_boxes == {"existing": 1, "recomputed": 3, "kept": 1}
    for source, n in n_boxes.items():
        mesh = next(t for t in fig.data if t.name == f"{SOURCE_NAMES[source]}: boxes")
        assert len(mesh.x) == 8 * n and len(mesh.i) == 12 * n
        assert not mesh.showlegend and mesh.opacity < 0.5
        # the legend entry is the edges' opaque line: legible, and the group's toggle
        edges = next(t for t in fig.data if t.name == SOURCE_NAMES[source])
        assert edges.legendgroup == source and len(edges.x) == 36 * n
        assert edges.showlegend and edges.mode == "lines"
    meshes = [t for t in fig.data if t.type == "mesh3d"
              and t.legendgroup in ("geometry", "changed geometry")]
    assert len(meshes) == 4  # one trace per link that has geometry
    changed = {r.name for r in hand_data.rows if r.fix.changed}
    assert {t.hovertemplate.split("<")[0] for t in meshes
            if t.legendgroup == "changed geometry"} == changed - {EVIL}
    squares = [t for t in fig.data if t.type == "scatter3d" and t.showlegend
               and t.mode == "markers"]
    assert {t.legendgroup for t in squares} == {"geometry", "changed geometry"}


def test_the_links_fix_changes_are_named_in_the_view(hand_data):
    fig = scene_figure(hand_data)
    names = [a.text for a in fig.layout.scene.annotations]
    changed = [r.name for r in hand_data.rows if r.fix.changed]
    assert sorted(names) == sorted(f"<b>{n}</b>" for n in changed)
    offsets = [(a.ax, a.ay) for a in fig.layout.scene.annotations]
    assert len(set(offsets)) == len(offsets)  # neighbours point from different sides
    assert "base" not in changed  # kept: not named, not tinted


def _panel_values(fig):
    (bar,) = fig.data
    return dict(zip(bar.y, bar.x, strict=True)), dict(zip(bar.y, bar.marker.color,
                                                          strict=True))


def test_error_figures_draw_the_numbers_of_compare(hand_data):
    series = hand_data.error_series
    figures = error_figures(series, hand_data)
    # --mass keep: no mass changed, so compare's mass panel is left out, as in its PNG.
    assert all(v is None or v < 1e-9 for v in series["mass_error"])
    panels = ERROR_PANELS[:3]
    assert [key for key, _ in figures] == [key for key, _, _, _ in panels]
    for (key, fig), (_, _, _, log) in zip(figures, panels, strict=True):
        shown, _ = _panel_values(fig)
        assert sorted(shown) == sorted(series["links"])
        for link, value in zip(series["links"], series[key], strict=True):
            if value is None:
                assert shown[link] is None
            elif log and value > 0:
                assert shown[link] == pytest.approx(value)
            elif not log:
                assert shown[link] == value


def test_error_bars_are_coloured_and_ranked_by_what_fix_does(hand_data):
    """A link fix keeps is not painted as an error, whatever its numbers; the links fix
    changes come first."""
    _, fig = error_figures(hand_data.error_series, hand_data)[0]
    _, colors = _panel_values(fig)
    verdicts = {r.name: r.fix for r in hand_data.rows}
    for link, color in colors.items():
        assert color == (COLORS["existing"] if verdicts[link].changed else COLORS["kept"])
    order = list(fig.data[0].y)
    assert order[-1] == "base" and all(verdicts[n].changed for n in order[:-1])


def test_error_figures_show_the_mass_panel_when_masses_changed(hand_urdf):
    data = collect(hand_urdf, FixOptions(mass="density"))
    assert len(error_figures(data.error_series, data)) == len(ERROR_PANELS)


def test_error_series_is_compares_own(hand_urdf, hand_data):
    from urdfinertia.analysis.compare import compare_with_geometry

    again = error_series(compare_with_geometry(hand_urdf, FixOptions()))
    assert json.dumps(again, sort_keys=True) == json.dumps(hand_data.error_series,
                                                           sort_keys=True)


# --- the page -----------------------------------------------------------------------------
def test_page_loads_nothing_from_elsewhere(hand_html):
    tree = lxml_html.fromstring(hand_html)
    assert not tree.xpath("//*[@src]"), "no element may load a resource"
    assert not tree.xpath("//link") and not tree.xpath("//iframe")
    scripts = tree.xpath("//script")
    assert scripts and all(s.get("src") is None for s in scripts)
    # plotly.js itself is inlined, once, and MathJax is not configured.
    assert sum("plotly.js v" in (s.text or "")[:2000] for s in scripts) == 1
    assert "MathJax.Hub.Config" not in hand_html and "window.MathJax" not in hand_html


def test_link_names_cannot_break_out_of_the_page(hand_html):
    assert EVIL not in hand_html
    tree = lxml_html.fromstring(hand_html)
    assert not tree.xpath("//img")
    names = tree.xpath('//table[@id="links"]/tbody/tr/td[1]/div/text()')
    assert EVIL in names


def test_table_has_one_row_per_link_with_its_story(hand_html, hand_data):
    tree = lxml_html.fromstring(hand_html)
    rows = tree.xpath('//table[@id="links"]/tbody/tr')
    assert len(rows) == len(hand_data.rows) == 5
    text = {r.xpath("td[1]/div/text()")[0]: r.text_content() for r in rows}
    assert "invalid: inertia of a positive mass must be positive semi-definite" in \
        text["not_definite"]
    assert "triangle inequality" in text["triangle"]
    assert "no <inertial>" in text[EVIL]
    assert "kept as written" in text["base"] and "plausible" in text["base"]
    # the base is kept as written: its values as written, nothing that fix writes
    assert "as written 2" in text["base"] and "fix writes" not in text["base"]
    assert re.search(r"(recomputed|repaired)", text["not_definite"])
    # the links fix changes first, the kept one after them, the untouched last
    order = [r.xpath("td[1]/div/text()")[0] for r in rows]
    changed = [r.name for r in hand_data.rows if r.fix.changed]
    assert sorted(order[:len(changed)]) == sorted(changed)
    assert order[len(changed)] == "base" and order[-1] == EVIL
    assert [r.get("class") for r in rows][:len(changed)] == ["g-changed"] * len(changed)


def test_the_page_speaks_plainly(hand_html):
    """No internal field names where a person reads; the verdict leads."""
    tree = lxml_html.fromstring(hand_html)
    for script in tree.xpath("//script"):
        script.getparent().remove(script)
    visible = tree.text_content()
    for internal in ("com_distance_rel", "inertia_rel_error", "axis_angle_deg",
                     "mass_error"):
        assert internal not in visible, internal
    assert not re.search(r"\de-(1[3-9]|[2-9]\d)", visible)  # no round-off printed
    verdict = tree.xpath('//div[@class="verdict"]')[0].text_content()
    assert verdict.startswith("fix changes 3 of 5 links")
    assert "keeps 1 as written" in verdict


def test_round_off_is_shown_as_zero():
    assert vec([-0.175, 2.203e-19, -8.175e-20]) == "-0.175 0 0"
    assert vec([0.45, 0.625, 0.625]) == "0.45 0.625 0.625"
    assert position([3e-19, -1e-20, 0.0]) == "0 0 0"  # under a picometre: round-off
    assert vec([3e-7, 1e-20, 0.0]) == "3e-07 0 0"  # relative to the largest component
    assert position([7.98e-06, 0.08859, -0.003552]) == "7.98e-06 0.08859 -0.003552"


def test_long_notes_fold(hand_data):
    """A row of many per-body repair notes is a count that opens, not a tall cell."""
    import dataclasses

    from urdfinertia.render.report_table import notes, notes_cell

    row = rows_by_name(hand_data)["triangle"]
    short = notes_cell(row)
    assert "<details>" not in short and short  # two short notes stay as they are
    from urdfinertia.findings import Finding
    from urdfinertia.rules import Rule

    bodies = tuple(f"collision[0] body {k}: merged 1751 duplicate vertices" for k in range(9))
    said = tuple(Finding(Rule.MESH_REPAIRED, row.name, b, None, "collision[0]")
                 for b in bodies)
    many = dataclasses.replace(row, fix=dataclasses.replace(
        row.fix, findings=row.fix.findings + said))
    folded = notes_cell(many)
    assert folded.startswith(f"<details><summary>{len(notes(many))} notes")
    assert all(b in folded for b in bodies)  # nothing dropped, only folded


def test_page_counts_its_plots_for_whoever_waits_on_them(hand_html):
    tree = lxml_html.fromstring(hand_html)
    figures = int(tree.xpath("//body/@data-figures")[0])
    divs = tree.xpath('//div[@class="plot"]/@id')
    assert figures == len(divs) == 4  # the view and three panels (no mass panel)
    assert sorted(divs) == ["errors-1", "errors-2", "errors-3", "view3d"]
    for div in divs:  # each is drawn by the script at the end of the page
        assert f'"{div}":{{"data":' in hand_html


# --- the command --------------------------------------------------------------------------
def test_cli_writes_the_report(tmp_path, robots_dir):
    out = tmp_path / "nm7mar.html"
    rc = main(["report", str(robots_dir / "nm7mar.urdf"), "--spec",
               str(robots_dir / "nm7mar.inertia.toml"), "-o", str(out)])
    assert rc == 0
    page = out.read_text(encoding="utf-8")
    assert "Inertia report: nm7mar" in page
    tree = lxml_html.fromstring(page)
    urdf_links = (robots_dir / "nm7mar.urdf").read_text().count("<link name=")
    assert len(tree.xpath('//table[@id="links"]/tbody/tr')) == urdf_links
    assert "spec" in tree.xpath('//p[@class="meta"]')[0].text_content()
    # With the spec, the geometry column names it.
    assert "spec:" in tree.xpath('//table[@id="links"]')[0].text_content()


def test_cli_errors_are_one_line_exit_2(tmp_path, capsys):
    rc = main(["report", str(tmp_path / "nope.urdf"), "-o", str(tmp_path / "x.html")])
    assert rc == 2
    assert "cannot read" in capsys.readouterr().err
    assert not (tmp_path / "x.html").exists()


def test_cli_refuses_a_zero_face_budget(tmp_path, robots_dir):
    with pytest.raises(SystemExit):
        main(["report", str(robots_dir / "nm7mar.urdf"), "-o", str(tmp_path / "x.html"),
              "--view-faces", "0"])


def test_a_sixty_link_robot_stays_under_15_mb(tmp_path, erd_dir):
    urdf = erd_dir / "robots" / "talos_data" / "robots" / "talos_full_v2.urdf"
    out = tmp_path / "talos.html"
    assert main(["report", str(urdf), "-o", str(out)]) == 0
    page = out.read_text(encoding="utf-8")
    n_links = len(lxml_html.fromstring(page).xpath('//table[@id="links"]/tbody/tr'))
    assert n_links >= 30
    size = out.stat().st_size
    print(f"talos_full_v2: {n_links} links, report {size / 1e6:.2f} MB")
    assert size < 15e6
    assert not math.isnan(size)


def _three_balls(tmp_path: Path) -> Path:
    """A robot of three links, each drawn with its own sphere mesh (1280 faces)."""
    import trimesh

    links, joints = [], []
    for i in range(3):
        trimesh.creation.icosphere(3, 0.05 + 0.01 * i).export(tmp_path / f"ball{i}.stl")
        links.append(f"""<link name="l{i}"><inertial><mass value="1"/>
  <inertia ixx="0.001" ixy="0" ixz="0" iyy="0.001" iyz="0" izz="0.001"/></inertial>
  <visual><geometry><mesh filename="ball{i}.stl"/></geometry></visual>
  <collision><geometry><sphere radius="{0.05 + 0.01 * i}"/></geometry></collision></link>""")
        if i:
            joints.append(f"""<joint name="j{i}" type="fixed"><parent link="l{i - 1}"/>
  <child link="l{i}"/><origin xyz="0 0 0.2"/></joint>""")
    urdf = tmp_path / "balls.urdf"
    urdf.write_text(f'<robot name="balls">{"".join(links)}{"".join(joints)}</robot>')
    return urdf


def test_display_copies_are_made_by_workers_into_the_cache(tmp_path, monkeypatch):
    """With -j 2 the display copies the cache lacks are made in worker processes and
    stored; the scene built from them equals the one made in this process."""
    from urdfinertia.batch import display
    from urdfinertia.cache.library import MeshLibrary, mesh_library
    from urdfinertia.cli import build_parser
    from urdfinertia.cli.batch import settings_from_args
    from urdfinertia.descriptions.formats import read_description
    from urdfinertia.render.scene import build_scene, display_paths

    urdf = _three_balls(tmp_path)
    argv = ["report", str(urdf), "-o", str(tmp_path / "r.html"), "-j", "2",
            "--view-faces", "900"]
    args = build_parser(argv)[0].parse_args(argv)
    monkeypatch.setattr(display, "DISPLAY_WORKERS_FROM_BYTES", 0)  # tiny meshes
    meshes = mesh_library(cache_dir=tmp_path / "cache")
    robot, _ = read_description(urdf)
    paths, cap = display_paths(robot, meshes, "visual", 900)
    assert len(paths) == 3 and cap == 300
    assert not any(meshes.display_cached(p, cap) for p in paths)
    display.prepare_display(args.urdf, meshes, args.view, args.view_faces,
                            settings_from_args(args))
    assert all(meshes.display_cached(p, cap) for p in paths)
    here = build_scene(robot, MeshLibrary(), face_budget=900)  # no cache: made here
    there = build_scene(robot, meshes, face_budget=900)
    assert [m.method for m in there.meshes] == ["quadric decimation"] * 3
    for a, b in zip(here.meshes, there.meshes, strict=True):
        np.testing.assert_array_equal(a.vertices, b.vertices)
        np.testing.assert_array_equal(a.faces, b.faces)


def test_report_pages_do_not_depend_on_the_workers(tmp_path, monkeypatch):
    urdf = _three_balls(tmp_path)
    from urdfinertia.batch import display

    monkeypatch.setattr(display, "DISPLAY_WORKERS_FROM_BYTES", 0)
    pages = []
    for jobs in ("1", "2"):
        out = tmp_path / f"r{jobs}.html"
        assert main(["report", str(urdf), "-o", str(out), "-j", jobs, "--view-faces", "900",
                     "--cache-dir", str(tmp_path / f"cache{jobs}")]) == 0
        pages.append(out.read_bytes())
    assert pages[0] == pages[1]
