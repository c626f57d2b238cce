"""Analysis of designs of experiments: range analysis, ANOVA, S/N ratios (Minitab-grade); and
the catalogue quantities of reducer curves (:mod:`rvsim.analysis.catalogue`).

Names load on first use (:mod:`lazy_loader`), so the catalogue functions a quasi-static run
needs do not import pandas.
"""

import lazy_loader

from .._display import Headline

__getattr__, __dir__, _ = lazy_loader.attach(__name__, submodules=["catalogue"], submod_attrs={
    "anova": ["AnovaTable", "anova", "predict_optimum", "signal_to_noise_smaller",
              "sn_response_table"],
    "range_analysis": ["RangeAnalysis", "range_analysis"],
})

__all__ = ["RangeAnalysis", "range_analysis", "AnovaTable", "anova", "predict_optimum",
           "signal_to_noise_smaller", "sn_response_table", "analyze_table", "StudyAnalysis",
           "unit_suffix", "suffix_of_unit", "UNIT_SUFFIXES", "catalogue"]


#: the unit suffixes of rvsim's column names and the units they stand for (the longest
#: matching suffix wins: "_rad_per_s" before "_s")
UNIT_SUFFIXES = {"_nm_per_arcmin": "N*m/arcmin", "_nm_per_rad": "N*m/rad", "_n_per_m": "N/m",
                 "_mm2_s": "mm^2/s", "_rad_per_s": "rad/s", "_deg_per_s": "deg/s",
                 "_mm_per_s": "mm/s", "_kg_per_m3": "kg/m^3", "_arcmin": "arcmin",
                 "_arcsec": "arcsec", "_rad": "rad", "_deg": "deg", "_gpa": "GPa",
                 "_mpa": "MPa", "_pa": "Pa", "_nm": "N*m", "_n": "N", "_mm": "mm", "_um": "um",
                 "_hours": "h", "_rpm": "rpm", "_s": "s", "_hz": "Hz", "_kgm2": "kg*m^2",
                 "_c": "degC", "_pct": "%", "_sn": "dB"}

#: units that are plain numbers (no suffix)
_PLAIN = ("-", "count", "flag", "choice", "")


def unit_suffix(column: str) -> tuple[str, str]:
    """(suffix, unit) of a column's name ("te_mean_arcmin" -> ("_arcmin", "arcmin"), an S/N
    ratio "_sn" -> dB); ("", "") when it names no unit."""
    for suffix in sorted(UNIT_SUFFIXES, key=len, reverse=True):
        if str(column).endswith(suffix):
            return suffix, UNIT_SUFFIXES[suffix]
    return "", ""


def suffix_of_unit(unit: str) -> str:
    """The column suffix of a unit as docs/parameters.md writes it ("N*m" -> "_nm", "N/m" ->
    "_n_per_m", "kg*m^2" -> "_kgm2", "degC" -> "_c"); "" for a plain number."""
    if unit in _PLAIN:
        return ""
    known = {u: s for s, u in UNIT_SUFFIXES.items() if s != "_sn"}
    return known.get(unit) or "_" + unit.lower().replace("*", "").replace("^", "").replace(
        "/", "_per_")


class StudyAnalysis(Headline, dict):
    """What :func:`analyze_table` returns: the dict ``rvsim analyze --json`` prints (its keys
    as before), and the same as pandas DataFrames with the unit in each column name:
    ``ranges`` (level means k<level>, range R, rank, optimal level), ``anova`` (DF, adjusted
    sums and mean squares in the response's unit squared, F, P), ``sn`` (S/N ratio per
    level [dB], or None), and ``range_analysis`` (the :class:`RangeAnalysis` they come from).
    Shown as its answer (factor order, significant factors, optimum, prediction); ``plot()``
    draws the main effects."""

    def __init__(self, out: dict, range_analysis, ranges, anova_frame, sn):
        super().__init__(out)
        self.range_analysis = range_analysis
        self.ranges, self.anova, self.sn = ranges, anova_frame, sn

    def headline(self) -> tuple[str, list[tuple]]:
        """The response, the factor order, the significant factors and the prediction."""
        from .._display import number

        unit = unit_suffix(self.response)[1]
        prediction = self.get("prediction") or {}
        optimum = ", ".join(f"{f}{level}" for f, level in self["optimum"].items())
        return (f"Analysis of {self.response} ({len(self.ranges)} factors)",
                [("factor order (by range)", self.get("order") or "none: constant response"),
                 ("significant (alpha " + f"{self['alpha']:g})",
                  ", ".join(self["significant"]) or "none"),
                 ("optimum levels", optimum),
                 ("predicted at the optimum", number(prediction.get("predicted"), unit))])

    @property
    def response(self) -> str:
        return self.ranges.attrs["response"]

    def plot(self, ax=None):
        """Main effects: level means of each factor (:func:`rvsim.analysis.figures.
        main_effects_plot`); returns the first panel's Axes."""
        from .figures import main_effects_plot

        fig = main_effects_plot(self.range_analysis, ax=ax)
        return ax if ax is not None else fig.axes[0]


def _frames(ra, table_anova, sn, response: str):
    """The range, ANOVA and S/N tables with the unit in each column name."""
    suffix = unit_suffix(response)[0] or ""
    ranges = ra.to_df().rename(columns=lambda c: f"{c}{suffix}" if c.startswith("k")
                               or c == "R" else c)
    ranges.attrs["response"] = response
    squared = f"{suffix}2" if suffix else ""
    anova_frame = table_anova.to_df().rename(columns={"adj_ss": f"adj_ss{squared}",
                                                      "adj_ms": f"adj_ms{squared}"})
    if sn is not None:
        sn = sn.rename(columns=lambda c: f"{c.replace(' ', '')}_dB" if c.startswith("level")
                       or c == "delta" else c)
    return ranges, anova_frame, sn


def analyze_table(table, response: str | None = None, factors=None, *, pool=(),
                  alpha: float = 0.1, sn: str | None = None) -> StudyAnalysis:
    """Everything ``rvsim analyze --json`` prints, as one dict (``order`` is None, and
    ``constant_response`` true, when the response is constant to round-off), with the same
    tables as DataFrames (:class:`StudyAnalysis`).  ``response`` None: the study's default
    (the first of :data:`rvsim.analysis.indices.DEFAULT_RESPONSES` the table has).  ``sn``:
    the S/N kind of the response table ("smaller", "larger"; None: the response's own sense,
    :func:`rvsim.analysis.signal_noise.table_kind`); a larger-the-better response's optimum
    is its largest level mean.  ``sn_kind`` says which (None for an S/N column)."""
    from .anova import anova, predict_optimum, sn_response_table
    from .indices import check_response
    from .range_analysis import range_analysis
    from .signal_noise import table_kind

    if not hasattr(table, "columns"):  # a path or a Study was an AttributeError
        from ..errors import ParameterError

        raise ParameterError("table", f"a pandas DataFrame of a study's runs (pandas.read_csv "
                             f"of its results.csv; got {type(table).__name__})")
    if response is None:
        response = check_response(table, None, factors=factors or (), option="response")

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
    return StudyAnalysis(out, ra, *_frames(ra, table_anova, sn, response))
