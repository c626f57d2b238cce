"""Taguchi's signal-to-noise ratios of replicated responses, and the columns of a robust study.

A robust study (a design whose every run is built ``samples`` times with drawn part errors,
:mod:`rvsim.tolerance.robust`) stores, per metric ``m``, the replicates' ``m_mean``,
``m_std``, ``m_p5``, ``m_p50``, ``m_p95`` and the three S/N ratios [dB]:

* smaller-the-better ``m_sn_smaller`` = -10 log10(mean(y^2));
* nominal-the-best ``m_sn_nominal`` = 10 log10(ybar^2 / s^2), s the sample standard
  deviation (n - 1);
* larger-the-better ``m_sn_larger`` = -10 log10(mean(1 / y^2));

and ``m_sn``, the ratio of the metric's own sense (:func:`sense`): larger-the-better for a
stiffness, a rigidity, the rated torque, the pins in contact (load sharing) and an
efficiency, smaller-the-better for every other metric (TE,
ATE, lost motion, forces, stresses).  Formulas: Minitab, "What is the signal-to-noise ratio?"
(Taguchi designs, static S/N ratios); Phadke, *Quality Engineering Using Robust Design*
(1989) (docs/model.md section 20).  A ratio that is not finite (a response of
exactly 0, or no spread) is None.
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["signal_to_noise", "signal_to_noise_smaller", "KINDS", "sense", "robust_columns",
           "STATISTICS", "table_kind"]

#: the S/N kinds and their column suffixes
KINDS = ("smaller", "nominal", "larger")
#: the replicate statistics of every metric (column suffixes)
STATISTICS = ("mean", "std", "p5", "p50", "p95")
#: metrics whose larger value is the better (every other: smaller is better)
_LARGER_IS_BETTER = ("torsional_stiffness_nm_per_arcmin", "torsional_rigidity_nm_per_arcmin",
                     "rated_torque_nm", "pins_in_contact_min", "pins_in_contact_max",
                     "efficiency")


def signal_to_noise_smaller(values) -> float:
    """Taguchi smaller-is-better S/N ratio: -10 log10(mean(y^2)) [dB] (the paper's Table 3
    analysis; :mod:`rvsim.analysis.anova` takes it from here)."""
    y = np.asarray(values, dtype=float)
    return float(-10.0 * np.log10(np.mean(y * y)))


def signal_to_noise(values, kind: str) -> float | None:
    """The ``kind`` ("smaller", "nominal", "larger") S/N ratio of ``values`` [dB]; None where
    it is not finite (a zero response; nominal-the-best: fewer than 2 values or no spread)."""
    y = np.asarray(values, dtype=float)
    if y.size == 0 or not np.all(np.isfinite(y)):
        return None
    with np.errstate(divide="ignore", invalid="ignore"):
        if kind == "smaller":
            out = signal_to_noise_smaller(y)
        elif kind == "nominal":
            out = (10.0 * math.log10(float(np.mean(y)) ** 2 / float(np.var(y, ddof=1)))
                   if y.size > 1 and np.var(y, ddof=1) > 0 and np.mean(y) != 0 else math.inf)
        elif kind == "larger":
            out = (float(-10.0 * np.log10(np.mean(1.0 / (y * y)))) if np.all(y != 0)
                   else math.inf)
        else:
            raise ValueError(f"unknown S/N kind {kind!r} (known: {', '.join(KINDS)})")
    return float(out) if math.isfinite(out) else None


def sense(metric: str) -> str:
    """The S/N kind of ``metric``'s own sense: "larger" or "smaller"."""
    return "larger" if metric in _LARGER_IS_BETTER else "smaller"


def table_kind(response: str, kind: str | None = None) -> str | None:
    """The S/N kind of the S/N response table of ``response``, one value per run (a plain
    study's row): ``kind`` ("smaller", "larger"; --sn) or the response's own sense
    (:func:`sense`, of the metric a robust study's ``_mean``/``_p5``/``_p50``/``_p95`` column
    summarises).  None when the response is itself an S/N ratio (a robust study's
    ``..._sn*``: no S/N of an S/N).  ParameterError (--sn): an unknown kind, nominal-the-best
    (it needs the spread of replicates), a kind for an S/N column."""
    import re

    from ..errors import ParameterError
    from .range_analysis import larger_is_better

    if kind is not None and kind not in KINDS:
        raise ParameterError("--sn", f"'{kind}': expected one of {', '.join(KINDS)}")
    if larger_is_better(response):
        if kind is None:
            return None
        base = re.sub(r"_sn(_smaller|_nominal|_larger)?$", "", response)
        raise ParameterError("--sn", f"{response} is itself an S/N ratio over the noise "
                             f"replicates: choose its kind by the column (--response "
                             f"{base}_sn_{kind})")
    if kind == "nominal":
        raise ParameterError("--sn", "nominal-the-best, 10 log10(ybar^2 / s^2), needs the "
                             "spread of replicates and a run of a plain study has one value: "
                             "a study with a [noise] section gives m_sn_nominal (--response "
                             "ate_arcmin_sn_nominal)")
    return kind or sense(re.sub(r"_(mean|p5|p50|p95)$", "", str(response)))


def robust_columns(metrics) -> tuple[str, ...]:
    """The columns a robust study's rows have for ``metrics`` (module docstring)."""
    out = []
    for m in metrics:
        out += [f"{m}_{s}" for s in STATISTICS]
        out += [f"{m}_sn"] + [f"{m}_sn_{k}" for k in KINDS]
    return tuple(out)
