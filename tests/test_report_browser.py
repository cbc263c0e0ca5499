"""The report in a real browser: headless Debian Chromium driven through ChromeDriver.

Chromium and ChromeDriver are installed by scripts/install_chromium.sh when missing (apt,
as root); the tests are skipped only when that install fails. Each page must draw all its
plots with no console error and no network request; the screenshot is kept in pytest's
temporary folder (its path is printed) and checked to show the inertia boxes.
"""

from __future__ import annotations

import importlib.util
import sys
from pathlib import Path

import numpy as np
import pytest

from urdfinertia.cli import main
from urdfinertia.render.report import COLORS

ROOT = Path(__file__).resolve().parents[1]


def _bench():
    spec = importlib.util.spec_from_file_location("bench_report",
                                                  ROOT / "scripts" / "bench_report.py")
    module = importlib.util.module_from_spec(spec)
    sys.modules["bench_report"] = module  # dataclasses look their module up there
    spec.loader.exec_module(module)
    return module


bench = _bench()


@pytest.fixture(scope="module")
def chromium() -> None:
    pytest.importorskip("selenium", reason="selenium is a dev dependency: pip install -e .[dev]")
    if not bench.install_chromium():
        pytest.skip("chromium/chromedriver missing and scripts/install_chromium.sh failed")


def color_pixels(png: Path, hex_color: str, tol: int = 40,
                 box: tuple[int, int, int, int] | None = None) -> int:
    """Pixels within ``tol`` (per channel, 0-255) of ``hex_color``, in ``box`` (left, top,
    width, height in pixels) when given."""
    import matplotlib.image

    rgb = (matplotlib.image.imread(str(png))[..., :3] * 255).astype(int)
    if box is not None:
        left, top, width, height = box
        rgb = rgb[top:top + height, left:left + width]
    target = np.array([int(hex_color[i:i + 2], 16) for i in (1, 3, 5)])
    return int(np.all(np.abs(rgb - target) <= tol, axis=-1).sum())


def render(tmp_path: Path, urdf: Path, *extra: str) -> Path:
    out = tmp_path / f"{urdf.stem}.html"
    assert main(["report", str(urdf), "-o", str(out), *extra]) == 0
    return out


#: Run in the page once every plot is drawn: where the 3-D view is, and whether any two
#: titles of the page (headings, the panels' titles) overlap.
PROBE = """
var r = document.getElementById('view3d').getBoundingClientRect();
var titles = Array.from(document.querySelectorAll('h1, h2, h3')).map(function (e) {
  var b = e.getBoundingClientRect(); return [b.left, b.top, b.right, b.bottom]; });
var overlaps = 0;
for (var i = 0; i < titles.length; i++) for (var j = i + 1; j < titles.length; j++) {
  var a = titles[i], b = titles[j];
  if (a[0] < b[2] && b[0] < a[2] && a[1] < b[3] && b[1] < a[3]) overlaps++; }
return {view: [r.left, r.top + window.scrollY, r.width, r.height], overlaps: overlaps,
        labels: getComputedStyle(document.querySelector('#links td'), '::before').content};
"""


def check_page(page: Path, shot: Path, width: int = 1400,
               boxes: tuple[str, ...] = ("existing", "recomputed")):
    load = bench.load_in_chromium(page, shot, width=width, full_page=True, probe=PROBE)
    print(f"{page.name} at {width} px: {page.stat().st_size / 1e6:.2f} MB, drawn in "
          f"{load.seconds:.2f} s, screenshot {shot}")
    assert load.rendered[1] >= 2 and load.rendered[0] == load.rendered[1], load
    assert load.console_errors == ()
    assert load.requests == ()
    assert load.webgl
    assert load.overflow <= 0, f"the page scrolls sideways in a {width} px window"
    assert load.probed["overlaps"] == 0, "titles overlap"
    # The 3-D view really shows both kinds of box (their edge colours), not a blank canvas:
    # counted inside the view, where the legend's two swatches make about 100 pixels; the
    # new boxes' edges are seen through the translucent faces of the old ones (tol 60)
    view = tuple(int(x) for x in load.probed["view"])
    for source in boxes:
        assert color_pixels(shot, COLORS[source], tol=60, box=view) > 300, source
    return load


@pytest.mark.parametrize("width", [1400, 800])
def test_nm7mar_report_in_chromium(chromium, tmp_path, robots_dir, width):
    page = render(tmp_path, robots_dir / "nm7mar.urdf",
                  "--spec", str(robots_dir / "nm7mar.inertia.toml"))
    load = check_page(page, tmp_path / f"nm7mar-{width}.png", width)
    # narrower than the table needs: each row is a card whose cells name their column
    assert (load.probed["labels"] == "none") == (width >= 1400), load.probed


def test_sixty_links_fit_the_window(chromium, tmp_path, erd_dir):
    """A big robot's table (long link names, many findings) fits 1400 px: no sideways
    scrolling, and the page stays under 5 MB."""
    urdf = erd_dir / "robots" / "talos_data" / "robots" / "talos_full_v2.urdf"
    page = render(tmp_path, urdf)
    assert page.stat().st_size < 5e6
    # fix changes three small links (an IMU, two tool frames): the boxes seen are kept ones
    check_page(page, tmp_path / "talos.png", boxes=("kept",))


def test_a_robot_fix_mostly_keeps_is_not_painted_as_errors(chromium, tmp_path, erd_dir):
    """UR5: fix changes its three wrist links and keeps the rest. Their bars are in the
    colour of a kept link, the wrists' in the colour of a changed one, and the view marks
    the wrists (tinted geometry)."""
    urdf = erd_dir / "robots" / "ur_description" / "urdf" / "ur5_robot.urdf"
    for width in (1400, 800):
        shot = tmp_path / f"ur5-{width}.png"
        load = check_page(render(tmp_path, urdf), shot, width, boxes=("existing", "kept"))
        view = tuple(int(x) for x in load.probed["view"])
        from urdfinertia.render.report import COLORS as C

        assert color_pixels(shot, C["kept"], tol=20) > 500  # kept bars and boxes
        assert color_pixels(shot, C["changed geometry"], tol=30, box=view) > 100


def test_the_watcher_sees_console_errors_and_requests(chromium, tmp_path):
    # The checks above must be able to fail: a page that logs an error and fetches an
    # image is caught (the fetch fails, no network here, but it is still a request).
    page = tmp_path / "bad.html"
    page.write_text(
        '<!DOCTYPE html><html><body data-figures="1"><img src="http://example.invalid/x.png">'
        "<script>console.error('boom'); window.urdfInertiaRendered = 1;</script>"
        "</body></html>")
    load = bench.load_in_chromium(page, None)
    assert any("boom" in e for e in load.console_errors)
    assert any("example.invalid" in r for r in load.requests)
