"""Taguchi's S/N ratios and a robust study row's replicate statistics against hand
calculations (issue 33 item 2; docs/model.md "Robust design").

The formulas (Minitab, "What is the signal-to-noise ratio?"; Phadke 1989; docs/model.md section 20):
smaller-the-better -10 log10(mean(y^2)), nominal-the-best 10 log10(ybar^2 / s^2) with the
sample variance (n - 1), larger-the-better -10 log10(mean(1 / y^2)).
"""

import math

import numpy as np
import pytest

from rvsim.analysis.signal_noise import robust_columns, sense, signal_to_noise


# --- S/N ratios: y = (1, 2, 3) by hand ------------------------------------------------------

def test_smaller_the_better_by_hand():
    # mean(y^2) = (1 + 4 + 9) / 3 = 14/3; -10 log10(14/3) = -6.690067810
    assert signal_to_noise([1.0, 2.0, 3.0], "smaller") == pytest.approx(-6.690067810, abs=1e-9)


def test_nominal_the_best_by_hand():
    # ybar = 2, s^2 = ((1-2)^2 + 0 + (3-2)^2) / (3 - 1) = 1; 10 log10(4) = 6.020599913
    assert signal_to_noise([1.0, 2.0, 3.0], "nominal") == pytest.approx(6.020599913, abs=1e-9)


def test_larger_the_better_by_hand():
    # mean(1/y^2) = (1 + 1/4 + 1/9) / 3 = 49/108; -10 log10(49/108) = 3.432277
    expected = -10.0 * math.log10(49.0 / 108.0)
    assert expected == pytest.approx(3.4322768, abs=1e-7)
    assert signal_to_noise([1.0, 2.0, 3.0], "larger") == pytest.approx(expected, abs=1e-12)


def test_one_value_smaller_the_better_is_the_existing_ratio():
    from rvsim.analysis.anova import signal_to_noise_smaller

    # 0.5 arcmin: -10 log10(0.25) = +6.0206 dB, the same function the paper's analysis uses
    assert signal_to_noise([0.5], "smaller") == signal_to_noise_smaller([0.5])
    assert signal_to_noise([0.5], "smaller") == pytest.approx(6.020599913, abs=1e-9)


def test_scaling_leaves_nominal_the_best_unchanged_and_shifts_the_others():
    y = np.array([0.8, 1.1, 0.9, 1.3])
    # ybar^2 / s^2 is scale free; a factor 10 moves smaller by -20 dB and larger by +20 dB
    assert signal_to_noise(10 * y, "nominal") == pytest.approx(signal_to_noise(y, "nominal"),
                                                               abs=1e-12)
    assert signal_to_noise(10 * y, "smaller") == pytest.approx(
        signal_to_noise(y, "smaller") - 20.0, abs=1e-12)
    assert signal_to_noise(10 * y, "larger") == pytest.approx(
        signal_to_noise(y, "larger") + 20.0, abs=1e-12)


def test_undefined_ratios_are_none_not_infinite():
    assert signal_to_noise([0.0, 1.0], "larger") is None          # 1/0
    assert signal_to_noise([2.0, 2.0, 2.0], "nominal") is None    # no spread
    assert signal_to_noise([2.0], "nominal") is None              # one value: no s
    assert signal_to_noise([0.0, 0.0], "smaller") is None         # log10(0)
    # a zero among others is a finite smaller-the-better ratio: -10 log10(1/2) = 3.0103
    assert signal_to_noise([0.0, 1.0], "smaller") == pytest.approx(3.010299957, abs=1e-9)
    with pytest.raises(ValueError):
        signal_to_noise([1.0], "biggest")


def test_each_metric_has_its_own_sense_and_columns():
    assert sense("ate_arcmin") == "smaller" and sense("lost_motion_arcmin") == "smaller"
    assert sense("torsional_rigidity_nm_per_arcmin") == "larger"
    cols = robust_columns(["ate_arcmin"])
    assert cols == ("ate_arcmin_mean", "ate_arcmin_std", "ate_arcmin_p5", "ate_arcmin_p50",
                    "ate_arcmin_p95", "ate_arcmin_sn", "ate_arcmin_sn_smaller",
                    "ate_arcmin_sn_nominal", "ate_arcmin_sn_larger")


# --- a row's statistics ------------------------------------------------------------------------

