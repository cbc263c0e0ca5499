"""Size and load time of ``urdf-inertia report`` pages in headless Chromium.

    .venv/bin/python scripts/bench_report.py ROBOT.urdf [...] [--screenshot PNG] [--runs N]

For each URDF: writes the report (timing it), prints its size, opens it from disk in
headless Debian Chromium through ChromeDriver (``scripts/install_chromium.sh`` installs
both) and prints the time until every plot is drawn, the console errors and the network
requests the page made. ``load_in_chromium`` is also what tests/test_report_browser.py
uses.
"""

from __future__ import annotations

import argparse
import json
import shutil
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
CHROMIUM = "/usr/bin/chromium"
CHROMEDRIVER = "/usr/bin/chromedriver"
#: The flags this machine needs (no sandbox as root, no background traffic), and software
#: WebGL: headless Chromium without a GPU refuses WebGL unless SwiftShader is allowed.
CHROMIUM_FLAGS = (
    "--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
    "--disable-background-networking", "--disable-component-update", "--disable-sync",
    "--enable-unsafe-swiftshader", "--hide-scrollbars",
)
#: Window size of a page load (CSS pixels) unless the caller asks for another width.
WINDOW = (1400, 1100)
#: Tallest full-page screenshot (pixels): a long table beyond it is cut.
MAX_SHOT_HEIGHT = 12000
#: URL schemes that are not network requests.
LOCAL_SCHEMES = ("data:", "blob:", "about:")


@dataclass(frozen=True)
class PageLoad:
    """What happened when a report was opened.

    seconds : wall time from navigation start until every plot reported being drawn.
    first_paint : seconds from navigation start to the first contentful paint (the
        text and the table are readable from then on; plots come later).
    console_errors : SEVERE entries of the browser console (JS errors included).
    console_other : every other console entry, for the record.
    requests : URLs the page requested besides itself (none expected).
    rendered : how many plots finished drawing, and how many the page has.
    overflow : CSS pixels the page is wider than the window (0: no sideways scrolling).
    probed : the value of the caller's ``probe`` script, run once every plot was drawn.
    """

    seconds: float
    first_paint: float
    console_errors: tuple[str, ...]
    console_other: tuple[str, ...]
    requests: tuple[str, ...]
    rendered: tuple[int, int]
    webgl: bool
    overflow: int = 0
    #: what ``probe`` (a script run once every plot is drawn) returned
    probed: object = None


def install_chromium() -> bool:
    """Run scripts/install_chromium.sh; True when chromium and chromedriver are there."""
    if shutil.which("chromium") and shutil.which("chromedriver"):
        return True
    done = subprocess.run(["bash", str(ROOT / "scripts" / "install_chromium.sh")],
                          capture_output=True, text=True)
    if done.returncode != 0:
        sys.stderr.write(done.stdout[-2000:] + done.stderr[-2000:])
    return done.returncode == 0 and bool(shutil.which("chromedriver"))


