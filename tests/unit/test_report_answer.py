"""The allocation report's answer says which targets are met by the allocation's own test: a
rigidity target is a lower bound (issue 34 item 2; no run: a result dict as allocate writes)."""

import pytest

from rvsim.analysis.headline import ltca_rows
from rvsim.parameters.rating import contact_stress_verdict
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


@pytest.mark.parametrize("stress, verdict, warned", [
    (623e6, "below the static limit (16 % of 4000 MPa)", False),
    (4000e6, "below the static limit (100 % of 4000 MPa)", False),
    (4200e6, "above the static limit (105 % of 4000 MPa): permanent deformation expected",
     True),
    (float("nan"), "not available", False)])
def test_contact_stress_against_the_static_limit(stress, verdict, warned):
    """ISO 76's 4000 MPa (rating.static_contact_stress): a verdict, and a warning above it
    (a result, not refused)."""
    text, warning = contact_stress_verdict(stress, 4000e6)
    assert text == verdict
    assert (warning == "largest contact stress 4200 MPa is above the static limit 4000 MPa "
                       "(rating.static_contact_stress): permanent deformation expected"
            if warned else warning is None)


def test_ltca_answer_without_a_limit_gives_no_verdict():
    row = ltca_rows({"max_contact_stress_mpa": 600.0, "torque_nm": 300.0}, 412.0)[4]
    assert row == ("largest pin-disc contact stress (Hertz)", "600 MPa", "-", "-")