def test_row_statistics_by_hand():
    from rvsim.tolerance.robust import _row_metrics

    row = _row_metrics({"ate_arcmin": [1.0, 2.0, 3.0, 4.0, 5.0],
                        "torsional_rigidity_nm_per_arcmin": [100.0, 100.0, 100.0, 100.0, 200.0]},
                       {"replicates": 5})
    assert row["replicates"] == 5
    assert row["ate_arcmin_mean"] == 3.0
    # sample standard deviation: sqrt(10 / 4)
    assert row["ate_arcmin_std"] == pytest.approx(math.sqrt(2.5), abs=1e-12)
    # linear interpolation between order statistics: position 0.05 * 4 = 0.2 -> 1.2
    assert row["ate_arcmin_p5"] == pytest.approx(1.2, abs=1e-12)
    assert row["ate_arcmin_p50"] == 3.0
    assert row["ate_arcmin_p95"] == pytest.approx(4.8, abs=1e-12)
    # mean(y^2) = 55/5 = 11
    assert row["ate_arcmin_sn_smaller"] == pytest.approx(-10 * math.log10(11.0), abs=1e-12)
    assert row["ate_arcmin_sn"] == row["ate_arcmin_sn_smaller"]
    # nominal: 10 log10(9 / 2.5)
    assert row["ate_arcmin_sn_nominal"] == pytest.approx(10 * math.log10(9 / 2.5), abs=1e-12)
    # the rigidity's own S/N is larger-the-better: mean(1/y^2) = (4e-4 + 2.5e-5) / 5
    rig = row["torsional_rigidity_nm_per_arcmin_sn"]
    assert rig == row["torsional_rigidity_nm_per_arcmin_sn_larger"]
    assert rig == pytest.approx(-10 * math.log10((4 * 1e-4 + 2.5e-5) / 5), abs=1e-12)


def test_replicates_draw_the_same_noise_for_every_row_and_summarise_the_engine():
    """A stand-in engine returns a drawn part's error: the row statistics are those of the
    draws, and every row meets the same draws (Taguchi's outer array, common random numbers)."""
    from rvsim.doe.engines import EVALUATORS
    from rvsim.doe.study import Study, StudyFactor
    from rvsim.tolerance.robust import evaluate_replicates, with_noise
    from rvsim.tolerance.spec import Tolerance

    def fake(reducer, **_):
        return {"status": "ok", "metrics": {"ate_arcmin": 1.0 + 1e3 * reducer.parts.pin_radius[0]}}

    EVALUATORS["robust-test"] = fake
    try:
        study = Study("s", (StudyFactor("H", "errors.pin_circle_radius", (0.01, 0.03)),),
                      design="L4", engine="quasi-static")
        study = with_noise(study, (Tolerance("pin_radius", 0.002, "normal"),), samples=4, seed=7)
        noise = study.noise
        rows = [evaluate_replicates(r, noise=noise, engine="robust-test",
                                    metrics=("ate_arcmin",), time_step=None)
                for r in study.reducers()]
        # what the draws are: sample k's first pin, from default_rng([7, k]) through the
        # normal truncated at 3 sigma, times 2 um
        expected = []
        for k in range(4):
            drawn = noise.spec.realise(np.random.default_rng([7, k]).random(noise.spec.dimension),
                                       nominal=study.reducers()[0])
            expected.append(1.0 + 1e3 * drawn.parts.pin_radius[0])
        assert all(abs(e - 1.0) <= 0.002 * 1e-3 * 1e3 + 1e-15 for e in expected)
        for row in rows:
            assert row["status"] == "ok" and row["metrics"]["replicates_ok"] == 4
            assert row["metrics"]["ate_arcmin_mean"] == pytest.approx(np.mean(expected),
                                                                      abs=1e-15)
            assert row["metrics"]["ate_arcmin_std"] == pytest.approx(np.std(expected, ddof=1),
                                                                     rel=1e-12)
        assert rows[0]["metrics"] == rows[1]["metrics"]
    finally:
        del EVALUATORS["robust-test"]


