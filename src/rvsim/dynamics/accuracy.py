"""Is a faster integration scheme as accurate as the explicit reference? (issue 35, item 1)

The criterion, over a set of runs (the paper's 36 L36 runs in benchmarks/
bench_scheme_accuracy.py, two shortened ones in tests/verification/test_scheme_accuracy.py):

* every run of the candidate and of the reference ends ``ok``;
* the mean TE of each run within :data:`MEAN_TE_LIMIT` (relative) of the reference's;
* the candidate's energy balance within :data:`ENERGY_LIMIT` of the input work in each run
  (``Result.energy["relative_residual"]``, the figure a run's status is judged on);
* for each peak metric (:data:`PEAK_METRICS`), the candidate's relative differences from the
  reference no larger than the chaotic spread: the change of the same metric when the
  reference's step is multiplied by 1 + :data:`PERTURBATION` (physically the same run, other
  rounding).  One perturbation gives one sample of the spread per run, so the two are compared
  as distributions over the runs: the median difference no larger than the median spread and
  the largest no larger than the largest (docs/decisions.md, issue 35 fifth session; the
  count of runs whose difference is within their own spread is reported beside it).

:func:`measure_run` runs one reducer (reference, perturbed reference, candidates),
:func:`differences` turns its metrics into one row per candidate, :func:`judge` applies the
criterion to the rows of many runs.
"""

from __future__ import annotations

import math
import time

from .model import EXPLICIT, SCHEMES

__all__ = ["MEAN_TE_LIMIT", "ENERGY_LIMIT", "PERTURBATION", "PEAK_METRICS", "REFERENCE",
           "PERTURBED", "candidate_name", "measure_run", "differences", "judge"]

#: largest relative difference of a run's mean TE from the explicit reference (issue 35)
MEAN_TE_LIMIT = 1e-4
#: largest |energy residual| of a candidate's run, relative to its input work (issue 35)
ENERGY_LIMIT = 1e-3
#: relative change of the reference's step that measures a run's chaotic spread (issue 35)
PERTURBATION = 1e-12
#: the peak metrics a run reports (``Result.metrics``); NaN in both runs (the ATE of a steady
#: window shorter than an output revolution) is left out
PEAK_METRICS = ("te_pp_arcmin", "max_pin_force_n", "te_max_arcmin", "ate_arcmin")
#: the reference and its perturbed twin, as :func:`measure_run` names them
REFERENCE = EXPLICIT
PERTURBED = f"{EXPLICIT}+{PERTURBATION:g}"
_KEPT = ("te_mean_arcmin", "energy_residual") + PEAK_METRICS


def candidate_name(scheme: str, time_step: float | None = None) -> str:
    """The name of a candidate: its scheme, with ``@step`` when not the scheme's own step."""
    return scheme if time_step is None else f"{scheme}@{time_step:g}"


def _parse(name: str) -> tuple[str, float | None]:
    scheme, _, step = name.partition("@")
    return scheme, (float(step) if step else None)


def measure_run(reducer, candidates=("implicit-bearings",), *, duration=None,
                reference: bool = True) -> dict:
    """Simulate ``reducer`` with the explicit reference, the reference at its step x (1 +
    :data:`PERTURBATION`) and each candidate (``"scheme"`` or ``"scheme@step"``; with
    ``reference=False`` the candidates alone, to add to an earlier measurement).  Returns
    {name: {metric: value, "status": ..., "cpu_s": thread CPU time of the run}}; failed runs
    are returned with their status, not raised."""
    from .simulate import simulate

    step = SCHEMES[REFERENCE]
    runs = ({REFERENCE: (REFERENCE, step), PERTURBED: (REFERENCE, step * (1.0 + PERTURBATION))}
            if reference else {})
    runs.update({name: _parse(name) for name in candidates})
    out = {}
    for name, (scheme, time_step) in runs.items():
        cpu = time.thread_time()
        result = simulate(reducer, duration=duration, time_step=time_step, scheme=scheme,
                          raise_on_failure=False)
        cpu = time.thread_time() - cpu
        metrics = result.metrics
        out[name] = {**{k: float(metrics[k]) for k in _KEPT}, "status": result.status,
                     "cpu_s": cpu}
    return out


