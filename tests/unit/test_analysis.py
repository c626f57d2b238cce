"""Analysis: ANOVA identities, pooling, S/N, optimum prediction, malformed tables."""

import json

import numpy as np
import pandas as pd
import pytest

from rvsim.analysis import (anova, analyze_table, predict_optimum, range_analysis,
                            signal_to_noise_smaller, sn_response_table)
from rvsim.errors import InputFileError
from rvsim.parameters import paper_l36_scheme


@pytest.fixture
def table3():
    return paper_l36_scheme().drop(columns=["note"])


def test_factor_sums_of_squares_match_the_level_means(table3):
    ra = range_analysis(table3, "te_arcmin")
    result = anova(table3, "te_arcmin")
    y = table3["te_arcmin"].to_numpy()
    for factor, k in ra.level_means.items():
        per_level = len(y) / len(k)
        expected = per_level * sum((ki - y.mean()) ** 2 for ki in k)
        assert result.rows[factor]["adj_ss"] == pytest.approx(expected, rel=1e-9)
    total = sum(r["adj_ss"] for s, r in result.rows.items() if s != "Total")
    assert total == pytest.approx(result.rows["Total"]["adj_ss"], rel=1e-9)
    assert result.rows["Error"]["df"] == 9 and result.rows["Total"]["df"] == 35
    assert result.rows["H"]["f"] == pytest.approx(
        result.rows["H"]["adj_ms"] / result.rows["Error"]["adj_ms"])


def test_paper_significance_at_alpha_0_1(table3):
    # paper Eqs. (24)/(25): only H and I exceed F_0.1(2, 9) = 3.01
    assert anova(table3, "te_arcmin").significant(0.1) == ["H", "I"]


def test_pooling_moves_factors_into_error(table3):
    full = anova(table3, "te_arcmin")
    pooled = anova(table3, "te_arcmin", pool=("B", "C", "D"))
    assert "B" not in pooled.rows
    assert pooled.rows["Error"]["df"] == 12
    extra = sum(full.rows[f]["adj_ss"] for f in "BCD")
    assert pooled.rows["Error"]["adj_ss"] == pytest.approx(full.rows["Error"]["adj_ss"] + extra)


def test_sn_ratio_and_prediction(table3):
    assert signal_to_noise_smaller([1.0]) == pytest.approx(0.0)
    assert signal_to_noise_smaller([0.1]) == pytest.approx(20.0)
    sn = sn_response_table(table3, "te_arcmin")
    assert sn.loc["H", "rank"] == 1
    pred = predict_optimum(table3, anova(table3, "te_arcmin"), "te_arcmin", alpha=0.1)
    ra = range_analysis(table3, "te_arcmin")
    expected = ra.grand_mean + sum(min(ra.level_means[f]) - ra.grand_mean for f in "HI")
    assert pred["predicted"] == pytest.approx(expected)


def test_analyze_json_layout(table3):
    out = analyze_table(table3, "te_arcmin")
    assert set(out) >= {"range", "order", "optimum", "anova"}
    assert set(out["anova"]) == set("ABCDEFGHIJKLMNO") | {"Error", "Total"}
    assert set(out["anova"]["A"]) == {"df", "adj_ss", "adj_ms", "f", "p"}


@pytest.mark.parametrize("mutate, words", [
    (lambda t: t.drop(columns=["te_arcmin"]), "response column 'te_arcmin' not in the table"),
    (lambda t: t.assign(A=t["A"].astype(str).replace("1", "x")), "factor column 'A'"),
    (lambda t: t.assign(te_arcmin=t["te_arcmin"].astype(object).where(t.index != 3, "n/a")),
     "row 4"),
    (lambda t: t.assign(te_arcmin=t["te_arcmin"].where(t.index != 5, float("inf"))),
     "row 6 is not finite"),
    (lambda t: t.assign(te_arcmin=0.0), "every value is zero"),
    (lambda t: t.assign(te_arcmin=t["te_arcmin"] * 1e300), "row 1 .* is beyond"),
    (lambda t: t.assign(P=t["H"]), "'H' and 'P' vary together"),
    (lambda t: pd.concat([t, t[["H"]]], axis=1), "'H' appears more than once"),
])
def test_malformed_tables(table3, mutate, words):
    with pytest.raises(InputFileError, match=words):
        analyze_table(mutate(table3), "te_arcmin")


