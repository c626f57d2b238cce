"""Tolerance allocation: the cheapest (loosest) tolerances that meet percentile targets.

Cost model (docs/decisions.md, "Tolerance allocation"): each toleranced error k costs
``weight_k * (reference_k / t_k) ** exponent_k`` (the reciprocal-power cost-tolerance curve of
Chase, Greenwood et al. 1990; reference_k = the study's tolerance, so every error costs its
weight there); the total is their sum.  Each error's tolerance is searched between
``tightest_k`` and ``loosest_k`` (default a quarter and four times the study's).  A study
file's ``[cost.NAME]`` tables (weight, exponent, tightest, loosest) edit them.

The reducers that bind on assembly are scrap: the binding share is a constraint too, at most
``binding_share=VALUE`` of ``--target`` or, when not given, at most the share of the study's
own tolerances (so the allocation never buys its savings with more scrap than the drawing as
given).  Reducers the model cannot evaluate (a drawn value outside what it accepts, a solve
that fails) are left out of the percentiles, so their share is a constraint as well: at most
the share of the tolerances as given (without it, loosening a tolerance into values the model
refuses would shrink the percentiles it is judged by).  The constraints are Monte Carlo
percentiles of ``samples`` reducers with common random
numbers (the same uniform numbers, only the tolerances scale them), so they are smooth
functions of the tolerances; the optimiser is SciPy's COBYLA on the logarithms of the
tolerances.  Every evaluation is stored in the study store (a repeated point is not re-run).
"""

from __future__ import annotations

import dataclasses
import math
import re
import shutil

import numpy as np

from ..errors import InputFileError, ParameterError, check_type
from ..parameters import plain_number
from .engine import METRICS
from .spec import FEATURES, ToleranceStudy, largest_tolerance

__all__ = ["status_text", "CostModel", "cost_table", "parse_targets", "allocate", "Target"]

#: the optimiser's targets are this much (relative) tighter than the user's (see allocate)
MARGIN = 0.01
_SHORT = {short: name for name, (short, _) in METRICS.items()}
#: metrics where a larger value is better (the target is a lower bound)
_LOWER_BOUND = {"torsional_rigidity_nm_per_arcmin"}
#: the share of reducers that bind on assembly (a target without percentile)
BINDING = "binding_share"
#: the share of reducers the model cannot evaluate (a target without percentile, always the
#: share of the tolerances as given)
FAILED = "failed_share"
#: the targets on a share, not a percentile (absolute margins, no optimiser margin)
_SHARES = (BINDING, FAILED)


@dataclasses.dataclass(frozen=True)
class Target:
    metric: str          # summary key, e.g. ate_arcmin
    percentile: float    # 0-100
    value: float
    text: str

    @property
    def lower_bound(self) -> bool:
        return self.metric in _LOWER_BOUND

    def margin(self, achieved: float) -> float:
        """>= 0 when met (relative to the target; the binding share: absolute)."""
        scale = 1.0 if self.metric in _SHARES else (abs(self.value) or 1.0)
        return ((achieved - self.value) if self.lower_bound else (self.value - achieved)) / scale


def parse_targets(text: str) -> list[Target]:
    """``ate_p95=0.5,lost_motion_p95=1.2`` (arcmin; torsional_rigidity_p5=200 N*m/arcmin is
    a lower bound)."""
    targets = []
    for item in (text or "").split(","):
        item = item.strip()
        if not item:
            continue
        if item.split("=")[0].strip() == BINDING:
            try:
                value = plain_number(item.split("=", 1)[1])
            except (IndexError, ValueError):
                raise ParameterError("--target", f"'{item}': value is not a number") from None
            if not 0.0 <= value < 1.0:
                raise ParameterError("--target", f"'{item}': the binding share must be from 0 "
                                     "to below 1")
            if any(t.metric == BINDING for t in targets):
                raise ParameterError("--target", f"'{item}': {BINDING} is given twice")
            targets.append(Target(BINDING, math.nan, value, item))
            continue
        match = re.fullmatch(r"([a-z_]+)_p(\d+(?:\.\d+)?)=(.+)", item)
        if not match or match.group(1) not in _SHORT:
            raise ParameterError("--target", f"'{item}' is not METRIC_pNN=VALUE with METRIC one "
                                 f"of {', '.join(_SHORT)} (e.g. ate_p95=0.5), or "
                                 f"{BINDING}=VALUE")
        percentile = float(match.group(2))
        if not 0 < percentile < 100:
            raise ParameterError("--target", f"'{item}': percentile must be between 0 and 100")
        try:
            value = plain_number(match.group(3))
        except ValueError:
            raise ParameterError("--target", f"'{item}': value is not a number") from None
        if not math.isfinite(value) or value <= 0:
            raise ParameterError("--target", f"'{item}': value must be a positive number")
        target = Target(_SHORT[match.group(1)], percentile, value, item)
        if any((t.metric, t.percentile) == (target.metric, target.percentile)
               for t in targets):
            raise ParameterError("--target", f"'{item}': {item.split('=')[0]} is given twice")
        targets.append(target)
    if not any(t.metric != BINDING for t in targets):
        raise ParameterError("--target", "needs at least one percentile target, e.g. "
                             "ate_p95=0.5")
    return targets


