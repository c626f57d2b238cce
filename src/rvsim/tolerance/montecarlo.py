"""Monte Carlo of a tolerance study on the study runner's store and workers.

:func:`run_samples` evaluates a list of designs (label -> vectors of uniform numbers) in
chunks: each chunk is realised, its samples that the store does not hold are sent to the
study runner's local worker pool or to a Dask scheduler (``rvsim.doe.runner``), and each
outcome is stored as it arrives (resumable; memory bounded by the chunk, whatever N).
:func:`summarise` turns the stored outcomes into the statistics of summary.json.
"""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import Callable, Iterable

import numpy as np

from .._files import atomic_write, atomic_write_text
from ..errors import InputFileError
from .engine import BINDS, METRICS
from .spec import ToleranceStudy

__all__ = ["run_samples", "monte_carlo_units", "summarise", "CHUNK", "collect", "failures",
           "failure_line", "first_line", "share_text",
           "study_torque", "torque_text"]

#: samples realised and dispatched at a time
CHUNK = 2000


def monte_carlo_units(study: ToleranceStudy, samples: int) -> Iterable[np.ndarray]:
    """The uniform vectors of Monte Carlo samples 0 .. samples - 1."""
    for index in range(samples):
        yield study.unit_sample(index)


def _chunks(units: Iterable[np.ndarray], size: int):
    batch = []
    for u in units:
        batch.append(u)
        if len(batch) == size:
            yield batch
            batch = []
    if batch:
        yield batch


def run_samples(study: ToleranceStudy, folder: Path, designs: dict[str, tuple[int, Callable]],
                *, workers: int | None = None, scheduler: str | None = None,
                progress: bool = False, tolerances: dict | None = None,
                store=None) -> dict[str, list[str]]:
    """Evaluate every design into the store of ``folder`` (locked by the caller, or opened
    here); ``designs``: label -> (count, function returning the iterable of unit vectors).
    Returns the store keys of each design's samples, in order."""
    from ..doe.runner import run_dask, run_local
    from ..doe.store import ResultStore
    from ..dynamics import DEFAULT_TIME_STEP
    from .engine import evaluate_run, evaluate_sample

    own = store is None
    store = store or ResultStore(folder)
    # the evaluator itself, not its name: a worker (forked, spawned or on a Dask cluster)
    # unpickles it by reference and so imports rvsim.tolerance.engine
    options = (DEFAULT_TIME_STEP, evaluate_run, False, study.positions)
    nominal = study.nominal
    keys: dict[str, list[str]] = {}
    total = sum(count for count, _ in designs.values())
    from tqdm import tqdm

    bar = tqdm(total=total, unit="reducer", disable=not progress, desc="tolerance",
               dynamic_ncols=True)
    try:
        with bar:
            for label, (count, units) in designs.items():
                keys[label] = []
                index = 0
                for batch in _chunks(units(), CHUNK):
                    batch_keys = [study.sample_key(label, index + k, tolerances)
                                  for k in range(len(batch))]
                    index += len(batch)
                    keys[label].extend(batch_keys)
                    done = store.get_many(batch_keys)
                    bar.update(len(done))
                    todo = {key: study.realise(u, tolerances, nominal)
                            for key, u in zip(batch_keys, batch) if key not in done}
                    if not todo:
                        continue

                    def store_result(key: str, outcome: dict) -> None:
                        store.put(key, outcome)
                        bar.update(1)

                    if scheduler:
                        run_dask(todo, options, scheduler, store_result)
                    elif workers == 1:        # in this process: no worker start-up
                        for key, reducer in todo.items():
                            store_result(key, evaluate_sample(reducer, study.positions))
                    else:
                        run_local(todo, options, workers, store_result)
    finally:
        if own:
            store.close()
    return keys


def collect(store, keys: list[str], metrics: Iterable[str] = tuple(METRICS)):
    """(status array, {metric: array}, error array) of the samples ``keys``: metrics NaN
    where not ok; the error is the first line of a sample's reason (None where ok)."""
    names = list(metrics)
    status = np.empty(len(keys), dtype=object)
    errors = np.full(len(keys), None, dtype=object)
    values = {m: np.full(len(keys), np.nan) for m in names}
    for start in range(0, len(keys), CHUNK):
        part = keys[start:start + CHUNK]
        rows = store.get_many(part)
        for k, key in enumerate(part, start=start):
            row = rows.get(key, {"status": "missing", "metrics": {},
                                 "error": "not in the store"})
            status[k] = row["status"]
            if row["status"] == "ok":
                for m in names:
                    value = row["metrics"].get(m)
                    values[m][k] = np.nan if value is None else float(value)
            else:
                errors[k] = first_line(row.get("error"))
    return status, values, errors


def first_line(error: str | None, limit: int = 300) -> str:
    """A stored reason's first line, at most ``limit`` characters ('' for none)."""
    return (error or "").strip().split("\n", 1)[0][:limit]