def test_a_failed_replicate_fails_the_row_with_its_reason():
    from rvsim.doe.engines import EVALUATORS
    from rvsim.doe.study import Study, StudyFactor
    from rvsim.tolerance.robust import evaluate_replicates, with_noise
    from rvsim.tolerance.spec import Tolerance

    calls = []

    def fake(reducer, **_):
        calls.append(1)
        if len(calls) == 2:
            return {"status": "not_converged", "error": "ltca not converged", "metrics": {}}
        return {"status": "ok", "metrics": {"ate_arcmin": 1.0}}

    EVALUATORS["robust-test"] = fake
    try:
        study = Study("s", (StudyFactor("H", "errors.pin_circle_radius", (0.01, 0.03)),),
                      design="L4", engine="quasi-static")
        study = with_noise(study, (Tolerance("pin_radius", 0.002),), samples=3)
        row = evaluate_replicates(study.reducers()[0], noise=study.noise, engine="robust-test",
                                  metrics=("ate_arcmin",), time_step=None)
        assert row["status"] == "not_converged"
        assert row["error"] == "replicate 1: ltca not converged"
        assert "ate_arcmin_mean" not in row["metrics"]
    finally:
        del EVALUATORS["robust-test"]


# --- a plain study's S/N table: one value per run, the response's own sense (issue 33) -----

def _l4(response: str, values) -> "pd.DataFrame":
    import pandas as pd

    # L4: A = 1 1 2 2, B = 1 2 1 2
    return pd.DataFrame({"A": [1, 1, 2, 2], "B": [1, 2, 1, 2], response: values})


def test_a_plain_table_s_n_larger_the_better_by_hand():
    from rvsim.analysis.anova import sn_response_table

    # rigidity y = 10, 20, 40, 80 N*m/arcmin; larger-the-better one value: 20 log10(y)
    table = _l4("torsional_rigidity_nm_per_arcmin", [10.0, 20.0, 40.0, 80.0])
    sn = sn_response_table(table, "torsional_rigidity_nm_per_arcmin", ["A", "B"], "larger")
    # A1: (20 + 20 log10 20) / 2 = 23.0103 dB; A2: (20 log10 40 + 20 log10 80) / 2 = 35.0515
    assert sn.loc["A", "level 1"] == pytest.approx(23.010299957, abs=1e-9)
    assert sn.loc["A", "level 2"] == pytest.approx(35.051499783, abs=1e-9)
    # B1: (20 + 32.0412) / 2 = 26.0206; B2: (26.0206 + 38.0618) / 2 = 32.0412
    assert sn.loc["B", "delta"] == pytest.approx(6.020599913, abs=1e-9)
    assert list(sn["rank"]) == [1, 2]
    # one value per run: larger-the-better is the smaller-the-better ratio negated, so the
    # deltas and ranks agree and only the best level (the largest S/N) turns over
    smaller = sn_response_table(table, "torsional_rigidity_nm_per_arcmin", ["A", "B"],
                                "smaller")
    assert np.allclose(smaller[["level 1", "level 2"]], -sn[["level 1", "level 2"]],
                       atol=1e-12)


def test_the_response_sense_chooses_the_table_and_the_optimum():
    from rvsim.analysis import analyze_table
    from rvsim.analysis.signal_noise import table_kind
    from rvsim.errors import ParameterError

    assert table_kind("ate_arcmin") == "smaller" and table_kind("te_mean_arcmin") == "smaller"
    assert table_kind("torsional_rigidity_nm_per_arcmin") == "larger"
    assert table_kind("efficiency") == "larger"
    assert table_kind("torsional_stiffness_nm_per_arcmin_mean") == "larger"
    assert table_kind("ate_arcmin_sn") is None           # an S/N ratio: no S/N of it
    assert table_kind("ate_arcmin", "larger") == "larger"
    for response, kind, words in (("ate_arcmin", "nominal", "replicates"),
                                  ("ate_arcmin_sn", "larger", "ate_arcmin_sn_larger"),
                                  ("ate_arcmin", "biggest", "expected one of")):
        with pytest.raises(ParameterError) as err:
            table_kind(response, kind)
        assert err.value.field == "--sn" and words in err.value.reason
    table = _l4("torsional_rigidity_nm_per_arcmin", [10.0, 20.0, 40.0, 80.0])
    out = analyze_table(table, "torsional_rigidity_nm_per_arcmin", ["A", "B"])
    assert out["sn_kind"] == "larger"
    assert out["optimum"] == {"A": 2, "B": 2}            # the stiffest levels
    assert out["sn_response"]["A"]["levels"][1] == pytest.approx(35.051499783, abs=1e-9)
    forced = analyze_table(table, "torsional_rigidity_nm_per_arcmin", ["A", "B"], sn="smaller")
    assert forced["sn_kind"] == "smaller" and forced["optimum"] == {"A": 1, "B": 1}
