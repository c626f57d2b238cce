"""Robust design (Taguchi's inner and outer arrays): a study whose every run is built
``samples`` times with drawn part errors (issue 33 item 2).

A study file's ``[noise]`` section is in the tolerance-file format (:mod:`.spec`)::

    [noise]
    samples = 20               # replicates of every run (2 .. MAX_REPLICATES)
    seed = 1                   # the draws are reproducible from it
    positions = 360            # optional, quasi-static engine: input positions per output
                               # revolution (default 360, a plain study's)
    [noise.tolerances.pin_radius]
    tolerance = 0.002          # mm, as in a tolerance file
    distribution = "normal"

Replicate k of every run draws its uniform numbers from ``numpy.random.default_rng([seed,
k])``: every run meets the same noise conditions (Taguchi's crossed arrays: the outer array
is the same for every row of the inner one; docs/decisions.md), so a resumed or parallel
study gives identical rows.  Each drawn reducer is checked for assembly (a binding one is
counted, not evaluated, as in a tolerance study) and evaluated by the study's own engine;
the row holds per metric the replicates' mean, std, p5/p50/p95 and the S/N ratios
(:mod:`rvsim.analysis.signal_noise`).  The replicates of one row run in one task, so the
study runner's store, resume, local workers and Dask work unchanged.
"""

from __future__ import annotations

import dataclasses
import functools
import hashlib
import json
from pathlib import Path

import numpy as np

from ..errors import InputFileError, ParameterError
from .spec import FEATURES, ToleranceStudy

__all__ = ["Noise", "MAX_REPLICATES", "read_noise", "with_noise", "load_robust_study",
           "evaluate_replicates", "paper_l36_robust", "BUILT_IN_ROBUST_STUDIES",
           "is_robust_file", "summarised_metrics"]

#: most replicates of one run: a row's replicates run in one task that stores nothing until
#: all are done (10 000 quasi-static replicates are about half an hour of one worker, lost if
#: it is stopped); their metrics in memory are under 1 MB
MAX_REPLICATES = 10_000
#: most evaluations (runs x replicates) of one robust study: the tolerance Monte Carlo's bound
#: (spec.MAX_SAMPLES)
MAX_EVALUATIONS = 1_000_000
#: keys of the [noise] section (the tolerance-file keys that make sense for noise factors)
_KEYS = {"samples", "seed", "positions", "tolerances"}
#: a tolerance file's keys that the study itself sets
_STUDY_KEYS = {"params": "the study's 'params' sets the reducer",
               "set": "the study's [set] sets the nominal values",
               "name": "the study's 'name' names it",
               "cost": "no allocation in a study", "profile_csv": "no measured profiles in a "
               "study's noise"}
#: metric columns that are bookkeeping, not responses: no statistics of them
_BOOKKEEPING = {"positions", "torque_nm", "wall_s", "te_window_revolutions", "sim_time_s",
                "steps", "points", "energy_residual", "speed_ratio", "guard_substep_checks",
                "guard_substep_checks_steady", "guard_peak_omega_dt", "implicit_factorisations",
                "implicit_alerts", "implicit_fallbacks"}


@dataclasses.dataclass(frozen=True)
class Noise:
    """The noise factors of a robust study: the toleranced errors (a :class:`ToleranceStudy`
    on the study's base reducer, whose samples, seed and positions are the replicates',
    the draws' and the quasi-static runs')."""

    spec: ToleranceStudy

    @property
    def samples(self) -> int:
        return self.spec.samples

    def unit(self, replicate: int) -> np.ndarray:
        """Replicate ``replicate``'s uniform numbers (the same for every run)."""
        return self.spec.unit_sample(replicate)

    def definition(self) -> dict:
        """What identifies the replicates (study.json; the run keys hash it with the code
        that draws and summarises them)."""
        out = self.spec.definition()
        out.pop("name"), out.pop("params"), out.pop("fixed"), out.pop("profile_points")
        out["kind"] = "noise"
        out["samples"] = self.samples
        return out

    def digest(self) -> str:
        code = "".join(Path(__file__).with_name(n).read_text(encoding="utf-8")
                       for n in ("robust.py", "spec.py"))
        payload = json.dumps({"noise": self.definition(), "code": code}, sort_keys=True,
                             default=str)
        return hashlib.sha256(payload.encode()).hexdigest()[:32]

    def evaluator(self, study):
        """The study runner's evaluator of one row (picklable: a worker or a Dask cluster
        unpickles it by reference)."""
        evaluator = functools.partial(evaluate_replicates, noise=self, engine=study.engine,
                                      metrics=summarised_metrics(study))
        evaluator.kernel_engine = study.engine     # the runner's compile-first check
        return evaluator

    def columns(self, study) -> tuple[str, ...]:
        """The numeric columns of the study's rows (``--response`` names one of them)."""
        from ..analysis.signal_noise import robust_columns

        return robust_columns(summarised_metrics(study)) + _COUNT_COLUMNS