@pytest.mark.parametrize("content, words", [
    ("run,A,B\n1,1,1\n2,2,2\n", "response column"),
    ("run,A,te_arcmin\n1,1,x\n2,2,1\n", "not a number"),
    ("", "empty"),
    ("A,A,te_arcmin\n1,1,1\n2,2,2\n", "more than once"),
    ("A,B,te_arcmin\n1,1,inf\n2,2,2\n1,2,1\n2,1,3\n", "not finite"),
    ("A,B,te_arcmin\n1,1,0\n2,2,0\n1,2,0\n2,1,0\n", "every value is zero"),
])
def test_analyze_cli_errors(tmp_path, cli, content, words):
    path = tmp_path / "t.csv"
    path.write_text(content)
    res = cli("analyze", str(path), "--response", "te_arcmin")
    assert res.code == 2 and words in res.err and res.err.count("\n") == 1


def test_analyze_cli_missing_file(cli):
    res = cli("analyze", "/nonexistent/table.csv")
    assert res.code == 2 and "not found" in res.err


def test_optimum_is_the_level_number_written_in_the_table():
    # a design that uses only levels 1 and 3 of A: the optimum is level 3, not "position 2"
    table = pd.DataFrame({"A": [1, 1, 3, 3] * 2, "B": [1, 2, 1, 2] * 2,
                          "y": [5.0, 6.1, 1.1, 2.0, 5.1, 6.0, 1.0, 2.1]})
    ra = range_analysis(table, "y", ["A", "B"])
    assert ra.optimum == {"A": 3, "B": 1}
    assert ra.levels["A"] == [1, 3] and ra.mean_at("A", 3) == pytest.approx(1.55)
    assert list(ra.to_df().columns[:3]) == ["k1", "k2", "k3"]
    assert np.isnan(ra.to_df().loc["A", "k2"]) and ra.to_df().loc["A", "optimal_level"] == 3
    out = analyze_table(table, "y", ["A", "B"])
    assert out["optimum"] == {"A": 3, "B": 1} and out["significant"] == ["A", "B"]
    assert out["prediction"]["levels"] == {"A": 3, "B": 1}
    expected = ra.mean_at("A", 3) + ra.mean_at("B", 1) - ra.grand_mean
    assert out["prediction"]["predicted"] == pytest.approx(expected, rel=1e-12)


def test_unbalanced_table_is_analysed_by_regression_with_a_note(table3):
    one_failed = table3.drop(index=17)          # the paper's L36 with run 18 missing
    out = analyze_table(one_failed, "te_arcmin")
    assert any("unbalanced" in note for note in out["notes"])
    assert out["anova"]["Error"]["df"] == 8 and out["anova"]["Total"]["df"] == 34
    # the regression's adjusted SS no longer add up to the total (not orthogonal any more)
    parts = sum(r["adj_ss"] for s, r in out["anova"].items() if s != "Total")
    assert parts != pytest.approx(out["anova"]["Total"]["adj_ss"], rel=1e-6)
    # each factor's adjusted SS is statsmodels' Type II SS of the main-effects model
    import statsmodels.api as sm
    import statsmodels.formula.api as smf

    data = one_failed.rename(columns={f: f"f{f}" for f in "ABCDEFGHIJKLMNO"})
    fit = smf.ols("te_arcmin ~ " + " + ".join(f"C(f{f})" for f in "ABCDEFGHIJKLMNO"),
                  data=data).fit()
    type2 = sm.stats.anova_lm(fit, typ=2)
    for f in "ABCDEFGHIJKLMNO":
        assert out["anova"][f]["adj_ss"] == pytest.approx(type2.loc[f"C(f{f})", "sum_sq"],
                                                          rel=1e-9, abs=1e-12)
    assert "H" in out["significant"]
    assert "notes" not in analyze_table(table3, "te_arcmin")


@pytest.mark.parametrize("scale", [0.0, 1e-15])
def test_no_significance_from_round_off(table3, scale):
    # a response constant, or varying at 1e-15 relative, has no significant factor
    noise = np.random.default_rng(1).standard_normal(len(table3))
    flat = table3.assign(te_arcmin=1.0 + scale * noise)
    out = analyze_table(flat, "te_arcmin")
    assert out["significant"] == []
    assert any("round-off" in note for note in out["notes"])
    assert all(np.isnan(out["anova"][f]["f"]) for f in "ABCDEFGHIJKLMNO")
    assert out["order"] is None and out["constant_response"] is True


