"""Main-effects ANOVA as Minitab prints it, with pooling, S/N ratios and optimum prediction.

The model is y = mean + sum of factor main effects (categorical).  Sums of squares are
Minitab's "Adj SS" (for a balanced orthogonal array they equal the sequential ones).
statsmodels fits the models on patsy's design matrix; factor columns are renamed before the
formula is built because patsy reserves C, I and Q.
"""

from __future__ import annotations

import dataclasses
import math
import numbers

import numpy as np
import pandas as pd

from ..errors import InputFileError
from ._table import UNBALANCED_NOTE, check_design_table, factor_columns, is_balanced
from .signal_noise import signal_to_noise, signal_to_noise_smaller

__all__ = ["AnovaTable", "anova", "signal_to_noise_smaller", "sn_response_table",
           "ZERO_RESPONSE_NOTE",
           "predict_optimum", "CONSTANT_NOTE"]

#: note of an ANOVA whose response varies only at round-off level
CONSTANT_NOTE = ("the response is constant to round-off: no factor can be significant "
                 "(F and P left empty)")
#: sums of squares are trusted above this many units of round-off (eps * max|y|, per run)
_ROUND_OFF_UNITS = 1e4


@dataclasses.dataclass(frozen=True)
class AnovaTable:
    """Rows by source (factors, Error, Total) with DF, Adj SS, Adj MS, F, P."""

    rows: dict[str, dict[str, float]]
    pooled: tuple[str, ...]
    response: str
    notes: tuple[str, ...] = ()

    def significant(self, alpha: float = 0.1) -> list[str]:
        alpha = check_alpha(alpha)
        return [s for s, r in self.rows.items()
                if s not in ("Error", "Total") and not math.isnan(r["p"]) and r["p"] < alpha]

    def to_dict(self) -> dict:
        return {s: {"df": int(r["df"]), "adj_ss": r["adj_ss"], "adj_ms": r["adj_ms"],
                    "f": r["f"], "p": r["p"]} for s, r in self.rows.items()}

    def to_df(self) -> pd.DataFrame:
        frame = pd.DataFrame(self.rows).T
        frame["df"] = frame["df"].astype(int)
        return frame[["df", "adj_ss", "adj_ms", "f", "p"]]


def anova(table: pd.DataFrame, response: str = "te_arcmin", factors=None, *,
          pool: tuple[str, ...] | list[str] = ()) -> AnovaTable:
    """Main-effects ANOVA of ``response``; factors in ``pool`` go into the error term.

    Adj SS of a factor is SSR(model without it) - SSR(full model), both fitted by least
    squares (statsmodels OLS); for a main-effects model that is Minitab's adjusted (type III)
    sum of squares, and it stays defined for saturated designs (error DF 0: F and P empty)
    and for unbalanced tables (a failed run missing), which carry a note saying so.

    Sums of squares within round-off of zero (``_ROUND_OFF_UNITS`` x machine epsilon x the
    largest response, per run) count as zero, so a constant response, or an exact fit, never
    yields an F value made of round-off.
    """
    import patsy
    from statsmodels.regression.linear_model import OLS

    factors = factor_columns(table, response, factors)
    unknown = [p for p in pool if p not in factors]
    if unknown:
        raise InputFileError(f"cannot pool {', '.join(unknown)}: not a factor column")
    data = check_design_table(table, response, factors)
    kept = [f for f in factors if f not in pool]
    alias = {f: f"f_{i}" for i, f in enumerate(kept)}
    frame = pd.DataFrame({alias[f]: data[f] for f in kept})
    frame["y"] = data[response].to_numpy()

    # the full model's design matrix (intercept, treatment-coded levels); a model without
    # some factors is the same matrix without their columns, so patsy builds it once
    design = patsy.dmatrix(" + ".join(f"C({alias[f]})" for f in kept) or "1", frame)
    columns = design.design_info.term_name_slices

    def residual(terms: list[str]) -> tuple[float, float]:
        names = ["Intercept"] + [f"C({alias[f]})" for f in terms]
        # Fortran order, as patsy's own matrices: the same sums as the formula fits, to the bit
        fit = OLS(frame["y"].to_numpy(), np.asfortranarray(np.column_stack(
            [np.asarray(design)[:, columns[n]] for n in names]))).fit()
        return float(fit.ssr), float(fit.df_resid)

    y = frame["y"].to_numpy()
    total_ss = float(((y - y.mean()) ** 2).sum())
    floor = len(y) * (_ROUND_OFF_UNITS * np.finfo(float).eps * float(np.abs(y).max())) ** 2
    constant = total_ss <= floor
    notes = [] if is_balanced(data, factors) else [UNBALANCED_NOTE]
    if constant:
        notes.append(CONSTANT_NOTE)
    error_ss, error_df = residual(kept)
    error_ss = error_ss if error_df > 0 and error_ss > floor else 0.0
    error_ms = error_ss / error_df if error_df > 0 else float("nan")
    rows: dict[str, dict[str, float]] = {}
    for f in kept:
        reduced_ss, reduced_df = residual([g for g in kept if g != f])
        ss, df = reduced_ss - error_ss, reduced_df - error_df
        if df < 1:
            raise InputFileError(f"factor column '{f}': its effect cannot be separated from "
                                 "the other factors in this table (confounded)")
        if ss <= floor + 1e-9 * reduced_ss:
            ss = 0.0                    # round-off of two nearly equal residual sums
        ms = ss / df
        usable = error_df > 0 and error_ms > 0 and not constant
        f_value = ms / error_ms if usable else float("nan")
        rows[f] = {"df": df, "adj_ss": ss, "adj_ms": ms, "f": f_value,
                   "p": _p_value(f_value, df, error_df)}
    rows["Error"] = {"df": error_df, "adj_ss": error_ss, "adj_ms": error_ms,
                     "f": float("nan"), "p": float("nan")}
    rows["Total"] = {"df": float(len(y) - 1), "adj_ss": total_ss,
                     "adj_ms": float("nan"), "f": float("nan"), "p": float("nan")}
    return AnovaTable(rows, tuple(pool), response, tuple(notes))