#: the replicate counts of every row
_COUNT_COLUMNS = ("replicates", "replicates_ok", "replicates_binding")


def summarised_metrics(study) -> tuple[str, ...]:
    """The metrics of ``study``'s engine that a robust row summarises."""
    from ..doe.engines import metric_columns

    return tuple(m for m in metric_columns(study.engine, study.hysteresis)
                 if m not in _BOOKKEEPING)


def _row_metrics(values: dict[str, list], counts: dict) -> dict:
    from ..analysis.signal_noise import KINDS, sense, signal_to_noise
    from .montecarlo import _stats

    out = dict(counts)
    for m, raw in values.items():
        x = np.asarray(raw, dtype=float)
        stats = _stats(x)
        for name in ("mean", "std", "p5", "p50", "p95"):
            out[f"{m}_{name}"] = stats[name]
        x = x[np.isfinite(x)]
        ratios = {k: signal_to_noise(x, k) if x.size else None for k in KINDS}
        out.update({f"{m}_sn_{k}": v for k, v in ratios.items()})
        out[f"{m}_sn"] = ratios[sense(m)]
    return out


def evaluate_replicates(reducer, *, noise: Noise, engine: str, metrics: tuple, time_step,
                        hysteresis: bool = False, scheme: str = "explicit", **_) -> dict:
    """One row of a robust study: ``noise.samples`` reducers drawn around ``reducer``, each
    checked for assembly and evaluated by the ``engine`` of the study; never raises.  The row
    is "ok" when at least 2 replicates assemble and none fails; a failed replicate fails the
    row with its status and reason (its statistics would hide it)."""
    from .._cache_guard import RunClock
    from ..doe.engines import EVALUATORS
    from ..errors import ParameterError as Invalid
    from .engine import BINDS, assembly_binds

    clock = RunClock()      # the row without numba compiling (a cold cache)
    values: dict[str, list] = {m: [] for m in metrics}
    binding, first_binding = 0, ""
    n = noise.samples
    for k in range(n):
        try:
            drawn = noise.spec.realise(noise.unit(k), nominal=reducer)
            why = assembly_binds(drawn)
        except Invalid as exc:
            return _failed("invalid", f"replicate {k}: {exc}", k, binding, clock)
        except Exception as exc:  # noqa: BLE001 - a failed row must not stop the study
            return _failed("error", f"replicate {k}: {type(exc).__name__}: {exc}", k, binding,
                           clock)
        if why:
            binding += 1
            first_binding = first_binding or f"replicate {k}: {why}"
            continue
        out = EVALUATORS[engine](drawn, time_step=time_step, hysteresis=hysteresis,
                                 positions=noise.spec.positions, scheme=scheme)
        if out["status"] != "ok":
            return _failed(out["status"], f"replicate {k}: {out.get('error') or out['status']}",
                           k, binding, clock)
        for m in metrics:
            value = out["metrics"].get(m)
            values[m].append(np.nan if value is None else float(value))
    ok = n - binding
    counts = {"replicates": n, "replicates_ok": ok, "replicates_binding": binding}
    wall = clock.split()[0]
    if ok < 2:
        return {"status": BINDS, "metrics": counts, "wall_s": wall,
                "error": f"{binding} of {n} replicates bind on assembly, fewer than 2 remain "
                         f"({first_binding})"}
    return {"status": "ok", "metrics": _row_metrics(values, counts), "wall_s": wall}


def _failed(status: str, error: str, k: int, binding: int, clock) -> dict:
    return {"status": status, "error": error, "wall_s": clock.split()[0],
            "metrics": {"replicates": k + 1, "replicates_binding": binding}}