def test_analyze_says_a_constant_response_has_no_factor_order(table3, tmp_path, capsys):
    from rvsim.cli import main

    path = tmp_path / "flat.csv"
    table3.assign(te_arcmin=2.5).to_csv(path, index=False)
    assert main(["analyze", str(path)]) == 0
    out = capsys.readouterr().out
    assert "order: none: the response 'te_arcmin' is constant" in out
    assert "order: A" not in out and ">" not in out.split("order:")[1].splitlines()[0]


def test_a_factor_without_effect_is_not_significant_in_an_exact_fit():
    # y depends on A only, exactly: B's SS is round-off and must not yield a huge F
    rng = np.random.default_rng(0)
    a = np.repeat([1, 2, 3], 12)
    b = np.tile([1, 2, 3], 12)
    c = rng.permutation(np.repeat([1, 2], 18))
    table = pd.DataFrame({"A": a, "B": b, "C": c, "y": 0.3 + 0.1 * a})
    out = analyze_table(table, "y", ["A", "B", "C"])
    assert out["anova"]["B"]["adj_ss"] == 0.0 and out["anova"]["C"]["adj_ss"] == 0.0
    assert "B" not in out["significant"] and "C" not in out["significant"]


def test_analysis_json_is_strict_json(tmp_path, table3):
    from rvsim.doe.outputs import write_study_outputs

    results = table3.rename(columns={"te_arcmin": "te_mean_arcmin"}).assign(status="ok")
    write_study_outputs(tmp_path, results, list("ABCDEFGHIJKLMNO"))

    def refuse(name):
        raise AssertionError(f"bare {name} in analysis.json")

    data = json.loads((tmp_path / "analysis.json").read_text(), parse_constant=refuse)
    assert data["anova"]["Error"]["f"] is None       # NaN -> null
    assert sorted(p.name for p in tmp_path.iterdir()) == ["analysis.json", "main_effects.png",
                                                           "results.csv"]


def test_analyze_cli_on_the_paper_table_minus_one_run(tmp_path, cli):
    from tests.conftest import REFERENCE

    lines = (REFERENCE / "table3_l36_results.csv").read_text().splitlines()
    kept = [ln for ln in lines if not ln.startswith("18,")]
    assert len(kept) == len(lines) - 1
    path = tmp_path / "l35.csv"
    path.write_text("\n".join(kept) + "\n")
    res = cli("analyze", str(path), "--response", "te_arcmin", "--json")
    assert res.code == 0, res.err
    out = json.loads(res.out)
    assert out["anova"]["Total"]["df"] == 34
    assert any("unbalanced" in note for note in out["notes"])
    text = cli("analyze", str(path), "--response", "te_arcmin")
    assert text.code == 0 and "note: unbalanced table" in text.out


def test_analyze_leaves_failed_runs_out(tmp_path, cli):
    """Regression (hostile review): `rvsim analyze` on a study's results.csv used the numbers
    of runs that ended in a failure status."""
    import json

    rows = ["run,A,B,te_mean_arcmin,status"]
    for run, (a, b, y) in enumerate([(1, 1, 1.0), (1, 2, 2.0), (2, 1, 3.0), (2, 2, 4.5),
                                     (1, 1, 1.1), (1, 2, 2.2), (2, 1, 900.0), (2, 2, -50.0)],
                                    start=1):
        rows.append(f"{run},{a},{b},{y},{'energy_imbalance' if run > 6 else 'ok'}")
    path = tmp_path / "results.csv"
    path.write_text("\n".join(rows) + "\n")
    res = cli("analyze", str(path), "--json")
    assert res.code == 0, res.err
    out = json.loads(res.out)
    assert any("2 run(s)" in note for note in out["notes"])
    # k of A's level 2 from the two ok rows at level 2 only: (3.0 + 4.5) / 2
    assert out["range"]["A"]["k"][1] == pytest.approx(3.75)


@pytest.mark.parametrize("levels", [(-1, 1), (0, 1), (1e300, 1)])
def test_levels_must_be_positive_level_numbers(tmp_path, cli, levels):
    """Regression (hostile review): levels -1, 0 or 1e300 gave a column k-9223372036854775808."""
    rows = ["A,B,y"] + [f"{levels[i % 2]},{1 + i // 2 % 2},{1.0 + i}" for i in range(8)]
    path = tmp_path / "t.csv"
    path.write_text("\n".join(rows) + "\n")
    res = cli("analyze", str(path), "--response", "y")
    assert res.code == 2 and "factor column 'A'" in res.err and len(res.err.splitlines()) == 1


