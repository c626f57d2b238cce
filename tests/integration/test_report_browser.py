"""The HTML reports (study, run, bench, ltca, hysteresis) in a real browser: headless Chromium
(Debian's package) via Playwright, one browser for the module (each report in a page of its own).

Fails on console errors, page errors, broken images, network requests other than the file
itself, or an empty page.  Screenshots go to the test's tmp folder (and, when RVSIM_SCREENSHOTS
names a folder, there too, for a person to look at).
"""

import os
import shutil
from pathlib import Path

import pytest

from rvsim.doe import load_study, run, write_study_outputs
from rvsim.report import write_study_report

CHROMIUM = shutil.which("chromium") or shutil.which("chromium-browser")
pytestmark = pytest.mark.skipif(
    CHROMIUM is None and not os.environ.get("CI"), reason="chromium not installed")

ARGS = ["--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
        "--disable-background-networking", "--disable-component-update", "--disable-sync"]


@pytest.fixture(scope="module")
def browser():
    """One headless Chromium for the module's pages (starting one costs more than a page)."""
    from playwright.sync_api import sync_playwright

    assert CHROMIUM, "chromium is required in CI (the README's test command installs it)"
    with sync_playwright() as p:
        chromium = p.chromium.launch(executable_path=CHROMIUM, args=ARGS)
        try:
            yield chromium
        finally:
            chromium.close()


#: the widths every report is read at (issue 34 item 2: a desktop and a narrow window)
WIDTHS = (1280, 800)

#: at each width: the page's own width, the right edge of its widest image and table, and
#: the tables that do not scroll inside their own box
LAYOUT = """() => [document.documentElement.scrollWidth,
  Math.max(0, ...Array.from(document.querySelectorAll('img, table'))
                      .map(e => e.getBoundingClientRect().right)),
  Array.from(document.querySelectorAll('table'))
       .filter(t => getComputedStyle(t).overflowX !== 'auto').length]"""


def _open(browser, path: Path, screenshot: Path) -> dict:
    """``path`` in one page of ``browser``, read at each of :data:`WIDTHS` (the page resized,
    not a new browser); the screenshot of the first width to ``screenshot`` (of every width
    when RVSIM_SCREENSHOTS names a folder)."""
    seen = {"console": [], "errors": [], "requests": [], "layout": {}}
    page = browser.new_page(viewport={"width": WIDTHS[0], "height": 900})
    extra = os.environ.get("RVSIM_SCREENSHOTS")
    try:
        page.on("console", lambda m: seen["console"].append(f"{m.type}: {m.text}"))
        page.on("pageerror", lambda e: seen["errors"].append(str(e)))
        page.on("request", lambda r: seen["requests"].append(r.url))
        page.goto(path.resolve().as_uri())
        page.wait_for_load_state("load")
        seen["images"] = page.evaluate("document.images.length")
        seen["broken"] = page.evaluate(
            "Array.from(document.images).filter(i => !(i.complete && i.naturalWidth > 0))"
            ".length")
        seen["text"] = page.inner_text("body")
        for width in WIDTHS:
            page.set_viewport_size({"width": width, "height": 900})
            seen["layout"][width] = page.evaluate(LAYOUT)
            if width == WIDTHS[0]:
                page.screenshot(path=str(screenshot), full_page=True)
            if extra:
                name = f"{screenshot.stem}_{width}{screenshot.suffix}"
                page.screenshot(path=str(Path(extra) / name), full_page=True)
    finally:
        page.close()
    seen["bytes"] = path.stat().st_size
    return seen


def _check(seen: dict, min_images: int) -> None:
    assert not [c for c in seen["console"] if c.startswith(("error", "warning"))], seen
    assert not seen["errors"]
    assert seen["broken"] == 0 and seen["images"] >= min_images
    assert [r for r in seen["requests"] if not r.startswith(("file:", "data:"))] == []
    assert len(seen["text"]) > 500
    for width, (page_width, right, fixed) in seen["layout"].items():
        # nothing scrolls the page sideways: images shrink, tables scroll in their own box
        assert page_width <= width and right <= width and fixed == 0, (width, seen["layout"])
    assert seen["bytes"] < 1_000_000                    # self-contained and under 1 MB


def test_study_report_in_browser(tmp_path, small_study, browser):
    out = tmp_path / "study"
    results = run(load_study(small_study), out, workers=1, progress=False)
    write_study_outputs(out, results, ["H", "I", "E"])
    report = write_study_report(out)
    seen = _open(browser, report, tmp_path / "study_report.png")
    _check(seen, min_images=4)
    assert "mean TE for t \u2265 0.3 s" in seen["text"]  # the study's own steady window
    for heading in ("Study definition", "Input and output speed", "Transmission error",
                    "TE spectrum", "Table 3 layout", "Table 8 layout", "Main effects",
                    "Signal-to-noise"):
        assert heading in seen["text"]
    assert (tmp_path / "study_report.png").stat().st_size > 10_000


