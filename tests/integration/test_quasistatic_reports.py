"""The ltca and hysteresis report pages in a real browser."""

import pytest

from tests.integration.test_report_browser import CHROMIUM, _check, _open

pytestmark = pytest.mark.skipif(CHROMIUM is None, reason="chromium not installed")


@pytest.mark.parametrize("command, headings", [
    ("ltca", ("Transmission error over one output revolution", "TE order spectrum",
              "Largest lines", "Pin load distribution")),
    ("hysteresis", ("Catalogue quantities", "Torque-angle curve", "GB/T 35089-2018")),
])
def test_quasistatic_pages_in_browser(tmp_path, cli, command, headings):
    page = tmp_path / f"{command}.html"
    res = cli(command, "--set", "I=0.01", "--report", str(page))
    assert res.code == 0, res.err
    seen = _open(page, tmp_path / f"{command}.png")
    _check(seen, min_images=1 if command == "hysteresis" else 3)
    for heading in headings:
        assert heading in seen["text"]