def test_factors_with_longer_labels_are_found_beside_single_letters(table3, tmp_path, cli):
    # found by a hostile review: a study's factor labelled "mod" was left out of `rvsim
    # analyze`, its effect folded into the error (H's p 0.34, "significant: none")
    table = table3.rename(columns={"J": "mod", "te_arcmin": "te_mean_arcmin"})
    table["energy_residual"] = 1e-5            # a study's result columns are not factors
    table["steps"] = 2
    table["run"] = range(1, 37)
    table.to_csv(tmp_path / "results.csv", index=False)
    res = cli("analyze", str(tmp_path / "results.csv"), "--json")
    assert res.code == 0, res.err
    data = json.loads(res.out)
    reference = analyze_table(table3, "te_arcmin")
    mod, j = data["range"]["mod"], reference["range"]["J"]
    assert mod.keys() == j.keys() and mod["levels"] == j["levels"]
    assert mod["R"] == pytest.approx(j["R"], rel=1e-12)
    assert mod["k"] == pytest.approx(j["k"], rel=1e-12)
    assert data["order"] == reference["order"].replace("J", "mod")
    from rvsim._json import to_json_safe

    assert data["anova"] == json.loads(json.dumps(to_json_safe(reference["anova"]))
                                       .replace('"J"', '"mod"'))
    assert "taken as factors by their level codes: mod (name the factors" in data["notes"][0]
    # a run-order column (each code once, Minitab's RunOrder) is not a factor (a reviewer's
    # case: it was, and the table was refused for too few runs)
    table["RunOrder"] = range(36, 0, -1)
    table.to_csv(tmp_path / "results.csv", index=False)
    again = json.loads(cli("analyze", str(tmp_path / "results.csv"), "--json").out)
    assert _p_values(again) == pytest.approx(_p_values(data), rel=1e-9)
    # beside a study's study.json, its own factor labels are the factors, without a note
    (tmp_path / "study.json").write_text(json.dumps(
        {"factors": [{"label": f} for f in table3.columns if len(f) == 1 and f != "J"]
         + [{"label": "mod"}]}))
    table["batch"] = [1, 2] * 18            # a user's column of codes: not the study's
    table.to_csv(tmp_path / "results.csv", index=False)
    study = json.loads(cli("analyze", str(tmp_path / "results.csv"), "--json").out)
    assert _p_values(study) == pytest.approx(_p_values(data), rel=1e-9)
    assert "notes" not in study


def _p_values(result):
    return {f: row["p"] for f, row in result["anova"].items() if row["p"] is not None}


def test_a_zero_response_has_no_sn_ratios_and_says_so(tmp_path, cli):
    # it printed numpy's "divide by zero" warning and null S/N values without a word
    (tmp_path / "z.csv").write_text("run,H,I,te_mean_arcmin\n1,1,1,0\n2,1,2,0.6\n3,2,1,0.7\n"
                                    "4,2,2,0.9\n")
    res = cli("analyze", str(tmp_path / "z.csv"), "--json")
    assert res.code == 0 and res.err == ""
    data = json.loads(res.out)
    assert data["sn_response"] is None and any("no S/N ratios" in n for n in data["notes"])


def test_a_label_with_dollars_is_drawn_as_written(table3, tmp_path):
    # a reviewer's factor "x$_$" started matplotlib's mathtext and failed the figure (the
    # study ended in a traceback after all its runs, with no results.csv)
    from rvsim.analysis.interactions import interaction_plots
    from rvsim.plots import figure_to_png, main_effects_plot

    # two factors (two panels to draw; the labels are what is checked)
    table = table3[["H", "I", "te_arcmin"]].rename(columns={"H": "x$_$", "te_arcmin": "te $y$"})
    figure = main_effects_plot(range_analysis(table, "te $y$"))
    figure_to_png(figure, tmp_path / "effects.png")
    figure = interaction_plots(table, "te $y$", [("x$_$", "I")])
    figure_to_png(figure, tmp_path / "interactions.png")
    assert (tmp_path / "effects.png").stat().st_size > 1000
