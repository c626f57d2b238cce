"""Reference: the analytical error model against the paper's Table 1.

Source: Table 1 (tests/reference/data/table1_sensitivity.csv, copied from shared/reference).
Tolerances: coefficients to the printed 2 decimals (+-0.005).  Sensitivity indices: the paper
divided by the coefficient already rounded to 0.68, which shifts every index by up to 0.24 %;
the tolerance is that shift plus half a unit of the last printed digit.  Row 9 (K_n) is
computed as Eq. (10) prints it and is NOT expected to match the printed 0.00005
(docs/analytical.md).
"""

import math

import pytest

from rvsim.analytical import sensitivity_table
from rvsim.parameters import RV40E
from tests.conftest import reference_table

TABLE1 = reference_table("table1_sensitivity.csv")
PRINTED = TABLE1.astype(str)  # the printed digits set the tolerance


def _half_unit(text: str) -> float:
    decimals = len(text.split(".")[1]) if "." in text else 0
    return 0.5 * 10.0 ** -decimals


def _terms():
    return {t.symbol: t for t in sensitivity_table(RV40E).terms}


@pytest.mark.parametrize("row", range(8))
def test_rows_1_to_8(row):
    ref = TABLE1.iloc[row]
    term = _terms()[ref.symbol]
    assert term.error * 1e3 == pytest.approx(ref.error_value_mm)
    assert abs(abs(term.coefficient) - abs(ref.coefficient)) <= 0.005
    printed_s = ref.sensitivity_index
    tolerance = 0.0024 * abs(printed_s) + _half_unit(PRINTED.iloc[row].sensitivity_index)
    assert abs(term.sensitivity_index - printed_s) <= tolerance


def test_sign_of_row_6_follows_eq6():
    # Table 1 prints coefficient 0.68 with index -1; Eq. (6) gives -sqrt(1-K1^2)
    term = _terms()["Delta_r_p"]
    assert term.coefficient < 0 and term.sensitivity_index == pytest.approx(-1.0)


def test_every_term_has_the_eq11_form():
    table = sensitivity_table(RV40E)
    scale = 2.0 / (1.5e-3 * 39)
    for t in table.terms:
        assert t.te == pytest.approx(t.coefficient * scale * t.error)
    assert table.mean_te == pytest.approx(sum(t.te for t in table.terms))


def test_row_9_is_computed_from_the_printed_formula():
    term = _terms()["delta_a"]
    k1 = 1.5 * 40 / 82
    root = math.sqrt(1 - k1 * k1)
    kn = 0.016 / (1.5 ** 2 * 39) - (39 / (1.5 * 82 ** 2 * root) + root / (1.5 ** 2 * 39)) * 0.026
    assert term.coefficient == pytest.approx(-kn * 1.5 * 39)
    assert term.coefficient != pytest.approx(TABLE1.iloc[8].coefficient, abs=1e-5)


def test_sensitivity_command_takes_the_reducers_error_values(cli):
    """`rvsim sensitivity --set H=... --set I=...` uses those values for their rows (Table 1's
    for the rest, and for every row without --set)."""
    import json

    from rvsim.analytical import PAPER_TABLE1_ERRORS

    res = cli("sensitivity", "--json")
    assert res.code == 0
    rows = {r["symbol"]: r for r in json.loads(res.out)["terms"]}
    assert all(r["source"] == "Table 1" for r in rows.values())
    assert rows["delta_r_p"]["error_mm"] == pytest.approx(PAPER_TABLE1_ERRORS["delta_r_p"] * 1e3)
    res = cli("sensitivity", "--set", "H=0.01", "--set", "I=0.032", "--json")
    assert res.code == 0
    rows = {r["symbol"]: r for r in json.loads(res.out)["terms"]}
    assert rows["delta_r_p"]["error_mm"] == pytest.approx(0.01)
    assert rows["delta_r_p"]["source"] == "errors.pin_circle_radius"
    assert rows["Delta_r_rp"]["error_mm"] == pytest.approx(0.032)
    assert rows["Delta_r_rp"]["source"] == "errors.equidistant_modification"
    assert rows["delta_r_rp"]["source"] == "Table 1"
    # the term is the coefficient times 2 / (a zc) times the value given
    term = _terms()["delta_r_p"]
    assert rows["delta_r_p"]["te_arcmin"] == pytest.approx(term.te_arcmin * 0.01 / 0.025,
                                                           rel=1e-12)
