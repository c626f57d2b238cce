"""The run report says what the speed curve shows (issue 8, item 9)."""

import re

from rvsim.dynamics import simulate
from rvsim.parameters import RV40E, with_values
from rvsim.report import write_run_report
from tests.integration.answer_block import answer

SHORT = {"operating.duration": 0.4, "operating.speed_ramp_time": 0.1,
         "operating.load_start": 0.1, "operating.load_ramp_end": 0.2,
         "operating.steady_start": 0.3}


def test_run_report_describes_the_speed_curve(tmp_path):
    reducer = with_values(RV40E, {**SHORT, "D": True, "K": 0.01})
    result = simulate(reducer)
    page = write_run_report(result, reducer, tmp_path / "run.html").read_text()
    note = re.search(r"<p class='note'>(The input follows.*?)</p>", page).group(1)
    assert "Before the load is applied (t &lt; 0.1 s)" in note
    assert "fluctuating torque of Eq. (20) (41.2 N*m at 20 Hz)" in note
    assert "load of 0.3 kg*m^2" in note and "strongest components" in note
    # the page opens with its answer (issue 34 item 2): this run's figures
    rows = answer(page)
    summary = result.summary()
    assert rows["mean TE, steady window"][0] == f"{summary['te_mean_arcmin']:.4g} arcmin"
    assert rows["mean TE, steady window"][1] == "paper's 36 runs: 0.60-2.27 arcmin"
    assert rows["status"][0] == summary["status"]
