"""Evaluate every run of a study with the dynamic model, in parallel, resumably.

``run(study, folder)`` evaluates what the store does not hold yet, in worker processes on this
machine (default: one per core) or on a Dask cluster (``scheduler="tcp://host:port"``), and
stores each outcome as it arrives.  A run whose simulation fails is stored with its status and
error; it does not stop the study.
"""

from __future__ import annotations

import os
import traceback
from concurrent.futures import ProcessPoolExecutor, as_completed
from pathlib import Path

import pandas as pd

from .._files import atomic_write_text
from ..dynamics import DEFAULT_TIME_STEP
from ..errors import InputFileError
from ..parameters import Reducer
from .store import ResultStore, run_key
from .study import Study

__all__ = ["run", "evaluate", "compact_history"]


def evaluate(reducer: Reducer, time_step: float, engine: str = "dynamic",
             hysteresis: bool = False) -> dict:
    """Simulate one run; never raises (the outcome carries status and error)."""
    if engine == "quasi-static":  # issue 9: the quasi-static engine (rvsim.doe.engines)
        from .engines import evaluate_quasi_static

        return evaluate_quasi_static(reducer, hysteresis=hysteresis)
    from ..dynamics import simulate

    try:
        result = simulate(reducer, time_step=time_step, raise_on_failure=False)
        summary = result.summary()
        outcome = {"status": result.status, "metrics": summary, "wall_s": result.wall_s,
                   "history": compact_history(result)}
        if result.status != "ok":
            outcome["error"] = f"simulation {result.status.replace('_', ' ')} at step " \
                               f"{result.steps}"
        return outcome
    except Exception as exc:  # noqa: BLE001 - a failed row must not stop the study
        return {"status": "error", "error": f"{type(exc).__name__}: {exc}",
                "metrics": {}, "detail": traceback.format_exc(limit=3)}


def compact_history(result, rate: float = 1000.0) -> bytes:
    """Time, input and output speed and TE at ``rate`` Hz, as compressed .npz bytes."""
    import io

    import numpy as np

    step = max(1, int(round(1.0 / (rate * (result.time[1] - result.time[0])))))
    buffer = io.BytesIO()
    np.savez_compressed(buffer, time=result.time[::step], omega_in=result.omega_in[::step],
                        omega_out=result.omega_out[::step], te=result.te[::step],
                        ratio=np.array(result.ratio), steady_start=np.array(result.steady_start))
    return buffer.getvalue()


def _progress(total: int, initial: int, enabled: bool):
    from tqdm import tqdm

    return tqdm(total=total, initial=initial, unit="run", disable=not enabled,
                desc="study", dynamic_ncols=True)


def run(study: Study, folder: str | Path, *, workers: int | None = None,
        scheduler: str | None = None, progress: bool = True) -> pd.DataFrame:
    """Evaluate ``study`` into ``folder``; return the results table (one row per run)."""
    folder = Path(folder)
    if folder.exists() and not folder.is_dir():
        raise InputFileError(f"{folder}: exists and is not a folder")
    table = study.table()
    reducers = study.reducers()              # validates every run before any simulation
    folder.mkdir(parents=True, exist_ok=True)
    time_step = study.time_step or DEFAULT_TIME_STEP
    _write_definition(study, folder, time_step, reducers[0])
    # issue 9: the engine is part of a run's identity (a dynamic and a quasi-static result
    # of the same reducer are different rows)
    options = {"engine": study.engine, "hysteresis": study.hysteresis}
    tag = time_step if study.engine == "dynamic" else \
        f"{study.engine}{'+hysteresis' if study.hysteresis else ''}"
    keys = [run_key(r, tag) for r in reducers]
    store = ResultStore(folder)
    try:
        done = store.finished()
        todo = {k: r for k, r in zip(keys, reducers) if k not in done}
        bar = _progress(len(set(keys)), len(set(keys)) - len(todo), progress)
        with bar:
            if scheduler:
                _run_dask(todo, time_step, scheduler, store, bar, options)
            elif todo:
                _run_local(todo, time_step, workers, store, bar, options)
        done = store.finished()
    finally:
        store.close()
    return _results_table(study, table, keys, done)


def _run_local(todo: dict, time_step: float, workers: int | None, store: ResultStore,
               bar, options: dict) -> None:
    workers = workers or os.cpu_count() or 1
    if workers == 1 or len(todo) == 1:
        for key, reducer in todo.items():
            store.put(key, evaluate(reducer, time_step, **options))
            bar.update(1)
        return
    with ProcessPoolExecutor(max_workers=min(workers, len(todo))) as pool:
        futures = {pool.submit(evaluate, reducer, time_step, **options): key
                   for key, reducer in todo.items()}
        for future in as_completed(futures):
            store.put(futures[future], future.result())
            bar.update(1)


def _run_dask(todo: dict, time_step: float, scheduler: str, store: ResultStore, bar,
              options: dict) -> None:
    import socket
    from urllib.parse import urlparse

    from distributed import Client, as_completed as dask_completed

    address = urlparse(scheduler if "://" in scheduler else f"tcp://{scheduler}")
    try:  # fail fast with a clear message instead of the client's 20 s timeout
        socket.create_connection((address.hostname, address.port or 8786), timeout=3).close()
    except (OSError, ValueError) as exc:
        raise InputFileError(f"cannot reach the Dask scheduler at {scheduler} ({exc})") from None
    try:
        client = Client(scheduler, timeout="20s")
    except OSError as exc:
        raise InputFileError(f"cannot reach the Dask scheduler at {scheduler} ({exc})") from None
    with client:
        futures = {client.submit(evaluate, reducer, time_step, **options, key=f"rvsim-{key}",
                                 pure=False):
                   key for key, reducer in todo.items()}
        for future in dask_completed(futures):
            store.put(futures[future], future.result())
            bar.update(1)


def _write_definition(study: Study, folder: Path, time_step: float, first: Reducer) -> None:
    import json

    definition = {
        "name": study.name, "design": study.design, "samples": study.samples,
        "seed": study.seed, "time_step": time_step,
        "engine": study.engine, "hysteresis": study.hysteresis,  # issue 9
        "reducer": f"{study.base.name} ({study.base.citation})" if study.base.citation
        else study.base.name,
        "steady_start": first.operating.steady_start,   # fixed settings included
        "factors": [{"label": f.label, "parameter": f.parameter, "levels": list(f.levels),
                     "low": f.low, "high": f.high} for f in study.factors],
        "fixed": [[k, v] for k, v in study.fixed],
    }
    atomic_write_text(folder / "study.json", json.dumps(definition, indent=2, default=str))


def _results_table(study: Study, table: pd.DataFrame, keys: list[str], done: dict
                   ) -> pd.DataFrame:
    rows = []
    for (_, row), key in zip(table.iterrows(), keys):
        outcome = done.get(key, {"status": "missing", "metrics": {}})
        metrics = {k: v for k, v in outcome["metrics"].items()
                   if k not in ("status", "reducer")}
        rows.append({**row.to_dict(), **metrics, "status": outcome["status"],
                     "error": outcome.get("error") or "", "key": key[:16]})
    frame = pd.DataFrame(rows)
    frame["run"] = frame["run"].astype(int)
    return frame
