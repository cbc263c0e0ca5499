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


def color_pixels(png: Path, hex_color: str, tol: int = 40) -> int:
    """Pixels within ``tol`` (per channel, 0-255) of ``hex_color``."""
    import matplotlib.image

    rgb = (matplotlib.image.imread(str(png))[..., :3] * 255).astype(int)
    target = np.array([int(hex_color[i:i + 2], 16) for i in (1, 3, 5)])
    return int(np.all(np.abs(rgb - target) <= tol, axis=-1).sum())


def render(tmp_path: Path, urdf: Path, *extra: str) -> Path:
    out = tmp_path / f"{urdf.stem}.html"
    assert main(["report", str(urdf), "-o", str(out), *extra]) == 0
    return out


def check_page(page: Path, shot: Path):
    load = bench.load_in_chromium(page, shot)
    print(f"{page.name}: {page.stat().st_size / 1e6:.2f} MB, drawn in {load.seconds:.2f} s, "
          f"screenshot {shot}")
    assert load.rendered[1] == 2 and load.rendered[0] == load.rendered[1], load
    assert load.console_errors == ()
    assert load.requests == ()
    assert load.webgl
    assert load.overflow <= 0, "the page scrolls sideways in a 1400 px window"
    # The 3-D view really shows both kinds of box (their edge colours), not a blank canvas.
    for source in ("existing", "recomputed"):
        assert color_pixels(shot, COLORS[source]) > 200, source
    return load


def test_nm7mar_report_in_chromium(chromium, tmp_path, robots_dir):
    page = render(tmp_path, robots_dir / "nm7mar.urdf",
                  "--spec", str(robots_dir / "nm7mar.inertia.toml"))
    check_page(page, tmp_path / "nm7mar.png")


def test_sixty_links_fit_the_window(chromium, tmp_path, erd_dir):
    """A big robot's table (long link names, many findings) fits 1400 px: no sideways
    scrolling, and the page stays under 5 MB."""
    urdf = erd_dir / "robots" / "talos_data" / "robots" / "talos_full_v2.urdf"
    page = render(tmp_path, urdf)
    assert page.stat().st_size < 5e6
    check_page(page, tmp_path / "talos.png")


def test_example_robot_data_report_in_chromium(chromium, tmp_path, erd_dir):
    urdf = erd_dir / "robots" / "ur_description" / "urdf" / "ur5_robot.urdf"
    check_page(render(tmp_path, urdf), tmp_path / "ur5.png")


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