_COST_KEYS = ("weight", "exponent", "tightest", "loosest")


def _default_bounds(name: str, reference: float) -> tuple[float, float]:
    """(tightest, loosest) of an error its [cost] table does not bound: a quarter of and four
    times the study's tolerance (within the feature's largest)."""
    return 0.25 * reference, min(4.0 * reference, largest_tolerance(name))


def cost_table(study: ToleranceStudy, table: dict | None = None) -> dict:
    """The study file's ``[cost.NAME]`` tables (or ``table``), checked: names of the study's
    toleranced errors, keys of :data:`_COST_KEYS`, positive numbers (ParameterError).  Both
    ``rvsim tolerance`` and ``rvsim allocate`` check them, so that a file one accepts the
    other does not refuse."""
    table = {n: dict(v) for n, v in study.cost} if table is None else table
    names = {t.name for t in study.tolerances}
    out = {}
    for name, spec in table.items():
        if name not in names:
            raise ParameterError(f"cost.{name}", "not a toleranced error of this study")
        if not isinstance(spec, dict) or set(spec) - set(_COST_KEYS):
            raise ParameterError(f"cost.{name}", f"a table of {', '.join(_COST_KEYS)}")
        for key, value in spec.items():
            if isinstance(value, bool) or not isinstance(value, (int, float)) \
                    or not math.isfinite(value) or value <= 0:
                raise ParameterError(f"cost.{name}.{key}", "must be a positive number")
        out[name] = {key: float(value) for key, value in spec.items()}
    # the bounds a table gives, against each other and the feature's largest tolerance, with
    # the defaults for what it leaves out
    for name, spec in out.items():
        ref = next(t.tolerance for t in study.tolerances if t.name == name)
        tightest, loosest = _default_bounds(name, ref)
        tightest, loosest = spec.get("tightest", tightest), spec.get("loosest", loosest)
        largest = largest_tolerance(name)
        if loosest > largest:
            raise ParameterError(f"cost.{name}.loosest", f"must be at most {largest:g} "
                                 f"{FEATURES[name][0]} (got {loosest:g})")
        if not tightest < loosest:
            raise ParameterError(f"cost.{name}", "tightest must be below loosest")
    return out


@dataclasses.dataclass(frozen=True)
class CostModel:
    """Per error: weight, exponent, tightest and loosest tolerance (user units)."""

    weight: dict
    exponent: dict
    tightest: dict
    loosest: dict
    reference: dict

    @classmethod
    def default(cls, study: ToleranceStudy, table: dict | None = None) -> "CostModel":
        names = [t.name for t in study.tolerances]
        ref = {t.name: t.tolerance for t in study.tolerances}
        for n in names:
            if ref[n] <= 0:
                raise ParameterError(f"tolerances.{n}.tolerance", "allocation needs a "
                                     "positive tolerance to scale")
        bounds = {n: _default_bounds(n, ref[n]) for n in names}
        out = {"weight": {n: 1.0 for n in names}, "exponent": {n: 1.0 for n in names},
               "tightest": {n: bounds[n][0] for n in names},
               "loosest": {n: bounds[n][1] for n in names}}
        # the table's values, checked by cost_table (bounds included); the defaults meet
        # those checks by construction for a positive tolerance within the feature's largest
        for name, spec in cost_table(study, table or {}).items():
            for key, value in spec.items():
                out[key][name] = value
        return cls(reference=ref, **out)

    def cost(self, tolerances: dict) -> float:
        return float(sum(self.weight[n] * (self.reference[n] / tolerances[n])
                         ** self.exponent[n] for n in tolerances))


def _evaluate(study, store, folder, samples, tolerances, targets, workers, scheduler):
    from .montecarlo import collect, monte_carlo_units, run_samples

    rounded = {k: float(f"{v:.6g}") for k, v in tolerances.items()}
    keys = run_samples(study, folder, {"allocation": (samples, lambda: monte_carlo_units(
        study, samples))}, workers=workers, scheduler=scheduler, tolerances=rounded,
        store=store)["allocation"]
    status, values, _ = collect(store, keys, {t.metric for t in targets
                                              if t.metric not in _SHARES})
    binds = int(np.sum(status == "binds"))
    share = binds / max(1, int(np.sum((status == "ok") | (status == "binds"))))
    failed = float(np.mean((status != "ok") & (status != "binds"))) if len(status) else 0.0
    achieved = {}
    for t in targets:
        if t.metric in _SHARES:
            achieved[t.text] = share if t.metric == BINDING else failed
            continue
        x = values[t.metric][np.isfinite(values[t.metric])]
        achieved[t.text] = float(np.percentile(x, t.percentile)) if x.size else math.nan
    return achieved, share, failed