def _p_value(f_value: float, df1: float, df2: float) -> float:
    if not (df2 > 0 and math.isfinite(f_value)):
        return float("nan")
    from scipy.stats import f as f_dist

    return float(f_dist.sf(f_value, df1, df2))


def check_alpha(alpha) -> float:
    """A significance level strictly between 0 and 1 (ParameterError): alpha = 5, a percent
    typed as a number, made every factor significant."""
    from ..errors import ParameterError

    if isinstance(alpha, bool) or not isinstance(alpha, numbers.Real) or not 0 < alpha < 1:
        raise ParameterError("alpha", f"must be a number between 0 and 1 (got {alpha!r})")
    return float(alpha)


#: why a table has no S/N ratios
ZERO_RESPONSE_NOTE = ("no S/N ratios: a run's response is exactly 0, where the S/N ratio "
                      "(-10 log10(y^2), or -10 log10(1/y^2) larger-the-better) is infinite")


def sn_response_table(table: pd.DataFrame, response: str = "te_arcmin", factors=None,
                      kind: str = "smaller") -> pd.DataFrame | None:
    """Mean S/N ratio per factor level, with Delta and Rank (Minitab), one value per run:
    ``kind`` "smaller" (-10 log10(y^2)) or "larger" (-10 log10(1/y^2)) the better
    (:func:`rvsim.analysis.signal_noise.signal_to_noise`); None when a run's response is 0
    (:data:`ZERO_RESPONSE_NOTE`).  The best level is the largest mean either way."""
    factors = factor_columns(table, response, factors)
    data = check_design_table(table, response, factors)
    ratios = [signal_to_noise([v], kind) for v in data[response]]
    if any(r is None for r in ratios):
        return None
    data = data.assign(sn=ratios)
    every = sorted({int(lv) for f in factors for lv in data[f].unique()})
    out = {}
    for f in factors:
        means = data.groupby(f)["sn"].mean()
        out[f] = [float(means.get(lv, float("nan"))) for lv in every]
    frame = pd.DataFrame(out, index=[f"level {lv}" for lv in every]).T
    frame["delta"] = frame.max(axis=1) - frame.min(axis=1)
    frame["rank"] = frame["delta"].rank(ascending=False, method="first").astype(int)
    return frame


def predict_optimum(table: pd.DataFrame, anova_table: AnovaTable, response: str = "te_arcmin",
                    *, alpha: float = 0.1, larger: bool | None = None) -> dict:
    """Predicted response at the optimum from the significant factors only (Taguchi).

    y_opt = grand mean + sum over significant factors of (best level mean - grand mean);
    the best level the largest mean when ``larger`` (None: :func:`larger_is_better`).
    """
    from .range_analysis import range_analysis

    ra = range_analysis(table, response, [f for f in anova_table.rows
                                          if f not in ("Error", "Total")] + list(
        anova_table.pooled), larger=larger)
    significant = anova_table.significant(alpha)
    best = ra.optimum
    value = ra.grand_mean + sum(ra.mean_at(f, best[f]) - ra.grand_mean for f in significant)
    return {"significant": significant, "levels": {f: best[f] for f in significant},
            "predicted": value, "alpha": alpha}
