"""The notebook API (issue 34 item 5): help(rvsim) is a short quick start, the top-level names
load lazily, a parameter set and every result show their headline figures (repr and HTML)
and draw themselves with ``.plot()``.  Results are built from known curves, no compiled run."""

from __future__ import annotations

import functools
import math
import pydoc
from pathlib import Path

import numpy as np
import pytest

import rvsim
from rvsim.errors import ParameterError
from rvsim.units import ARCMIN
from tests.unit.test_joint_model import FREE_PLAY, RATED, STIFFNESS, known_loop, known_te

W_OUT = 2.0 * math.pi        # [rad/s] one output revolution per second


def known_run(ratio: float = 121.0):
    """2 s at one output revolution per second; TE 1.5 + 0.2 sin(2 theta_out) arcmin; every
    pin at 500 N; steady from 0.5 s (1.5 output revolutions, three whole TE periods)."""
    from rvsim.dynamics.result import Result
    from rvsim.physics import _layout as L

    time = np.linspace(0.0, 2.0, 2001)
    te = (1.5 + 0.2 * np.sin(2.0 * W_OUT * time)) * ARCMIN
    channels = np.zeros((time.size, len(L.CHANNEL_NAMES)))
    for name, values in (("time", time), ("theta_in", ratio * W_OUT * time),
                         ("omega_in", np.full_like(time, ratio * W_OUT)),
                         ("theta_out", W_OUT * time - te), ("omega_out", np.full_like(time, W_OUT))):
        channels[:, L.CHANNEL_NAMES.index(name)] = values
    return Result(time, channels, np.full((time.size, 2, 40), 500.0), ratio, 0.5, "ok", 4000,
                  1.25, {"relative_residual": 3e-5}, reducer_name="RV-40E")


def known_map():
    from rvsim.quasistatic.efficiency import RPM, EfficiencyResult

    speeds, torques = np.array([500.0, 1500.0]) * RPM, np.array([206.0, 412.0])
    eff = np.array([[0.90, 0.92], [0.88, 0.91]])
    return EfficiencyResult(speeds, torques, eff, torques / (121.0 * eff), np.array([0.01, 0.02]),
                            0.005, 121.0, 24, True, "ok", 0.5, rated_torque=412.0)


def test_help_is_a_short_quick_start():
    text = pydoc.render_doc(rvsim, renderer=pydoc.plaintext)
    assert len(text.splitlines()) <= 80                  # 596 lines before (issue 34)
    assert "rvsim.simulate(r)" in text and "ParameterError" in text
    assert "class ParameterError" not in text            # the exceptions' methods left out


def test_top_level_names_are_the_subpackages_own():
    from rvsim.doe.result import run_study
    from rvsim.quasistatic.efficiency import efficiency
    from rvsim.testrig.calibration import calibrate

    assert rvsim.efficiency is efficiency and rvsim.run_study is run_study
    assert rvsim.calibrate is calibrate
    assert rvsim.BUILT_IN_SETS["RV-40E-bearings"].name == "RV-40E-bearings"
    assert set(rvsim._LAZY) <= set(dir(rvsim))
    with pytest.raises(AttributeError, match="no attribute 'simulat'"):
        rvsim.simulat


def test_reducer_shows_its_dimensions_in_mm():
    text = repr(rvsim.RV40E)
    assert len(text.splitlines()) == 6 and len(text) < 450        # was 3,735 characters
    for words in ("ratio 121", "40 pins r 3 mm on r 82 mm", "eccentricity 1.5 mm",
                  "412 N*m rated", "2058 N*m momentary"):
        assert words in text
    assert "gear stage" not in repr(rvsim.CYCLOID_DRIVE)          # one stage
    assert rvsim.RV40E._repr_html_().count("<tr>") == 5


def _check(result, title: str, figures: list[str], lines: int):
    text = repr(result)
    assert text.startswith(title)
    assert len(text.splitlines()) == lines and len(text) < 900
    for figure in figures:
        assert figure in text
    page = result._repr_html_()
    assert page.startswith("<table>") and all(f in page for f in figures)


