"""Which transmission-error index a column holds, and whether a bench can check it (issue 33).

The paper's index is the mean TE after the start-up, from a centred assembly; a bench zeroes its
encoders at an arbitrary moment, so the mean of its TE carries no information.  What a bench,
GB/T 35089-2018 and the catalogues measure is the angular transmission error (ATE): the
peak-to-peak of TE over one output revolution (docs/catalogue_tests.md, docs/validation.md).
"""

from __future__ import annotations

import pandas as pd

from ..errors import ParameterError

__all__ = ["DEFAULT_RESPONSES", "response_label", "response_bench_note", "check_response"]

#: the response analysed when none is named: the paper's index (a study's results.csv), then
#: the paper's Table 3 column
DEFAULT_RESPONSES = ("te_mean_arcmin", "te_arcmin")

#: column -> (axis label, what it is and whether a bench can check it)
_INDICES = {
    "te_mean_arcmin": ("mean TE [arcmin]",
                       "the paper's index: the mean of TE over the window, from a centred "
                       "assembly (lost motion plus wind-up); no bench can check it, since a "
                       "bench zeroes its encoders at an arbitrary moment"),
    "te_arcmin": ("TE [arcmin]", "the paper's Table 3 index (its mean TE); no bench can "
                                 "check it"),
    "ate_arcmin": ("ATE [arcmin]",
                   "the angular transmission error, peak-to-peak TE over one output "
                   "revolution (GB/T 35089-2018, catalogues): what a bench measures"),
    "te_pp_arcmin": ("peak-to-peak TE [arcmin]",
                     "peak-to-peak TE over the run's window: the ATE, which a bench checks, "
                     "when the window covers an output revolution (quasi-static engine); a "
                     "dynamic run's steady window is usually a part of one "
                     "(te_window_revolutions)"),
    "lost_motion_arcmin": ("lost motion [arcmin]", "a torque-reversal quantity of GB/T "
                                                   "35089-2018: a bench measures it"),
    "backlash_arcmin": ("backlash [arcmin]", "a torque-reversal quantity of GB/T 35089-2018: "
                                             "a bench measures it"),
    "hysteresis_loss_arcmin": ("hysteresis loss [arcmin]", "a torque-reversal quantity of "
                               "GB/T 35089-2018: a bench measures it"),
    "torsional_rigidity_nm_per_arcmin": ("torsional rigidity [N*m/arcmin]", "a "
                                         "torque-reversal quantity of GB/T 35089-2018: a bench "
                                         "measures it"),
}


def response_label(column: str) -> str:
    """The axis label of ``column`` (the column's own name when it is no known index)."""
    robust = _robust(column)
    if robust:
        base, what = robust
        return f"{what} of {_INDICES.get(base, (base, ''))[0]}"
    return _INDICES.get(column, (column, ""))[0]


#: a robust study's column suffixes (rvsim.analysis.signal_noise) -> what they are
_ROBUST = {"_sn_smaller": "S/N smaller-the-better [dB]", "_sn_nominal": "S/N nominal-the-best "
           "[dB]", "_sn_larger": "S/N larger-the-better [dB]", "_sn": "S/N [dB]",
           "_mean": "mean", "_std": "std", "_p5": "p5", "_p50": "p50", "_p95": "p95"}


def _robust(column: str) -> tuple[str, str] | None:
    """(metric, statistic) of a robust study's column of a known index, else None."""
    for suffix, what in _ROBUST.items():
        if column.endswith(suffix) and column[:-len(suffix)] in _INDICES:
            return column[:-len(suffix)], what
    return None


def response_bench_note(column: str) -> str:
    """What ``column`` is and whether a bench can check it, in one sentence."""
    known = _INDICES.get(column)
    if known:
        return f"{column}: {known[1]}"
    robust = _robust(column)
    if robust:
        base, what = robust
        return (f"{column}: the {what} over a robust study's noise replicates of {base}, "
                f"{_INDICES[base][1]}")
    return (f"{column}: a metric of the runs, not a transmission-error index of the paper or of "
            "GB/T 35089-2018 (docs/validation.md says which quantities a bench measures)")


def _numeric(values: pd.Series) -> pd.Series:
    return pd.to_numeric(values, errors="coerce")


def check_response(table: pd.DataFrame, response: str | None, *, factors=(),
                   option: str = "--response") -> str:
    """The response column of ``table`` (its finished runs): ``response``, or the first of
    :data:`DEFAULT_RESPONSES` it has.  A column the table does not have, one without a single
    number, or a factor column raise :class:`ParameterError` on ``option`` naming the numeric
    columns there are.  (A column with some values missing passes: the analysis names the
    row.)"""
    factors = list(factors or ())
    numeric = [str(c) for c in table.columns if c not in factors and c != "run"
               and _numeric(table[c]).notna().any()]
    available = f"numeric columns: {', '.join(numeric) or 'none'}"
    if response is None:
        for name in DEFAULT_RESPONSES:
            if name in table.columns:
                return name
        raise ParameterError(option, f"the table has none of the default response columns "
                                     f"{', '.join(DEFAULT_RESPONSES)}: name one ({available})")
    if response not in table.columns:
        raise ParameterError(option, f"response column '{response}' not in the table "
                                     f"({available})")
    if response in factors or response == "run":
        what = "the run number" if response == "run" else "a factor column"
        raise ParameterError(option, f"'{response}' is {what}, not a response ({available})")
    if not _numeric(table[response]).notna().any():
        why = (" (their windows cover less than an output revolution: te_window_revolutions)"
               if response == "ate_arcmin" else "")
        raise ParameterError(option, f"response column '{response}' holds no number in the "
                                     f"finished runs{why} ({available})")
    return response
