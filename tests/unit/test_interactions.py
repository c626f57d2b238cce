"""ANOVA with two-factor interactions (issue 11 item 4) on tables with known effects."""

import itertools

import numpy as np
import pandas as pd
import pytest

from rvsim.analysis.interactions import interaction_anova, interaction_degrees
from rvsim.errors import InputFileError


def _factorial(response):
    rows = [dict(zip("ABC", levels)) for levels in itertools.product((1, 2, 3), repeat=3)]
    table = pd.DataFrame(rows)
    table["y"] = [response(r["A"], r["B"], r["C"]) for r in rows]
    return table


def test_an_interaction_is_found_and_sized():
    # y = A + 2 B + A*B (the product's non-additive part) + small noise; C no effect
    rng = np.random.default_rng(1)
    table = _factorial(lambda a, b, c: a + 2 * b + a * b + 1e-5 * rng.standard_normal())
    rows = interaction_anova(table, "y", list("ABC"))
    assert rows.loc["A x B", "P"] < 1e-6
    assert rows.loc["A x C", "P"] > 0.01 and rows.loc["B x C", "P"] > 0.01
    # the interaction SS of a*b on a 3x3x3 design: sum over cells of (ab - row - col + mean)^2
    ab = np.outer([1, 2, 3], [1, 2, 3]).astype(float)
    resid = ab - ab.mean(1)[:, None] - ab.mean(0)[None, :] + ab.mean()
    assert rows.loc["A x B", "SS"] == pytest.approx(3 * np.sum(resid ** 2), rel=1e-4)
    assert rows.loc["Total", "share"] == pytest.approx(1.0)


def test_an_additive_response_has_no_interaction_share():
    table = _factorial(lambda a, b, c: a + 2 * b - c)
    table["y"] += np.random.default_rng(2).standard_normal(len(table)) * 1e-6
    rows = interaction_anova(table, "y", list("ABC"))
    shares = rows.loc[[i for i in rows.index if " x " in i], "share"]
    assert shares.max() < 1e-9


def test_a_design_without_the_degrees_of_freedom_is_refused():
    table = _factorial(lambda a, b, c: a).iloc[:9]            # 9 runs, 3 factors
    assert interaction_degrees(table, list("ABC"))[1] == 8
    with pytest.raises(InputFileError, match="degrees of freedom"):
        interaction_anova(table, "y", ["A", "B"] + ["C"])


def test_runs_that_alias_terms_are_refused_in_one_line_without_a_warning():
    """A study stopped part-way: its finished runs may leave enough degrees of freedom by
    count and still alias terms (here A and B always equal).  statsmodels warned
    (SingularMatrixWarning) on the stopped study's stderr; now one InputFileError."""
    rows = [dict(zip("ABC", (a, a, c))) for a, c in itertools.product((1, 2), repeat=2)] * 2
    table = pd.DataFrame(rows)
    table["y"] = np.arange(len(table), dtype=float)
    need, have = interaction_degrees(table, list("ABC"))
    assert need < have                            # the count alone lets it through
    import warnings
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        with pytest.raises(InputFileError, match=r"do not separate .*\(rank 4 of 7 terms"):
            interaction_anova(table, "y", list("ABC"))
