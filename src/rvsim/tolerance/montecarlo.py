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

__all__ = ["run_samples", "monte_carlo_units", "summarise", "CHUNK", "collect"]

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
    from ..doe.runner import _run_dask, _run_local
    from ..doe.store import ResultStore
    from ..dynamics import DEFAULT_TIME_STEP

    own = store is None
    store = store or ResultStore(folder)
    options = (DEFAULT_TIME_STEP, "tolerance", False, study.positions)
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
                        _run_dask(todo, options, scheduler, store_result)
                    elif workers == 1:        # in this process: no worker start-up
                        from .engine import evaluate_sample

                        for key, reducer in todo.items():
                            store_result(key, evaluate_sample(reducer, study.positions))
                    else:
                        _run_local(todo, options, workers, store_result)
    finally:
        if own:
            store.close()
    return keys


def collect(store, keys: list[str], metrics: Iterable[str] = tuple(METRICS)):
    """(status array, {metric: array}) of the samples ``keys`` (NaN where not ok)."""
    names = list(metrics)
    status = np.empty(len(keys), dtype=object)
    values = {m: np.full(len(keys), np.nan) for m in names}
    for start in range(0, len(keys), CHUNK):
        part = keys[start:start + CHUNK]
        rows = store.get_many(part)
        for k, key in enumerate(part, start=start):
            row = rows.get(key, {"status": "missing", "metrics": {}})
            status[k] = row["status"]
            if row["status"] == "ok":
                for m in names:
                    value = row["metrics"].get(m)
                    values[m][k] = np.nan if value is None else float(value)
    return status, values


def _stats(x: np.ndarray) -> dict:
    x = x[np.isfinite(x)]
    if x.size == 0:
        return {"n": 0, "mean": None, "std": None, "p5": None, "p50": None, "p95": None}
    p5, p50, p95 = np.percentile(x, [5, 50, 95])
    return {"n": int(x.size), "mean": float(np.mean(x)),
            "std": float(np.std(x, ddof=1)) if x.size > 1 else 0.0,
            "p5": float(p5), "p50": float(p50), "p95": float(p95)}


def summarise(status: np.ndarray, values: dict) -> dict:
    """summary.json's statistics: per metric mean, std, p5, p50, p95 over the reducers that
    assemble and solve; the binding share over those that assemble or bind."""
    ok = int(np.sum(status == "ok"))
    binds = int(np.sum(status == BINDS))
    failed = int(len(status) - ok - binds)
    share = binds / (ok + binds) if ok + binds else math.nan
    out = {"samples": int(len(status)), "ok": ok, "binds": binds, "failed": failed,
           "binding_share": share, "metrics": {}}
    for name, x in values.items():
        out["metrics"][name] = {**_stats(x), "binding_share": share,
                                "description": METRICS.get(name, ("", ""))[1]}
    return out


def write_results_csv(path: Path, status: np.ndarray, values: dict, keys: list[str]) -> None:
    import pandas as pd

    frame = pd.DataFrame({"sample": np.arange(len(keys)), "status": status, **values,
                          "key": [k[:16] for k in keys]})
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