def read_noise(raw, study) -> Noise:
    """The noise factors of a study file's ``[noise]`` table for ``study`` (checked: every
    error names its key under ``noise.``)."""
    from .spec import _tolerance

    if not isinstance(raw, dict):
        raise ParameterError("noise", "must be a table ([noise] with samples, seed and "
                             "[noise.tolerances.NAME] tables)")
    for key in raw:
        if key in _STUDY_KEYS:
            raise ParameterError(f"noise.{key}", f"not in a [noise] section "
                                 f"({_STUDY_KEYS[key]})")
    unknown = set(raw) - _KEYS
    if unknown:
        raise ParameterError("noise", f"unknown key(s) {', '.join(sorted(unknown))} (known: "
                             f"{', '.join(sorted(_KEYS))})")
    tolerances = raw.get("tolerances")
    if not isinstance(tolerances, dict) or not tolerances:
        raise ParameterError("noise.tolerances", "needs at least one [noise.tolerances.NAME] "
                             f"table (per-part errors: {', '.join(FEATURES)}; or a numeric "
                             "parameter)")
    try:
        parsed = tuple(_tolerance(name, spec, None) for name, spec in tolerances.items())
    except ParameterError as exc:
        raise ParameterError(f"noise.{exc.field}", exc.reason) from None
    if "samples" not in raw:
        raise ParameterError("noise.samples", "missing (the replicates of every run, e.g. 20)")
    if "positions" in raw and study.engine != "quasi-static":
        raise ParameterError("noise.positions", f"the study runs the {study.engine} engine, "
                             "whose runs have no positions (the quasi-static engine's)")
    return with_noise(study, parsed, raw["samples"], raw.get("seed", 0),
                      raw.get("positions", 360))


def with_noise(study, tolerances, samples: int, seed: int = 0, positions: int = 360):
    """``study`` with the noise factors ``tolerances`` (:class:`~.spec.Tolerance`), each run
    replicated ``samples`` times; checked (errors name ``noise.*``)."""
    _check_samples(samples, len(study.table()))
    if isinstance(seed, bool) or not isinstance(seed, int) or seed < 0:
        raise ParameterError("noise.seed", f"must be a whole number >= 0 (got {seed!r})")
    by_parameter = {f.parameter: f.label for f in study.factors}
    for t in tolerances:
        if t.name in by_parameter:
            raise ParameterError(f"noise.tolerances.{t.name}", f"is the parameter of control "
                                 f"factor {by_parameter[t.name]}: a factor is set by the "
                                 "design, not drawn (remove one of them)")
    try:
        spec = ToleranceStudy(name=f"{study.name} noise", tolerances=tuple(tolerances),
                              base=study.base, samples=samples, seed=seed,
                              positions=positions)
    except ParameterError as exc:
        raise ParameterError(f"noise.{exc.field}", exc.reason) from None
    noise = Noise(spec)
    counts = spec.part_counts()
    for number, reducer in enumerate(study.reducers(), start=1):
        if dataclasses.replace(spec, base=reducer).part_counts() != counts:
            raise ParameterError("noise", f"study run {number} has other part counts than the "
                                 "base reducer (a factor changes the pin count, the discs or "
                                 "the cranks): its parts cannot be drawn alike")
    return dataclasses.replace(study, noise=noise)


def _check_samples(samples, runs: int) -> None:
    if isinstance(samples, bool) or not isinstance(samples, int) \
            or not 2 <= samples <= MAX_REPLICATES:
        raise ParameterError("noise.samples", f"must be a whole number from 2 to "
                             f"{MAX_REPLICATES} replicates per run (got {samples!r})")
    if samples * runs > MAX_EVALUATIONS:
        raise ParameterError("noise.samples", f"{runs} runs x {samples} replicates = "
                             f"{samples * runs} evaluations, more than the {MAX_EVALUATIONS} "
                             "a study may have")


def is_robust_file(path) -> bool:
    """Whether a TOML study file has a [noise] table (False if it cannot be read)."""
    from .._files import read_toml
    from ..errors import RvsimError

    try:
        return "noise" in read_toml(path)
    except RvsimError:
        return False


def load_robust_study(path):
    """Read a study file with a [noise] section (module docstring; the rest as
    :func:`rvsim.doe.load_study`)."""
    from .._files import read_study_toml
    from ..doe.study import study_from_data

    path = Path(path)
    data = read_study_toml(path)
    if "noise" not in data:
        raise InputFileError(f"{path}: has no [noise] section")
    raw = data.pop("noise")
    study = study_from_data(data, path)
    return read_noise(raw, study)


def paper_l36_robust():
    """The paper's L36 (Table 2 factors, built-in ``paper-l36``) on the quasi-static engine,
    each run built 20 times with the per-part errors of the built-in tolerance study
    ``rv40e-tolerances`` (docs/tolerances.md; its clearance tolerances are left out: the
    crank - arm bushing clearance is the paper's factor K); response the ATE."""
    from ..doe.study import paper_l36
    from .spec import rv40e_tolerances

    base = dataclasses.replace(paper_l36(), name="paper-l36-robust", engine="quasi-static",
                               scheme="explicit")
    parts = tuple(t for t in rv40e_tolerances().tolerances if t.name in FEATURES)
    return with_noise(base, parts, samples=20, seed=1)


BUILT_IN_ROBUST_STUDIES = {"paper-l36-robust": paper_l36_robust}
