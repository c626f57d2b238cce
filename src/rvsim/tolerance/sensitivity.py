"""Sobol indices of a tolerance study's errors with SALib (first, total, second order).

Each toleranced error is one group of SALib's problem (all its parts' random variables), so
its indices are those of the error as a whole.  The design is SALib's Saltelli-Sobol sample of
``base * (2 G + 2)`` reducers (G errors; ``base`` a power of 2); the confidence intervals are
SALib's bootstrap ones (95 %).  A reducer that binds or fails has no metric: it is given the
mean of the others (the count is reported with the indices).
"""

from __future__ import annotations

import math

import numpy as np

from ..errors import ParameterError
from .spec import ToleranceStudy

__all__ = ["problem", "sobol_units", "sobol_count", "sobol_indices", "check_base", "check_groups",
           "indices_from_samples"]


def check_base(base) -> int:
    if isinstance(base, bool) or not isinstance(base, (int, np.integer)) or base < 2 \
            or base & (base - 1) or base > 65536:
        raise ParameterError("sobol", f"the Sobol base sample size must be a power of 2 from "
                             f"2 to 65536 (got {base!r})")
    return int(base)


def check_groups(study: ToleranceStudy) -> None:
    """Sobol indices apportion the variance between two or more toleranced errors; with one,
    all of it is that error's (S1 = ST = 1), and SALib would take its parts' random numbers
    for the groups (it reads a single group as none) and report the first part's index."""
    if len(study.tolerances) < 2:
        names = ", ".join(t.name for t in study.tolerances) or "none"
        raise ParameterError("sobol", f"Sobol indices need two or more toleranced errors (this "
                             f"study has {len(study.tolerances)}: {names}; with one, all the "
                             "variance is its own)")


def problem(study: ToleranceStudy) -> dict:
    """SALib problem: one variable per random number, grouped by toleranced error."""
    groups = []
    for t, size in zip(study.tolerances, study.sizes()):
        groups += [t.name] * size
    names = [f"x{i}" for i in range(len(groups))]
    out = {"num_vars": len(groups), "names": names, "bounds": [[0.0, 1.0]] * len(groups)}
    if len(study.tolerances) < len(groups):
        out["groups"] = groups
    else:
        out["names"] = groups
    return out


def sobol_count(study: ToleranceStudy, base: int) -> int:
    return base * (2 * len(study.tolerances) + 2)


def sobol_units(study: ToleranceStudy, base: int) -> np.ndarray:
    """The Saltelli-Sobol design (rows of uniform numbers), reproducible from the seed."""
    from SALib.sample import sobol as sobol_sample

    check_base(base)
    return sobol_sample.sample(problem(study), base, calc_second_order=True,
                               seed=study.seed)


def indices_from_samples(prob: dict, y: np.ndarray, seed: int = 0, resamples: int = 200):
    """SALib's Sobol analysis of outputs ``y`` of a Saltelli-Sobol design: (first/total
    indices by group, second-order pairs sorted by S2, descending)."""
    return _analyze(prob, y, seed, resamples)[:2]


def _analyze(prob: dict, y: np.ndarray, seed: int = 0, resamples: int = 200):
    """:func:`indices_from_samples` and whether some bootstrap resamples were constant (SALib's
    warning, caught here: the confidence intervals are then unreliable)."""
    import warnings

    from SALib.analyze import sobol as sobol_analyze

    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        result = sobol_analyze.analyze(prob, np.asarray(y, dtype=float), calc_second_order=True,
                                       num_resamples=resamples, conf_level=0.95, seed=seed)
    constant = any("onstant values" in str(w.message) for w in caught)
    names = list(dict.fromkeys(prob.get("groups") or prob["names"]))
    first = {n: {"S1": float(result["S1"][i]), "ST": float(result["ST"][i]),
                 "S1_conf": float(result["S1_conf"][i]), "ST_conf": float(result["ST_conf"][i])}
             for i, n in enumerate(names)}
    pairs = []
    for i in range(len(names)):
        for j in range(i + 1, len(names)):
            pairs.append({"pair": [names[i], names[j]], "S2": float(result["S2"][i, j]),
                          "S2_conf": float(result["S2_conf"][i, j])})
    pairs.sort(key=lambda p: -p["S2"] if math.isfinite(p["S2"]) else math.inf)
    return first, pairs, constant


def sobol_indices(study: ToleranceStudy, values: dict, status: np.ndarray) -> dict:
    """{"sobol": {metric: {error: {S1, ST, S1_conf, ST_conf}}}, "sobol_second_order":
    {metric: [pairs]}, "sobol_imputed": count} from the Sobol design's outcomes."""
    prob = problem(study)
    first_all, second_all = {}, {}
    imputed = 0
    notes: list[str] = []
    for metric, y in values.items():
        y = np.array(y, dtype=float)
        bad = ~np.isfinite(y)
        if bad.all():
            continue
        imputed = max(imputed, int(bad.sum()))
        y[bad] = np.mean(y[~bad])
        if np.ptp(y) == 0.0:
            continue                   # a constant metric has no variance to share
        first, second = _indices(prob, y, study.seed, metric, notes)
        first_all[metric], second_all[metric] = first, second
    binds = (status == "binds").astype(float)
    if 0 < binds.sum() < len(binds):
        first, second = _indices(prob, binds, study.seed, "binds", notes)
        first_all["binds"], second_all["binds"] = first, second
    if imputed:
        notes.append(f"Sobol indices: {imputed} of the {len(status)} reducers of the design "
                     "bind or fail and were given the mean of the others: the indices describe "
                     "the reducers that assemble and solve, and are less certain than their "
                     "intervals say")
    out = {"sobol": first_all, "sobol_second_order": second_all, "sobol_imputed": imputed,
           "sobol_samples": int(len(status))}
    if notes:
        out["sobol_notes"] = notes
    return out


def _indices(prob: dict, y: np.ndarray, seed: int, metric: str, notes: list) -> tuple:
    first, second, constant = _analyze(prob, y, seed)
    if constant:
        notes.append(f"Sobol indices of {metric}: some bootstrap resamples had one value only (too few distinct "
                     "outcomes for this Sobol base); its confidence intervals are unreliable")
    return first, second