def _relative(value: float, reference: float) -> float:
    """|value - reference| / |reference|; 0 where both are 0, inf where only the reference is."""
    if reference == 0.0:
        return 0.0 if value == 0.0 else math.inf
    return abs(value - reference) / abs(reference)


def differences(measured: dict, candidate: str) -> dict:
    """One run's row for ``candidate`` from :func:`measure_run`'s answer: statuses, the mean
    TE's relative difference (and, for information, its chaotic spread), the candidate's
    energy residual, and for each peak metric the candidate's relative difference
    (``<metric>_difference``) and the perturbed reference's (``<metric>_spread``), NaN where
    the metric is NaN in the reference."""
    ref, twin, cand = measured[REFERENCE], measured[PERTURBED], measured[candidate]
    row = {"status_reference": ref["status"], "status_perturbed": twin["status"],
           "status_candidate": cand["status"],
           "mean_te_difference": _relative(cand["te_mean_arcmin"], ref["te_mean_arcmin"]),
           "mean_te_spread": _relative(twin["te_mean_arcmin"], ref["te_mean_arcmin"]),
           "energy_residual": cand["energy_residual"],
           "cpu_reference_s": ref["cpu_s"], "cpu_candidate_s": cand["cpu_s"]}
    for metric in PEAK_METRICS:
        row[f"{metric}_difference"] = _relative(cand[metric], ref[metric])
        row[f"{metric}_spread"] = _relative(twin[metric], ref[metric])
    return row


def _median_max(values) -> dict:
    import numpy as np

    values = np.asarray([v for v in values if not math.isnan(v)], dtype=float)
    if not len(values):
        return {"median": float("nan"), "max": float("nan")}
    return {"median": float(np.median(values)), "max": float(values.max())}


def judge(rows: list[dict]) -> dict:
    """The criterion over the rows (:func:`differences`) of one candidate's runs: for each
    part its figures, limit and ``passed``, and ``passed`` overall.  A NaN figure (a run that
    failed) fails its part."""
    failed = [i for i, row in enumerate(rows)
              if (row["status_reference"], row["status_perturbed"],
                  row["status_candidate"]) != ("ok", "ok", "ok")]
    verdict = {"status": {"runs": len(rows), "not_ok": failed,
                          "passed": bool(rows) and not failed}}      # no runs: no verdict
    mean = [row["mean_te_difference"] for row in rows]
    energy = [abs(row["energy_residual"]) for row in rows]
    for key, values, limit in (("mean_te", mean, MEAN_TE_LIMIT),
                               ("energy", energy, ENERGY_LIMIT)):
        figures = _median_max(values)
        ok = all(v <= limit for v in values)          # False for a NaN
        verdict[key] = {**figures, "limit": limit, "passed": ok}
    verdict["mean_te"]["spread"] = _median_max([row["mean_te_spread"] for row in rows])
    for metric in PEAK_METRICS:
        pairs = [(row[f"{metric}_difference"], row[f"{metric}_spread"]) for row in rows
                 if not math.isnan(row[f"{metric}_spread"])]
        if not pairs:
            continue
        difference = _median_max([d for d, _ in pairs])
        spread = _median_max([s for _, s in pairs])
        ok = (all(not math.isnan(d) for d, _ in pairs)
              and difference["median"] <= spread["median"]
              and difference["max"] <= spread["max"])
        within = sum(d <= s for d, s in pairs)       # the stricter run-by-run reading
        verdict[metric] = {"difference": difference, "spread": spread,
                           "runs_within_spread": within, "runs": len(pairs), "passed": ok}
    verdict["passed"] = all(part["passed"] for part in verdict.values())
    return verdict
