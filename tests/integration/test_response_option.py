"""``--response COLUMN`` on ``rvsim study``, ``analyze`` and ``report``, and the bench's index
``ate_arcmin`` under one name in every JSON (issue 33, items 1 and 6).

One small quasi-static study (L4, four LTCA runs) is run once for the module; everything else
reads its folder or the paper's Table 3."""

import json
import math
import shutil
import textwrap

import pandas as pd
import pytest

from tests.conftest import REFERENCE

QS_STUDY = """
name = "qs-ate"
design = "L4"
engine = "quasi-static"
[factors.H]
parameter = "H"
levels = [0.0, 0.02]
[factors.I]
parameter = "I"
levels = [0.0, 0.03]
"""


@pytest.fixture(scope="module")
def qs_folder(tmp_path_factory):
    from tests.conftest import run_cli

    root = tmp_path_factory.mktemp("qs")
    path = root / "qs.toml"
    path.write_text(textwrap.dedent(QS_STUDY))
    res = run_cli("study", str(path), "--out", str(root / "out"), "--workers", "1",
                  "--response", "ate_arcmin", "--json")
    assert res.code == 0, res.err
    return root / "out", json.loads(res.out)


def _one_line(res, *words):
    assert res.code == 2, (res.out, res.err)
    assert res.err.count("\n") == 1 and res.err.startswith("rvsim: error: "), res.err
    assert "--response" in res.err and "Traceback" not in res.err
    for w in words:
        assert w in res.err, res.err


# --- the same key in every JSON ----------------------------------------------------------------

def test_ltca_json_names_its_peak_to_peak_the_ate(cli):
    res = cli("ltca", "--positions", "81", "--json")
    assert res.code == 0, res.err
    s = json.loads(res.out)
    assert s["ate_arcmin"] == s["te_pp_arcmin"] and s["te_window_revolutions"] == 1.0
    assert "te_mean_arcmin" in s


def test_simulate_json_says_why_a_short_run_has_no_ate(cli):
    from .test_simulate_cli import SHORT_ARGS

    res = cli("simulate", *SHORT_ARGS, "--json")      # 0.4 s, steady from 0.3 s
    assert res.code == 0, res.err
    s = json.loads(res.out)
    # 0.1 s of steady window at 7000 deg/s, ratio 121, in 201 samples at 2 kHz, each standing
    # for its 0.5 ms: 0.1005 s x 7000 / 121 / 360 = 0.01615 revolution
    assert s["ate_arcmin"] is None
    assert s["te_window_revolutions"] == pytest.approx(0.1005 * 7000 / 121 / 360, rel=1e-3)
    assert "of an output revolution" in s["ate_note"] and s["te_pp_arcmin"] > 0


def test_study_rows_and_analysis_name_the_ate(qs_folder):
    folder, printed = qs_folder
    rows = pd.read_csv(folder / "results.csv")
    assert (rows["status"] == "ok").all() and len(rows) == 4
    # the quasi-static engine covers one output revolution: its peak-to-peak is the ATE
    assert (rows["ate_arcmin"] == rows["te_pp_arcmin"]).all()
    assert (rows["te_window_revolutions"] == 1.0).all() and "ate_note" not in rows
    analysis = json.loads((folder / "analysis.json").read_text())
    assert analysis["response"] == "ate_arcmin" and printed["analysis"]["response"] == "ate_arcmin"
    assert "what a bench measures" in analysis["response_note"]
    # the range analysis of the ATE column, by hand: k of H's level 1 is the mean of its rows
    level1 = rows.loc[rows["H"] == 1, "ate_arcmin"].mean()
    assert analysis["range"]["H"]["k"][0] == pytest.approx(level1, rel=1e-12)
    html = (folder / "report.html").read_text()
    assert "Analysed here: ate_arcmin" in html and "what a bench measures" in html