def status_text(success: bool, calls: int, limit: int | None, evaluations: int) -> str:
    """The allocation's end in plain words (SciPy's COBYLA message is kept beside it as
    ``optimizer_message``): converged, or stopped at the --max-evaluations limit, or stopped
    otherwise; the tolerances reported are the cheapest that met every target."""
    done = f"{evaluations} Monte Carlo evaluations"
    if success:
        return (f"converged: the search's steps fell below its tolerance after {done}; the "
                "cheapest tolerances that met every target are reported")
    if limit is None or calls >= limit:
        given = "" if limit is None else f" {limit}"
        return (f"stopped at the evaluation limit (--max-evaluations{given}) before "
                f"converging, after {done}: the cheapest tolerances found so far that meet "
                "every target are reported; a larger --max-evaluations may loosen them further")
    return (f"stopped before converging after {done} (see optimizer_message): the cheapest "
            "tolerances found that meet every target are reported")


def allocate(study: ToleranceStudy, targets: list[Target], folder, *, samples: int = 200,
             cost: CostModel | None = None, workers: int | None = None,
             scheduler: str | None = None, max_evaluations: int = 60) -> dict:
    """The loosest tolerances (least cost) whose Monte Carlo percentiles meet ``targets``
    (module docstring).  ParameterError naming the target that cannot be met even with every
    tolerance at its tightest."""
    from pathlib import Path

    from .spec import check_samples

    check_type(study, ToleranceStudy, "study", "a tolerance study "
               "(rvsim.load_tolerance_study(path), rvsim.BUILT_IN_TOLERANCE_STUDIES[name]())")
    if isinstance(targets, str):              # the command line's form, "ate_p95=0.3"
        targets = parse_targets(targets)
    check_type(targets, (list, tuple), "targets", "a list of targets (parse_targets("
               "\"ate_p95=0.3\"), or that text)")
    for target in targets:
        check_type(target, Target, "targets", "a list of targets (parse_targets("
                   "\"ate_p95=0.3\"), or that text)")
    check_samples(samples)
    cost = cost or CostModel.default(study, {n: dict(v) for n, v in study.cost})
    if max_evaluations < len(study.tolerances) + 2:      # COBYLA's least (it would warn)
        raise ParameterError("--max-evaluations", f"must be at least "
                             f"{len(study.tolerances) + 2} for {len(study.tolerances)} "
                             f"toleranced errors (got {max_evaluations})")
    folder = Path(folder)
    if folder.exists() and not folder.is_dir():
        raise InputFileError(f"{folder}: exists and is not a folder")
    study.nominal
    if (folder / "summary.json").exists():    # its report.html would be replaced
        raise InputFileError(f"{folder}: holds a tolerance study (summary.json), whose "
                             "report.html the allocation would replace: give another --out "
                             "folder")
    created = not folder.exists()
    before = set() if created else {p.name for p in folder.iterdir()}
    folder.mkdir(parents=True, exist_ok=True)
    try:
        return _allocate(study, targets, folder, samples, cost, workers, scheduler,
                         max_evaluations)
    except (ParameterError, InputFileError):
        # bad input (an impossible target) leaves no partial folder, and in a folder that
        # was there before, nothing it did not hold
        if created:
            shutil.rmtree(folder, ignore_errors=True)
        else:
            for path in folder.iterdir():
                if path.name not in before:
                    if path.is_dir():
                        shutil.rmtree(path, ignore_errors=True)
                    else:
                        path.unlink(missing_ok=True)
        raise


