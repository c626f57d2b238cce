"""Two-factor interactions of a design: ANOVA with interaction terms, interaction plots
(:mod:`.figures`).

The model is y = mean + main effects + every two-factor interaction (all categorical), fitted
with statsmodels; sums of squares are type II (for a balanced full factorial they equal the
sequential ones).  The design must leave degrees of freedom for the error after the main
effects and the interactions (a full factorial, or a resolution V fraction): otherwise
:func:`interaction_anova` raises InputFileError saying how many are missing, or that the runs
alias some terms (rank-deficient: a design interrupted part-way, its finished runs only).
"""

from __future__ import annotations

import itertools
import math
import warnings

import numpy as np
import pandas as pd

from ..errors import InputFileError
from .figures import interaction_plots   # public here too (issue 31 step 6)

__all__ = ["interaction_anova", "interaction_degrees", "interaction_plots"]


def interaction_degrees(table: pd.DataFrame, factors: list[str]) -> tuple[int, int]:
    """(degrees of freedom the main effects and two-factor interactions need, runs - 1)."""
    levels = {f: table[f].nunique() for f in factors}
    need = sum(n - 1 for n in levels.values())
    need += sum((levels[a] - 1) * (levels[b] - 1) for a, b in itertools.combinations(factors, 2))
    return need, len(table) - 1


def interaction_anova(table: pd.DataFrame, response: str, factors: list[str]) -> pd.DataFrame:
    """ANOVA rows (main effects, A x B, Error, Total) with DF, SS, MS, F, P and each source's
    share of the total sum of squares, largest first (Error and Total last)."""
    import statsmodels.api as sm
    from statsmodels.formula.api import ols

    need, have = interaction_degrees(table, factors)
    if need >= have:
        raise InputFileError(f"the design has {have} degrees of freedom; the main effects and "
                             f"two-factor interactions of {len(factors)} factors need {need} "
                             "plus at least one for the error (run a full factorial or a "
                             "resolution V design)")
    # patsy reserves C, I and Q: rename the columns
    names = {f: f"f{i}" for i, f in enumerate(factors)}
    data = table[factors + [response]].rename(columns=names | {response: "y"})
    terms = [f"C({names[f]})" for f in factors]
    pairs = [f"C({names[a]}):C({names[b]})" for a, b in itertools.combinations(factors, 2)]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")     # a singular design is refused below, in one line
        model = ols("y ~ " + " + ".join(terms + pairs), data=data).fit()
        design = model.model.exog
        rank = np.linalg.matrix_rank(design)
        if rank < design.shape[1]:
            raise InputFileError(
                f"the {len(data)} runs do not separate the main effects and two-factor "
                f"interactions of {len(factors)} factors (rank {rank} of {design.shape[1]} "
                "terms: some "
                "are aliased; run a full factorial or a resolution V design, all its runs "
                "finished)")
        frame = sm.stats.anova_lm(model, typ=2)
    back = {f"C({v})": k for k, v in names.items()}

    def label(term: str) -> str:
        if term == "Residual":
            return "Error"
        return " x ".join(back[p] for p in term.split(":"))

    frame.index = [label(t) for t in frame.index]
    frame = frame.rename(columns={"df": "DF", "sum_sq": "SS", "PR(>F)": "P"})
    frame["MS"] = frame["SS"] / frame["DF"]
    total = float(np.sum((data["y"] - data["y"].mean()) ** 2))
    frame.loc["Total"] = {"DF": len(data) - 1, "SS": total, "F": math.nan, "P": math.nan,
                          "MS": math.nan}
    frame["share"] = frame["SS"] / total
    effects = frame.drop(index=["Error", "Total"]).sort_values("SS", ascending=False)
    return pd.concat([effects, frame.loc[["Error", "Total"]]])[["DF", "SS", "MS", "F", "P",
                                                                  "share"]]