def test_run_shows_its_te_figures():
    _check(known_run(), "Result of RV-40E: ok, 2 s simulated (4000 steps, 1.25 s wall)",
           ["1.5 arcmin", "0.4 arcmin", "500 N", "3e-05 of the input work"], 6)


def test_ltca_shows_its_figures_against_the_class():
    # the known TE: the wind-up at rated torque, half the free play and three harmonics
    te = known_te(rvsim.RV40E)
    mean = RATED / STIFFNESS / ARCMIN + FREE_PLAY / 2 / ARCMIN
    _check(te, "LTCA at 412 N*m: ok, 360 positions",
           [f"{mean:.4g} arcmin", "35 N*m/arcmin", "0 N", "0 to 0"], 9)


def test_hysteresis_shows_the_catalogue_quantities():
    # the spring with free play: rigidity 35 N*m/arcmin (113 the class's lowest), lost motion
    # the free play plus the wind-up of +-3 % of rated, 0.4 + 2 x 12.36 / 35 = 1.106 arcmin,
    # the loop's width at 0 N*m the free play, 0.4 arcmin
    _check(known_loop(), "Torque reversal to +-412 N*m: ok, 101 points",
           ["35 N*m/arcmin", "0.31 x the class (softer)", "1.11 arcmin", "0.4 arcmin"], 5)


def test_efficiency_shows_its_map():
    _check(known_map(), "Efficiency map: ok, 2 speeds x 2 torques",
           ["92 %", "91 %", "0.01 N*m", "0.005 N*m"], 5)


@functools.cache
def l36_analysis():
    """The paper's L36 table analysed (0.8 s: once for the tests that need it)."""
    from rvsim.parameters import paper_l36_scheme

    return rvsim.analyze_table(paper_l36_scheme().drop(columns=["note"]))


def test_analysis_frames_carry_units():
    analysis = l36_analysis()                           # the default response: te_arcmin
    assert analysis["significant"] == ["H", "I"] and analysis.response == "te_arcmin"
    assert list(analysis.ranges.columns) == ["k1_arcmin", "k2_arcmin", "k3_arcmin",
                                             "R_arcmin", "rank", "optimal_level"]
    assert list(analysis.anova.columns) == ["df", "adj_ss_arcmin2", "adj_ms_arcmin2", "f", "p"]
    assert list(analysis.sn.columns) == ["level1_dB", "level2_dB", "level3_dB", "delta_dB",
                                         "rank"]
    assert analysis.ranges.loc["H", "R_arcmin"] == analysis["range"]["H"]["R"]
    text = repr(analysis)
    assert "H>I>N" in text and "H, I" in text and len(text.splitlines()) == 5


@pytest.mark.parametrize("make", [known_run, lambda: known_te(rvsim.RV40E), known_loop, known_map,
                                  lambda: known_tolerances()])
def test_plot_returns_an_axes(make):
    from rvsim.plots import pyplot

    plt = pyplot()
    result = make()
    ax = result.plot()
    assert ax.get_ylabel() and ax.lines or ax.images or ax.collections
    plt.close(ax.figure)
    fig, given = plt.subplots()
    assert result.plot(ax=given).figure is fig         # drawn in the caller's figure
    plt.close(fig)


def test_plot_of_something_else_than_an_axes_is_one_type_error():
    """``result.plot(ax="x")`` was an AttributeError from inside matplotlib (issue 30, fifth
    session): every public ``plot`` names ``ax`` and what it must be."""
    from rvsim.doe.result import StudyResult

    analysis = l36_analysis()
    study = StudyResult(None, Path("unused"), None)      # refused before its study is read
    results = [known_run(), known_te(rvsim.RV40E), known_loop(), known_map(), known_tolerances(),
               analysis, analysis.range_analysis, study]
    for result, ax in [(r, "x") for r in results] + [(known_map(), 1), (known_loop(), [None])]:
        with pytest.raises(TypeError) as error:
            result.plot(ax=ax)
        assert str(error.value) == ("ax must be a matplotlib Axes (e.g. from plt.subplots()) or "
                                    f"None, not {type(ax).__name__} {ax!r}")