def _allocate(study, targets, folder, samples, cost, workers, scheduler, max_evaluations):
    from scipy.optimize import minimize

    from ..doe.folder import check_same_study, lock_folder
    from ..doe.store import ResultStore

    names = [t.name for t in study.tolerances]
    low = np.log([cost.tightest[n] for n in names])
    high = np.log([cost.loosest[n] for n in names])
    history = []
    with lock_folder(folder):
        store = ResultStore(folder)
        try:
            check_same_study(folder, study.definition(), bool(store.finished()))
            import json

            from .._files import atomic_write_text

            atomic_write_text(folder / "study.json", json.dumps(study.definition(), indent=2,
                                                                default=str))

            def run(x):
                tol = dict(zip(names, np.exp(np.clip(x, low, high))))
                achieved, share, failed = _evaluate(study, store, folder, samples, tol,
                                                    targets, workers, scheduler)
                history.append({"tolerances": tol, "achieved": achieved,
                                "binding_share": share, "failed_share": failed,
                                "cost": cost.cost(tol)})
                return achieved

            given_x = np.log([cost.reference[n] for n in names])
            start = np.clip(given_x, low, high)
            run(start)                  # the tolerances as given (within their cost bounds)
            notes = [f"{n}: given {cost.reference[n]:g} {t.unit}, outside its cost bounds "
                     f"({cost.tightest[n]:g} .. {cost.loosest[n]:g}): the search starts at "
                     f"{math.exp(x):g}" for n, t, x, g in zip(names, study.tolerances, start,
                                                             given_x) if x != g]
            label = "at the start" if notes else "as given"
            added = []
            if not any(t.metric == BINDING for t in targets):
                # no more scrap than the tolerances as given
                given = history[-1]["binding_share"]
                added.append(Target(BINDING, math.nan, given,
                                    f"{BINDING}<={given:.4g} ({label})"))
            given = history[-1]["failed_share"]
            added.append(Target(FAILED, math.nan, given, f"{FAILED}<={given:.4g} ({label})"))
            targets = [*targets, *added]
            for t in added:
                history[-1]["achieved"][t.text] = history[-1][t.metric]
            tight = run(low)
            for t in sorted(targets, key=lambda t: t.metric not in _SHARES):
                if not t.margin(tight[t.text]) >= 0:
                    if t.metric == BINDING:
                        there = f"there the binding share is {tight[t.text]:.4g}"
                    elif t.metric == FAILED:
                        there = (f"there {tight[t.text]:.4g} of the reducers cannot be "
                                 "evaluated")
                    elif math.isnan(tight[t.text]):
                        there = "there no reducer assembles and solves"
                    else:
                        there = f"there p{t.percentile:g} = {tight[t.text]:.4g}"
                    raise ParameterError("--target", f"{t.text} cannot be met even at the "
                                         f"tightest tolerances ({there})")
            cache = {tuple(np.round(start, 9)): history[0]["achieved"]}   # evaluated already

            def achieved_at(x):
                key = tuple(np.round(x, 9))
                if key not in cache:
                    cache[key] = run(x)
                return cache[key]

            def objective(x):
                return cost.cost(dict(zip(names, np.exp(np.clip(x, low, high)))))

            # the optimiser works to targets 1 % tighter: COBYLA ends on the constraint's
            # boundary, approached from either side; the result must meet the real target
            # (the binding share moves in steps of 1 / samples: no margin)
            constraints = [{"type": "ineq",
                            "fun": (lambda x, t=t: t.margin(achieved_at(x)[t.text])
                                    - (0.0 if t.metric in _SHARES else MARGIN))}
                           for t in targets]
            constraints += [{"type": "ineq", "fun": (lambda x, i=i: x[i] - low[i])}
                            for i in range(len(names))]
            constraints += [{"type": "ineq", "fun": (lambda x, i=i: high[i] - x[i])}
                            for i in range(len(names))]
            result = minimize(objective, start, method="COBYLA", constraints=constraints,
                              options={"maxiter": max_evaluations, "rhobeg": 0.5,
                                       "catol": 1e-4})
            feasible = [h for h in history if all(
                t.margin(h["achieved"][t.text]) >= 0.0 for t in targets)]
            best = min(feasible, key=lambda h: h["cost"])
        finally:
            store.close()
    return {
        "study": study.name, "samples": samples, "evaluations": len(history),
        "status": "ok" if result.success else "stopped",
        "status_text": status_text(result.success, int(result.nfev), max_evaluations,
                                   len(history)),
        "optimizer_message": str(result.message),
        # the cost of the tolerances as given, not of the start moved into the cost bounds
        "cost": best["cost"], "cost_start": cost.cost(dict(cost.reference)),
        "notes": notes,
        "binding_share": best["binding_share"],
        "failed_share": best["failed_share"],
        "tolerances": [{"name": n, "unit": t.unit, "given": t.tolerance,
                        "allocated": float(best["tolerances"][n]),
                        "tightest": cost.tightest[n], "loosest": cost.loosest[n],
                        "weight": cost.weight[n], "exponent": cost.exponent[n]}
                       for n, t in zip(names, study.tolerances)],
        "targets": [{"target": t.text, "metric": t.metric,
                     "percentile": None if t.metric in _SHARES else t.percentile,
                     "limit": t.value, "achieved": best["achieved"][t.text],
                     "at_tightest": tight[t.text]} for t in targets],
        "history": history,
    }