def test_analyze_and_report_take_any_metric_column(qs_folder, cli, tmp_path):
    folder, _ = qs_folder
    res = cli("analyze", str(folder / "results.csv"), "--response", "ate_arcmin", "--json")
    assert res.code == 0, res.err
    out = json.loads(res.out)
    stored = json.loads((folder / "analysis.json").read_text())
    assert out["range"] == stored["range"] and out["response"] == "ate_arcmin"
    # the report of another column of the same folder: the paper's index, which no bench checks
    copy = tmp_path / "copy"
    shutil.copytree(folder, copy)
    res = cli("report", str(copy), "--response", "te_mean_arcmin")
    assert res.code == 0, res.err
    html = (copy / "report.html").read_text()
    assert "Analysed here: te_mean_arcmin" in html and "no bench can check it" in html
    rows = pd.read_csv(copy / "results.csv")
    k1 = rows.loc[rows["I"] == 1, "te_mean_arcmin"].mean()
    assert f"{k1:.4g}" in html
    # analysis.json is the study's own: a report does not rewrite it
    assert json.loads((copy / "analysis.json").read_text()) == stored


def test_analyze_default_is_unchanged_the_papers_index(cli):
    res = cli("analyze", str(REFERENCE / "table3_l36_results.csv"), "--json")
    assert res.code == 0, res.err
    out = json.loads(res.out)
    assert out["response"] == "te_arcmin" and "no bench can check it" in out["response_note"]


# --- bad input: one line naming --response and the columns there are, nothing written --------

@pytest.mark.parametrize("column, words", [
    ("nope", ("response column 'nope' not in the table", "numeric columns: ", "te_arcmin")),
    ("note", ("holds no number", "te_arcmin")),         # a text column
    ("A", ("'A' is a factor column",)),
    ("run", ("the run number",)),
])
def test_analyze_refuses_a_column_it_cannot_analyse(cli, column, words):
    res = cli("analyze", str(REFERENCE / "table3_l36_results.csv"), "--response", column)
    _one_line(res, *words)
    assert res.out == ""


def test_report_refuses_an_absent_column_and_keeps_the_report(qs_folder, cli):
    folder, _ = qs_folder
    before = (folder / "report.html").read_bytes()
    res = cli("report", str(folder), "--response", "backlash_arcmin")
    _one_line(res, "'backlash_arcmin' not in the table", "ate_arcmin")
    assert (folder / "report.html").read_bytes() == before
    res = cli("report", str(folder), "--response", "status")
    _one_line(res, "holds no number")


def test_study_refuses_a_response_before_any_run(tmp_path, cli):
    path = tmp_path / "qs.toml"
    path.write_text(textwrap.dedent(QS_STUDY))
    out = tmp_path / "out"
    res = cli("study", str(path), "--out", str(out), "--response", "backlash_arcmin")
    _one_line(res, "quasi-static engine", "ate_arcmin")        # no hysteresis = true
    assert not out.exists()
    res = cli("study", "rv40e-tolerances", "--out", str(out), "--response", "ate_arcmin")
    _one_line(res, "tolerance study")
    assert not out.exists()


def test_a_dynamic_study_too_short_for_a_revolution_is_refused_its_ate(tmp_path, cli):
    from tests.integration.conftest import write_study

    out = tmp_path / "out"
    res = cli("study", str(write_study(tmp_path)), "--out", str(out), "--response",
              "ate_arcmin")
    # the short schedule: 0.1 s of steady window; one output revolution at 7000 deg/s, ratio
    # 121, takes 121 * 360 / 7000 = 6.223 s
    _one_line(res, "6.223 s", "te_pp_arcmin")
    assert not out.exists()
    assert math.isclose(121 * 360 / 7000, 6.2229, rel_tol=1e-4)


def test_the_engines_metric_lists_are_what_runs_give(qs_folder):
    """``rvsim study --response`` checks names against these lists before any run."""
    from rvsim.doe.engines import metric_columns
    from tests.verification.test_ate_index import _result

    folder, _ = qs_folder
    rows = pd.read_csv(folder / "results.csv")
    given = set(rows.columns) - {"run", "H", "I", "status", "error", "key"}
    assert given == set(metric_columns("quasi-static"))
    dynamic = set(_result(1.5).summary()) - {"status", "reducer"}
    assert dynamic <= set(metric_columns("dynamic"))
    assert {"ate_arcmin", "te_mean_arcmin", "te_window_revolutions"} <= dynamic