def test_a_figure_of_panels_needs_an_axes_alone():
    from rvsim.plots import pyplot

    plt = pyplot()
    fig, (left, _) = plt.subplots(1, 2)
    with pytest.raises(ParameterError, match="this result draws a figure of several") as error:
        known_loop().plot(ax=left)
    assert error.value.field == "ax"
    plt.close(fig)


def known_tolerances():
    """Eleven reducers whose metrics are evenly spread (p5, p50, p95 known)."""
    from rvsim.tolerance.analysis import ToleranceSummary
    from rvsim.tolerance.montecarlo import summarise

    values = {"ate_arcmin": np.linspace(0.1, 0.3, 11), "te_mean_arcmin": np.linspace(1, 2, 11),
              "lost_motion_arcmin": np.linspace(0.2, 0.4, 11),
              "torsional_rigidity_nm_per_arcmin": np.linspace(100.0, 120.0, 11)}
    status = np.array(["ok"] * 11, dtype=object)
    return ToleranceSummary({"study": "spread", **summarise(status, values)}, values)


def test_tolerance_summary_is_still_the_dict_and_shows_its_percentiles():
    import json

    summary = known_tolerances()
    assert json.loads(json.dumps(summary))["metrics"]["ate_arcmin"]["p95"] == pytest.approx(0.29)
    _check(summary, "Tolerance study spread: 11 reducers, 11 analysed, 0 bind, 0 failed",
           ["0.29 arcmin", "1.05 / 1.5 / 1.95 arcmin", "0.39 arcmin", "101 N*m/arcmin"], 6)
    assert summary.to_frame().shape == (11, 4)
    from rvsim.plots import pyplot

    ax = summary.plot(metric="lost_motion_arcmin")
    assert ax.get_xlabel() == "lost_motion_arcmin"
    pyplot().close(ax.figure)
    with pytest.raises(ParameterError, match="not a metric of this study"):
        summary.plot(metric="te_arcmin")


def test_calibration_shows_each_estimate_with_its_interval():
    from rvsim.testrig.calibration import Calibration

    fit = Calibration(["errors.pin_radius"], ["mm"], np.array([0.0]), np.array([0.0123]),
                      np.array([0.0011]), np.array([0.0101]), np.array([0.0145]), np.eye(1),
                      [], 41.5, 3.25, 2048, 17, "ok")
    _check(fit, "Calibration: ok, 2048 residuals, 17 model evaluations",
           ["3.25 arcsec (at the start 41.5 arcsec)", "0.0123 mm (95 %: 0.0101 to 0.0145; start 0)"], 3)
    nan = np.array([np.nan])
    lost = Calibration(["errors.pin_radius"], ["mm"], np.array([0.0]), np.array([0.0123]),
                       np.array([np.inf]), nan, nan, np.eye(1), [], 41.5, 3.25, 2048, 17,
                       "not_identifiable")
    _check(lost, "Calibration: not_identifiable, 2048 residuals, 17 model evaluations",
           ["0.0123 mm (not identifiable; start 0)"], 3)     # not "not available to ..."


@pytest.mark.parametrize("backend, used", [("svg", "svg"), ("nonsense", "agg")])
def test_pyplot_keeps_a_backend_already_chosen(backend, used):
    """MPLBACKEND as Jupyter's kernel sets it (a process of its own: pyplot is imported here
    already; the other case, pyplot imported before rvsim, is the same condition's).  A
    backend matplotlib does not know (its ValueError at import was a traceback after every
    report's run, hostile5) is left for Agg."""
    import os
    import subprocess
    import sys

    code = ("from rvsim._matplotlib import pyplot\npyplot()\nimport matplotlib\n"
            "print(matplotlib.get_backend().lower())")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True, env={**os.environ, "MPLBACKEND": backend}).stdout
    assert out.split()[-1] == used


#: the columns of the public frames that are plain numbers by their name (docs/decisions.md,
#: issue 34 fifth session): counts, flags, ratios, orders, identifiers
DIMENSIONLESS = {"branch", "converged", "pins_in_contact_disc1", "pins_in_contact_disc2",
                 "efficiency", "order", "run", "status", "error", "key"}


