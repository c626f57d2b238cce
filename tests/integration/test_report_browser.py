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


def _open(browser, path: Path, screenshot: Path) -> dict:
    seen = {"console": [], "errors": [], "requests": []}
    page = browser.new_page(viewport={"width": 1200, "height": 900})
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
        page.screenshot(path=str(screenshot), full_page=True)
    finally:
        page.close()
    extra = os.environ.get("RVSIM_SCREENSHOTS")
    if extra:
        shutil.copy(screenshot, Path(extra) / screenshot.name)
    return seen


def _check(seen: dict, min_images: int) -> None:
    assert not [c for c in seen["console"] if c.startswith(("error", "warning"))], seen
    assert not seen["errors"]
    assert seen["broken"] == 0 and seen["images"] >= min_images
    assert [r for r in seen["requests"] if not r.startswith(("file:", "data:"))] == []
    assert len(seen["text"]) > 500


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