def load_in_chromium(html: Path, screenshot: Path | None = None,
                     timeout: float = 60.0, width: int = WINDOW[0],
                     full_page: bool = False, probe: str | None = None) -> PageLoad:
    """Open ``html`` (a local file) in a fresh headless Chromium ``width`` CSS pixels wide
    and watch it load; ``screenshot``: a PNG of the window, or with ``full_page`` of the
    whole page (the window stretched to its height, at most ``MAX_SHOT_HEIGHT``)."""
    from selenium import webdriver
    from selenium.webdriver.chrome.service import Service

    profile = tempfile.mkdtemp(prefix="urdfinertia-chromium-")
    options = webdriver.ChromeOptions()
    options.binary_location = CHROMIUM
    for flag in (*CHROMIUM_FLAGS, f"--window-size={width},{WINDOW[1]}",
                 f"--user-data-dir={profile}"):
        options.add_argument(flag)
    options.set_capability("goog:loggingPrefs", {"browser": "ALL", "performance": "ALL"})
    driver = webdriver.Chrome(options=options, service=Service(CHROMEDRIVER))
    try:
        url = Path(html).resolve().as_uri()
        start = time.perf_counter()
        driver.get(url)  # returns after the load event
        wanted = int(driver.execute_script("return +document.body.dataset.figures || 0"))
        done = 0
        while time.perf_counter() - start < timeout:
            done = int(driver.execute_script("return window.urdfInertiaRendered || 0"))
            if done >= wanted:
                break
            time.sleep(0.02)
        seconds = time.perf_counter() - start
        first_paint = float(driver.execute_script(
            "var p = performance.getEntriesByName('first-contentful-paint');"
            "return p.length ? p[0].startTime : NaN")) / 1000
        webgl = bool(driver.execute_script(
            "return !!document.createElement('canvas').getContext('webgl')"))
        overflow = int(driver.execute_script(
            "return document.documentElement.scrollWidth - window.innerWidth"))
        probed = driver.execute_script(probe) if probe is not None else None
        if screenshot is not None:
            if full_page:
                height = int(driver.execute_script(
                    "return document.documentElement.scrollHeight"))
                driver.set_window_size(width, min(height + 150, MAX_SHOT_HEIGHT))
                time.sleep(0.7)  # the plots redraw at the new size
            time.sleep(0.3)  # let the WebGL canvas present its first frame
            driver.save_screenshot(str(screenshot))
        console = driver.get_log("browser")
        perf = driver.get_log("performance")
    finally:
        driver.quit()
        shutil.rmtree(profile, ignore_errors=True)
    requests = []
    for entry in perf:
        message = json.loads(entry["message"])["message"]
        if message.get("method") != "Network.requestWillBeSent":
            continue
        params = message["params"]
        req = params["request"]["url"]
        # Chromium's own start page (chrome://...) loads in the same log before ours.
        ours = params.get("documentURL") == url or not req.startswith("chrome")
        if ours and req != url and not req.startswith(LOCAL_SCHEMES):
            requests.append(req)
    errors = tuple(e["message"] for e in console if e["level"] == "SEVERE")
    other = tuple(f"{e['level']}: {e['message']}" for e in console if e["level"] != "SEVERE")
    return PageLoad(seconds, first_paint, errors, other, tuple(requests), (done, wanted), webgl,
                    overflow, probed)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("urdf", nargs="+", type=Path)
    ap.add_argument("--out", type=Path, default=Path(tempfile.gettempdir()),
                    help="folder for the HTML files")
    ap.add_argument("--screenshot", type=Path, help="PNG of the first robot's page")
    ap.add_argument("--runs", type=int, default=3, help="page loads per robot")
    ap.add_argument("--spec", type=Path, help="decomposition spec passed to every report")
    args = ap.parse_args(argv)
    if not install_chromium():
        print("chromium/chromedriver missing and scripts/install_chromium.sh failed")
        return 1
    from urdfinertia.cli import main as cli

    for n, urdf in enumerate(args.urdf):
        html = args.out / f"{urdf.stem}-report.html"
        t0 = time.perf_counter()
        spec = ["--spec", str(args.spec)] if args.spec else []
        rc = cli(["report", str(urdf), "-o", str(html), *spec])
        build = time.perf_counter() - t0
        if rc != 0:
            return rc
        size = html.stat().st_size
        loads = []
        for run in range(args.runs):
            shot = args.screenshot if (n == 0 and run == 0) else None
            loads.append(load_in_chromium(html, shot))
        times = sorted(x.seconds for x in loads)
        paints = sorted(x.first_paint for x in loads)
        last = loads[-1]
        print(f"{urdf.name}: {size / 1e6:.2f} MB, built in {build:.1f} s, first paint "
              f"{' / '.join(f'{t:.2f}' for t in paints)} s, all plots drawn "
              f"{' / '.join(f'{t:.2f}' for t in times)} s (sorted, {args.runs} loads), "
              f"plots drawn {last.rendered[0]}/{last.rendered[1]}, webgl {last.webgl}, "
              f"console errors {len(last.console_errors)}, network requests "
              f"{len(last.requests)}")
        for line in (*last.console_errors, *last.console_other, *last.requests):
            print("   ", line[:300])
    return 0


if __name__ == "__main__":
    sys.exit(main())
