"""Analysis: ANOVA identities, pooling, S/N, optimum prediction, malformed tables."""

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
    (lambda t: t.iloc[:-1], "unbalanced"),
])
def test_malformed_tables(table3, mutate, words):
    with pytest.raises(InputFileError, match=words):
        analyze_table(mutate(table3), "te_arcmin")


@pytest.mark.parametrize("content, words", [
    ("run,A,B\n1,1,1\n2,2,2\n", "response column"),
    ("run,A,te_arcmin\n1,1,x\n2,2,1\n", "not a number"),
    ("", "empty"),
])
def test_analyze_cli_errors(tmp_path, cli, content, words):
    path = tmp_path / "t.csv"
    path.write_text(content)
    res = cli("analyze", str(path), "--response", "te_arcmin")
    assert res.code == 2 and words in res.err and res.err.count("\n") == 1


def test_analyze_cli_missing_file(cli):
    res = cli("analyze", "/nonexistent/table.csv")
    assert res.code == 2 and "not found" in res.err