def _stats(x: np.ndarray) -> dict:
    x = x[np.isfinite(x)]
    if x.size == 0:
        return {"n": 0, "mean": None, "std": None, "p5": None, "p50": None, "p95": None}
    p5, p50, p95 = np.percentile(x, [5, 50, 95])
    return {"n": int(x.size), "mean": float(np.mean(x)),
            "std": float(np.std(x, ddof=1)) if x.size > 1 else 0.0,
            "p5": float(p5), "p50": float(p50), "p95": float(p95)}


def summarise(status: np.ndarray, values: dict, errors: np.ndarray | None = None) -> dict:
    """summary.json's statistics: per metric mean, std, p5, p50, p95 over the reducers that
    assemble and solve; the binding share over those that assemble or bind (None when none
    does); with ``errors``, each failure status's count and first sample and reason."""
    ok = int(np.sum(status == "ok"))
    binds = int(np.sum(status == BINDS))
    failed = int(len(status) - ok - binds)
    share = binds / (ok + binds) if ok + binds else None
    out = {"samples": int(len(status)), "ok": ok, "binds": binds, "failed": failed,
           "binding_share": share, "metrics": {}}
    for name, x in values.items():
        out["metrics"][name] = {**_stats(x), "binding_share": share,
                                "description": METRICS.get(name, ("", ""))[1]}
    if errors is not None:
        out["failures"] = failures(status, errors)
    return out


def failures(status: np.ndarray, errors: np.ndarray) -> dict:
    """status -> {count, first_sample, reason} of the samples neither ok nor binding."""
    out: dict[str, dict] = {}
    for k in np.flatnonzero((status != "ok") & (status != BINDS)):
        entry = out.setdefault(str(status[k]), {"count": 0, "first_sample": int(k),
                                                "reason": errors[k] or ""})
        entry["count"] += 1
    return out


def study_torque(study) -> dict:
    """The summary's torque: ``torque_nm``, the nominal output torque every reducer runs at,
    or, when the load torque is itself toleranced, ``torque_nm`` None and ``torque_drawn``
    (the nominal, the tolerance, its distribution and the range drawn from, N*m)."""
    nominal = study.nominal.operating.load_torque
    for t in study.tolerances:
        if t.name == "operating.load_torque":
            low = max(nominal - t.tolerance, 0.0)      # realise() keeps a torque >= 0
            return {"torque_nm": None, "torque_drawn": {
                "nominal_nm": nominal, "tolerance_nm": t.tolerance,
                "distribution": t.distribution, "low_nm": low, "high_nm": nominal + t.tolerance}}
    return {"torque_nm": nominal}


def torque_text(summary: dict) -> str:
    """'412 N*m', or the torques drawn ('212 to 612 N*m, drawn uniform around 412 N*m')."""
    drawn = summary.get("torque_drawn")
    if not drawn:
        return f"{summary['torque_nm']:g} N*m"
    shape = {"uniform": "uniform", "normal": "normal, the tolerance at 3 sigma"}.get(
        drawn["distribution"], drawn["distribution"])
    return (f"{drawn['low_nm']:g} to {drawn['high_nm']:g} N*m (toleranced: {shape} around "
            f"{drawn['nominal_nm']:g} N*m, each reducer at its own)")


def share_text(share: float | None) -> str:
    """A binding share as text: 'n/a' when no reducer assembled or bound (None; NaN in the
    summary.json of earlier versions)."""
    return "n/a" if share is None or share != share else f"{100 * share:.2f} %"


def failure_line(summary: dict) -> str:
    """One line naming the failures of a summary and the commonest's first reason ('' if
    none failed)."""
    found = summary.get("failures") or {}
    if not found:
        return ""
    parts = ", ".join(f"{v['count']} {k}" for k, v in
                      sorted(found.items(), key=lambda kv: -kv[1]["count"]))
    status, top = max(found.items(), key=lambda kv: kv[1]["count"])
    reason = f": {top['reason']}" if top["reason"] else ""
    return f"{parts} (sample {top['first_sample']}, {status}{reason})"


def write_results_csv(path: Path, status: np.ndarray, values: dict, keys: list[str],
                      errors: np.ndarray | None = None) -> None:
    import pandas as pd

    columns = {"sample": np.arange(len(keys)), "status": status, **values}
    if errors is not None:
        columns["error"] = errors
    frame = pd.DataFrame({**columns, "key": [k[:16] for k in keys]})
    # pandas writes the file in chunks: no string of the whole table in memory
    atomic_write(path, lambda tmp: frame.to_csv(tmp, index=False))


def write_json(path: Path, data: dict) -> None:
    from .._json import dumps

    try:
        atomic_write_text(path, dumps(data, indent=2))
    except OSError as exc:
        raise InputFileError(f"{path}: cannot write ({exc.strerror or exc})") from None


def read_json(path: Path) -> dict:
    return json.loads(Path(path).read_text())
