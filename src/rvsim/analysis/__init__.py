"""Analysis of designs of experiments: range analysis, ANOVA, S/N ratios (Minitab-grade)."""

from .anova import (AnovaTable, anova, predict_optimum, signal_to_noise_smaller,
                    sn_response_table)
from .range_analysis import RangeAnalysis, range_analysis

__all__ = ["RangeAnalysis", "range_analysis", "AnovaTable", "anova", "predict_optimum",
           "signal_to_noise_smaller", "sn_response_table", "analyze_table"]


def analyze_table(table, response: str = "te_arcmin", factors=None, *, pool=(),
                  alpha: float = 0.1) -> dict:
    """Everything ``rvsim analyze --json`` prints, as one dict."""
    ra = range_analysis(table, response, factors)
    table_anova = anova(table, response, factors, pool=pool)
    out = ra.to_dict()
    out["anova"] = table_anova.to_dict()
    out["significant"] = table_anova.significant(alpha)
    out["alpha"] = alpha
    out["prediction"] = predict_optimum(table, table_anova, response, alpha=alpha)
    notes = list(dict.fromkeys(list(ra.notes) + list(table_anova.notes)))
    if notes:
        out["notes"] = notes
    sn = sn_response_table(table, response, factors)
    out["sn_response"] = {f: {"levels": [v for v in row[:-2] if v == v], "delta": row["delta"],
                              "rank": int(row["rank"])} for f, row in sn.iterrows()}
    return out
