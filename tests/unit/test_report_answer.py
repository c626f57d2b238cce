"""The allocation report's answer says which targets are met by the allocation's own test: a
rigidity target is a lower bound (issue 34 item 2; no run: a result dict as allocate writes)."""

from rvsim.tolerance.report import write_allocation_report
from tests.integration.answer_block import answer


def test_allocation_answer_knows_lower_bounds(tmp_path):
    result = {"study": "s", "status": "ok", "cost": 8.0, "cost_start": 10.0, "evaluations": 3,
              "samples": 4, "binding_share": 0.0, "tolerances": [{"name": "pin_radius"}],
              "targets": [
                  {"target": "ate_p95=0.30", "metric": "ate_arcmin", "percentile": 95.0,
                   "limit": 0.3, "achieved": 0.31, "at_tightest": 0.2},
                  {"target": "torsional_rigidity_p5=200", "percentile": 5.0,
                   "metric": "torsional_rigidity_nm_per_arcmin", "limit": 200.0,
                   "achieved": 250.0, "at_tightest": 260.0}]}
    rows = answer(write_allocation_report(tmp_path, result).read_text())
    assert rows["target ate_p95=0.30"] == ["0.31", "0.3", "not met"]
    assert rows["target torsional_rigidity_p5=200"] == ["250", "200", "met"]
    assert rows["relative cost (1 = the tolerances as given)"][0] == "0.8"