def test_run_report_in_browser(tmp_path, cli, browser):
    from .test_run_report import SHORT

    report = tmp_path / "run.html"
    schedule = [a for name, value in SHORT.items() for a in ("--set", f"{name}={value}")]
    res = cli("simulate", *schedule, "--report", str(report))
    assert res.code == 0, res.err
    seen = _open(browser, report, tmp_path / "run_report.png")
    _check(seen, min_images=4)
    assert "Pin contact forces" in seen["text"]


def test_testrig_report_in_browser(tmp_path, browser):
    from rvsim.cli import main

    report = tmp_path / "bench.html"
    assert main(["testrig", "docs/examples/testrig", "--params",
                 "docs/examples/testrig_start.toml", "--compare", "--report",
                 str(report)]) == 0
    seen = _open(browser, report, tmp_path / "testrig_report.png")
    _check(seen, min_images=3)
    assert "lost_motion_arcmin" in seen["text"] and "difference" in seen["text"]


@pytest.mark.parametrize("command, headings", [
    ("ltca", ("Transmission error over one output revolution", "TE order spectrum",
              "Largest lines", "Pin load distribution")),
    ("hysteresis", ("Catalogue quantities", "Torque-angle curve", "GB/T 35089-2018")),
])
def test_quasistatic_pages_in_browser(tmp_path, cli, browser, command, headings):
    page = tmp_path / f"{command}.html"
    res = cli(command, "--set", "I=0.01", "--report", str(page))
    assert res.code == 0, res.err
    seen = _open(browser, page, tmp_path / f"{command}.png")
    _check(seen, min_images=1 if command == "hysteresis" else 3)
    for heading in headings:
        assert heading in seen["text"]


def test_efficiency_tolerance_and_allocation_reports_in_browser(tmp_path, cli, browser,
                                                                small_run):
    """The reports of issue 34 item 2's other commands: the efficiency heat map, the
    tolerance report's flagged Sobol indices, the allocation's before/after and convergence
    plots (from docs/validation_data's allocation of the RV-40E tolerances, written by an
    older version: no status_text, SciPy's message as its status)."""
    import json

    from rvsim.tolerance.report import write_allocation_report
    page = tmp_path / "efficiency.html"
    res = cli("efficiency", "--params", "RV-40E-bearings", "--speeds", "500,1500",
              "--torques", "206,412", "--report", str(page))
    assert res.code == 0, res.err
    seen = _open(browser, page, tmp_path / "efficiency.png")
    _check(seen, min_images=1)
    assert "Efficiency [%]" in seen["text"] and "1500 rpm" in seen["text"]

    res, folder = small_run            # conftest.py: SMALL's tolerance study, --sobol 2
    assert res.code == 0, res.err
    seen = _open(browser, folder / "report.html", tmp_path / "tolerance.png")
    _check(seen, min_images=4)
    # two base samples: intervals far wider than the indices, flagged, with advice
    assert "interval wider than the index" in seen["text"] and "--sobol " in seen["text"]
    assert "unit" in seen["text"] and "N*m/arcmin" in seen["text"]

    result = json.loads((Path(__file__).resolve().parents[2] / "docs" / "validation_data"
                         / "rv40e_allocation_example.json").read_text())
    report = write_allocation_report(tmp_path, result)
    seen = _open(browser, report, tmp_path / "allocation.png")
    _check(seen, min_images=2)
    for heading in ("Before and after", "Convergence", "Tolerances", "Targets"):
        assert heading in seen["text"]


def test_grid_report_in_browser(tmp_path, cli, browser):
    """The speed-torque grid's report (issue 33 item 4) from the smallest grid that makes one:
    one point of the single-stage drive on test_grid.py's short schedule (about 0.3 s
    simulated)."""
    from .test_grid import SHORT

    page = tmp_path / "grid.html"
    res = cli("grid", *SHORT, "--speeds-rpm", "12000", "--torques", "50", "--workers", "1",
              "--out", str(tmp_path / "grid"), "--report", str(page), "--no-progress")
    assert res.code == 0, res.err
    seen = _open(browser, page, tmp_path / "grid.png")
    _check(seen, min_images=2)
    for heading in ("Campbell", "natural frequency", "arcmin"):
        assert heading in seen["text"]