def _unnamed(frame) -> list[str]:
    from rvsim.analysis import unit_suffix

    return [c for c in frame.columns if c not in DIMENSIONLESS and not unit_suffix(c)[1]]


def test_every_frame_column_names_its_unit():
    for frame in (known_run().to_frame(), known_te(rvsim.RV40E).to_frame(),
                  known_loop().to_frame(), known_map().to_frame(), known_run().spectrum(),
                  known_te(rvsim.RV40E).spectrum(), known_tolerances().to_frame()):
        assert _unnamed(frame) == []
    frame = known_run().to_frame()
    assert frame["te_arcmin"].mean() == pytest.approx(1.5, abs=1e-3)
    assert {"time_s", "theta_in_rad", "omega_out_rad_per_s", "torque_in_nm",
            "pin_f_max_n"} <= set(frame.columns)


def test_a_sampling_study_frame_names_each_factor_unit():
    """results.csv keeps the factor labels (a file's columns stay, issue 31); the frame of a
    sampling design, whose factor columns hold values, names their units."""
    import pandas as pd

    from rvsim.analysis import suffix_of_unit
    from rvsim.doe.result import StudyResult
    from rvsim.doe.study import study_from_data

    study = study_from_data({"name": "s", "design": "lhs", "samples": 4,
                             "engine": "quasi-static", "factors": {
                                 "F": {"parameter": "errors.pin_radius", "range": [0.01, 0.03]},
                                 "T": {"parameter": "operating.load_torque",
                                       "range": [100.0, 300.0]}}}, Path("s.toml"))
    table = study.table().assign(te_mean_arcmin=1.0, status="ok", error="", key="k")
    frame = StudyResult(study, Path("s"), table).to_frame()
    assert list(frame.columns) == ["run", "F_mm", "T_nm", "te_mean_arcmin", "status", "error",
                                   "key"]
    assert _unnamed(frame) == [] and list(table.columns)[:3] == ["run", "F", "T"]
    levels = StudyResult(rvsim.paper_l36(), Path("p"), pd.DataFrame({"run": [1], "H": [2]}))
    assert list(levels.to_frame().columns) == ["run", "H"]       # level numbers
    assert (suffix_of_unit("N/m"), suffix_of_unit("kg*m^2"), suffix_of_unit("degC"),
            suffix_of_unit("count")) == ("_n_per_m", "_kgm2", "_c", "")


def test_a_failed_result_shows_its_status_not_numbers():
    import dataclasses

    te = known_te(rvsim.RV40E)
    failed = dataclasses.replace(te, status="not_converged",
                                 converged=np.zeros(te.converged.size, bool))
    text = repr(failed)
    assert text.startswith("LTCA at 412 N*m: not_converged")
    for row in text.splitlines()[2:]:                 # every figure but the torque
        assert row.endswith("not available") or "not available  (" in row, row


def test_a_repr_never_raises():
    loop = known_loop()
    loop.torque = loop.torque[:3]                       # no longer a loop
    text = repr(loop)
    assert text.startswith("HysteresisResult (no headline: ") and "\n" not in text


def test_a_study_result_shows_its_analysis():
    from rvsim.doe.result import StudyResult
    from rvsim.parameters import paper_l36_scheme

    table = paper_l36_scheme().drop(columns=["note"]).assign(status="ok")
    table.loc[35, "status"] = "diverged"                 # left out of the analysis
    result = StudyResult(rvsim.paper_l36(), Path("study"), table)
    _check(result, "Study paper-l36: 35 of 36 runs ok (dynamic engine, L36), in study",
           ["te_arcmin", "H"], 6)
    assert result.analysis().ranges.shape[0] == 15
    from rvsim.plots import pyplot

    ax = result.plot()
    assert ax.get_title() == "A"
    pyplot().close(ax.figure)


def test_a_map_without_friction_says_so():
    import dataclasses

    text = repr(dataclasses.replace(known_map(), friction=False))
    assert text.splitlines()[1].startswith("  friction") and "none in this parameter set" in text
