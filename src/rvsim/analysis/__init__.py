"""Analysis of designs of experiments: range analysis, ANOVA, S/N ratios (Minitab-grade); and
the catalogue quantities of reducer curves (:mod:`rvsim.analysis.catalogue`).

Names load on first use (:mod:`lazy_loader`), so the catalogue functions a quasi-static run
needs do not import pandas.
"""

import lazy_loader

__getattr__, __dir__, _ = lazy_loader.attach(__name__, submodules=["catalogue"], submod_attrs={
    "anova": ["AnovaTable", "anova", "predict_optimum", "signal_to_noise_smaller",
              "sn_response_table"],
    "range_analysis": ["RangeAnalysis", "range_analysis"],
})

__all__ = ["RangeAnalysis", "range_analysis", "AnovaTable", "anova", "predict_optimum",
           "signal_to_noise_smaller", "sn_response_table", "analyze_table", "catalogue"]


def analyze_table(table, response: str = "te_arcmin", factors=None, *, pool=(),
                  alpha: float = 0.1, sn: str | None = None) -> dict:
    """Everything ``rvsim analyze --json`` prints, as one dict (``order`` is None, and
    ``constant_response`` true, when the response is constant to round-off).  ``sn``: the S/N
    kind of the response table ("smaller", "larger"; None: the response's own sense,
    :func:`rvsim.analysis.signal_noise.table_kind`); a larger-the-better response's optimum
    is its largest level mean.  ``sn_kind`` says which (None for an S/N column)."""
    from .anova import anova, predict_optimum, sn_response_table
    from .range_analysis import range_analysis
    from .signal_noise import table_kind

    kind = table_kind(response, sn)
    larger = None if kind is None else kind == "larger"
    ra = range_analysis(table, response, factors, larger=larger)
    table_anova = anova(table, response, factors, pool=pool)
    out = ra.to_dict()
    out["anova"] = table_anova.to_dict()
    out["significant"] = table_anova.significant(alpha)
    out["alpha"] = alpha
    out["prediction"] = predict_optimum(table, table_anova, response, alpha=alpha,
                                        larger=larger)
    out["sn_kind"] = kind
    from .anova import CONSTANT_NOTE

    if CONSTANT_NOTE in table_anova.notes:
        # the ranges are round-off: no order of the factors (docs/decisions.md)
        out["order"] = None
        out["constant_response"] = True
    from .anova import ZERO_RESPONSE_NOTE

    notes = list(dict.fromkeys(list(ra.notes) + list(table_anova.notes)))
    if factors is None:                 # say which columns were taken by their level codes
        coded = [f for f in ra.level_means if not (len(str(f)) == 1 and str(f).isalpha())]
        if coded:
            notes.append(f"taken as factors by their level codes: {', '.join(coded)} (name "
                         "the factors with --factors if that is wrong)")
    from .range_analysis import larger_is_better

    # the response is itself an S/N ratio (a robust study's): no S/N of it (issue 33)
    sn = None if kind is None else sn_response_table(table, response, factors, kind)
    if kind == "larger":
        notes.append(f"{response} is larger-the-better: S/N = -10 log10(1/y^2) and the "
                     "optimum takes the largest level mean")
    if larger_is_better(response):
        out["sn_response"] = None
        notes.append(f"{response} is an S/N ratio: larger is better (the optimum maximises "
                     "it); no S/N ratio of it is taken")
    elif sn is None:
        notes.append(ZERO_RESPONSE_NOTE)
        out["sn_response"] = None
    else:
        out["sn_response"] = {f: {"levels": [v for v in row[:-2] if v == v],
                                  "delta": row["delta"], "rank": int(row["rank"])}
                              for f, row in sn.iterrows()}
    if notes:
        out["notes"] = notes
    return out