def test_a_table_whose_runs_have_no_ate_is_refused_with_the_reason(tmp_path, cli):
    """A dynamic study's rows (steady windows shorter than a revolution): ate_arcmin empty."""
    from tests.conftest import reference_table

    table = reference_table("table3_l36_results.csv")
    table = table.rename(columns={"te_arcmin": "te_mean_arcmin"}).drop(columns=["note"])
    table["ate_arcmin"] = float("nan")
    table["te_window_revolutions"] = 0.4
    path = tmp_path / "results.csv"
    table.to_csv(path, index=False)
    res = cli("analyze", str(path), "--response", "ate_arcmin")
    _one_line(res, "holds no number", "te_window_revolutions", "te_mean_arcmin")
    assert cli("analyze", str(path), "--json").code == 0       # the default: the paper's index


# --- the S/N kind: the response's own sense, or --sn (issue 33) -------------------------------

def _sn_line(res, *words):
    assert res.code == 2, (res.out, res.err)
    assert res.err.count("\n") == 1, res.err
    assert res.err.startswith("rvsim: error: parameter '--sn': "), res.err
    assert "Traceback" not in res.err and res.out == ""
    for w in words:
        assert w in res.err, res.err


def test_a_stiffness_is_analysed_larger_the_better(qs_folder, cli, tmp_path):
    folder, _ = qs_folder
    column = "torsional_stiffness_nm_per_arcmin"
    rows = pd.read_csv(folder / "results.csv")
    res = cli("analyze", str(folder / "results.csv"), "--response", column, "--json")
    assert res.code == 0, res.err
    out = json.loads(res.out)
    assert out["sn_kind"] == "larger"
    sn1 = {}
    for f in ("H", "I"):                     # the optimum: the stiffer level, by hand
        means = rows.groupby(f)[column].mean()
        assert out["optimum"][f] == int(means.idxmax())
        # larger-the-better of one value per run: mean of 20 log10(y) over the level's rows
        sn1[f] = (20 * rows.loc[rows[f] == 1, column].map(math.log10)).mean()
        assert out["sn_response"][f]["levels"][0] == pytest.approx(sn1[f], rel=1e-12)
    res = cli("analyze", str(folder / "results.csv"), "--response", column, "--sn",
              "smaller", "--json")
    forced = json.loads(res.out)
    assert forced["sn_kind"] == "smaller"
    assert forced["sn_response"]["H"]["levels"][0] == pytest.approx(-sn1["H"], rel=1e-12)
    assert forced["optimum"]["H"] == int(rows.groupby("H")[column].mean().idxmin())
    copy = tmp_path / "copy"
    shutil.copytree(folder, copy)
    assert cli("report", str(copy), "--response", column).code == 0
    html = (copy / "report.html").read_text()
    assert "Signal-to-noise ratios (larger is better" in html
    assert "Optimum (larger is better)" in html


def test_sn_kinds_a_table_cannot_take_are_refused(qs_folder, cli, tmp_path):
    folder, _ = qs_folder
    res = cli("analyze", str(folder / "results.csv"), "--response", "ate_arcmin", "--sn",
              "nominal")
    _sn_line(res, "nominal-the-best", "replicates", "m_sn_nominal")
    before = (folder / "report.html").read_bytes()
    _sn_line(cli("report", str(folder), "--sn", "nominal"), "replicates")
    assert (folder / "report.html").read_bytes() == before
    path = tmp_path / "qs.toml"
    path.write_text(textwrap.dedent(QS_STUDY))
    out = tmp_path / "out"
    _sn_line(cli("study", str(path), "--out", str(out), "--sn", "nominal"), "replicates")
    assert not out.exists()
    _sn_line(cli("study", "rv40e-tolerances", "--out", str(out), "--sn", "larger"),
             "tolerance study")
    assert not out.exists()
