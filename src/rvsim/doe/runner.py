"""Evaluate every run of a study with the dynamic model, in parallel, resumably.

``run(study, folder)`` evaluates what the store does not hold yet, in worker processes on this
machine (default: one per core, see ``_workers``) or on a Dask cluster
(``scheduler="tcp://host:port"``), and stores each outcome as it arrives.  A run whose
simulation fails is stored with its status and error; it does not stop the study, nor does a
worker process that dies (the run is retried once, then stored as failed).  The folder is
locked while the study runs (``folder``); Ctrl-C or SIGTERM stop it at once, keeping every
finished row.
"""

from __future__ import annotations

import dataclasses
import json
import os
import signal
from contextlib import contextmanager
from pathlib import Path
from typing import Callable

import pandas as pd

from .._files import atomic_write_text
from .._stopping import stop_signals
from ..dynamics.model import EXPLICIT, SCHEMES
from ..dynamics.simulate import default_time_step
from ..errors import InputFileError, ParameterError, Terminated
from ..parameters import Reducer
from ._workers import TEST_KILL_ENV, run_workers
from .engines import EVALUATORS, compact_history
from .folder import check_not_foreign, check_same_study, held_lock_fds, lock_folder
from .store import ResultStore, run_key
from .study import Study

__all__ = ["run", "evaluate", "evaluate_task", "compact_history", "run_local", "run_dask",
           "check_scheduler", "StudyTerminated", "kernel_ready"]


def evaluate(reducer: Reducer, time_step: float, engine="dynamic",
             hysteresis: bool = False, positions: int = 360, scheme: str = "explicit") -> dict:
    """Evaluate one run; never raises (the outcome carries status and error).

    ``engine`` names an evaluator of :data:`rvsim.doe.engines.EVALUATORS` or is one (issue 31
    step 7: one protocol, no dispatch by name on packages above doe): "dynamic" (a
    simulation at ``time_step`` with the integration ``scheme``), "quasi-static"
    (:func:`rvsim.doe.engines.evaluate_quasi_static`, with the torque-reversal test when
    ``hysteresis``) and, registered by :mod:`rvsim.tolerance.engine` once it is imported,
    "tolerance" (one Monte Carlo reducer, ``positions`` per output revolution).  A
    simulation that stops (even at step 0) keeps its own status; "error" is reserved for an
    exception of the code itself.
    """
    evaluator = engine if callable(engine) else EVALUATORS.get(engine)
    if evaluator is None:        # a caller's mistake: said
        known = list(EVALUATORS)
        names = ", ".join(known[:-1]) + f" or {known[-1]}" if len(known) > 1 else known[0]
        return {"status": "error", "metrics": {},
                "error": f"ParameterError: unknown engine {engine!r} ({names})"}
    return evaluator(reducer, time_step=time_step, hysteresis=hysteresis, positions=positions,
                     scheme=scheme)


def evaluate_task(key: str, reducer, time_step: float, engine="dynamic",
                  hysteresis: bool = False, positions: int = 360,
                  scheme: str = "explicit") -> tuple[str, dict]:
    """Evaluate one run in a worker (the entry point of local and Dask workers; moved from
    ``rvsim.doe._workers``, issue 31 step 8).  Looks :func:`evaluate` up when called."""
    doomed = os.environ.get(TEST_KILL_ENV)
    if doomed and key.startswith(doomed):
        os.kill(os.getpid(), signal.SIGKILL)
    return key, evaluate(reducer, time_step, engine, hysteresis, positions, scheme)


def _progress(total: int, initial: int, enabled: bool):
    from tqdm import tqdm

    return tqdm(total=total, initial=initial, unit="run", disable=not enabled,
                desc="study", dynamic_ncols=True)


#: the study process received SIGTERM or SIGHUP (handled like Ctrl-C: finished rows kept);
#: the command line's own exception for these signals, so that one before the runs or after
#: them is the same
StudyTerminated = Terminated


def run(study: Study, folder: str | Path, *, workers: int | None = None,
        scheduler: str | None = None, progress: bool = True,
        finish: Callable[[pd.DataFrame], object] | None = None,
        prepare: Callable[[], object] | None = None) -> pd.DataFrame:
    """Evaluate ``study`` into ``folder``; return the results table (one row per run).

    The folder is locked for the study's duration; ``finish(results)``, if given, runs while it
    still is (the CLI writes the outputs and the report there); ``prepare()``, if given, runs
    in the last local runs' time, once a core is free (the CLI imports what ``finish``
    needs).  Ctrl-C, SIGTERM and SIGHUP
    stop the workers at once and keep every finished row (KeyboardInterrupt, or its subclass
    StudyTerminated, is then raised).
    """
    folder = Path(folder)
    if workers is not None and workers < 1:
        raise InputFileError(f"workers: must be at least 1 (got {workers})")
    if folder.exists() and not folder.is_dir():
        raise InputFileError(f"{folder}: exists and is not a folder")
    table = study.table()
    reducers = study.reducers()              # validates every run before any simulation
    time_step = study.time_step or default_time_step(study.scheme)
    if study.engine == "dynamic":             # run length and step, also before anything runs
        from ..dynamics.simulate import check_run_options

        for number, reducer in enumerate(reducers, start=1):
            try:
                check_run_options(reducer, time_step=time_step, scheme=study.scheme)
            except ParameterError as exc:
                raise ParameterError(exc.field, f"{exc.reason} (study run {number})") from None
    if scheduler:                            # the input's own errors first, then the cluster
        check_scheduler(scheduler)           # before anything is written
    definition = _definition(study, time_step, reducers[0])
    # the engine is part of a run's identity: a dynamic and a quasi-static result of the same
    # reducer are different rows
    if study.engine != "dynamic":
        tag = f"{study.engine}{'+hysteresis' if study.hysteresis else ''}"
    elif study.scheme == EXPLICIT:      # the keys of the studies before the schemes
        tag = time_step
    else:
        tag = f"{time_step} {study.scheme}"
    engine = study.engine
    if study.noise is not None:   # a robust study: each row's replicates in one task (issue 33)
        tag = f"{tag} noise {study.noise.digest()}"
        engine = study.noise.evaluator(study)
    keys = [run_key(r, tag) for r in reducers]
    options = (time_step, engine, study.hysteresis, 360, study.scheme)
    text = json.dumps(definition, indent=2, default=str)
    with study_folder(folder, definition, text, _other_schemes(study, reducers[0])) as (
            store, done):
        todo = to_run(keys, reducers, done)
        bar = _progress(len(set(keys)), len(set(keys)) - len(todo), progress)
        with bar:
            def store_result(key: str, outcome: dict) -> None:
                store.put(key, outcome)
                bar.update(1)

            if scheduler and todo:
                run_dask(todo, options, scheduler, store_result)
            elif todo:
                run_local(todo, options, workers, store_result, prepare)
        done = store.finished()
        store.close()                    # complete on disk before the report is written
        results = _results_table(study, table, keys, done)
        if finish is not None:
            finish(results)
    return results


#: stored status that a resumed study evaluates again
RETRIED_ON_RESUME = "worker_died"


@contextmanager
def study_folder(folder: Path, definition: dict, text: str,
                 other_schemes: dict[str, dict] | None = None):
    """``folder`` made and locked, Ctrl-C, SIGTERM and SIGHUP stopping the workers and keeping
    every finished row, its store open: yields (store, finished rows) once the stored rows are
    checked to belong to ``definition`` and ``text`` (the definition as written) is in
    study.json; the store is closed on the way out.  Shared by studies and grids."""
    check_not_foreign(folder)
    folder.mkdir(parents=True, exist_ok=True)
    with lock_folder(folder), stop_signals():
        store = ResultStore(folder)
        try:
            done = store.finished()
            check_same_study(folder, definition, bool(done), other_schemes)
            atomic_write_text(folder / "study.json", text)
            yield store, done
        finally:
            store.close()


def to_run(keys: list[str], items: list, done: dict) -> dict:
    """key -> item of the runs not stored yet, or stored by a worker that died (killed from
    outside, out of memory: a fault of the process, not a result, so a resumed study runs it
    again; docs/decisions.md)."""
    return {k: item for k, item in zip(keys, items)
            if k not in done or done[k]["status"] == RETRIED_ON_RESUME}


def run_local(todo: dict, options: tuple, workers: int | None, store_result,
               on_idle: Callable[[], None] | None = None) -> None:
    """Evaluate the runs ``todo`` (key -> reducer) in ``workers`` local processes (default:
    one per core), calling ``store_result(key, outcome)`` as each finishes.  ``options``: the
    (time_step, engine, hysteresis, positions, scheme) of :func:`evaluate`; ``on_idle``: see
    :func:`rvsim.doe._workers.run_workers`."""
    workers = min(workers or os.cpu_count() or 1, len(todo))
    # a cold cache: one worker compiles (and caches) the kernel while the others wait, instead
    # of each compiling the same kernel at once (issue 35 item 3)
    first_alone = workers > 1 and not kernel_ready(options[1])
    run_workers({key: (reducer, *options) for key, reducer in todo.items()},
                workers, store_result, held_lock_fds(), on_idle,
                task=evaluate_task, first_alone=first_alone)


def kernel_ready(engine) -> bool:
    """Whether the compiled kernel of ``engine`` is ready without compiling (in this process or
    in numba's disk cache; :func:`rvsim._cache_guard.compiled_or_cached`): the dynamic engine's
    integrator, else the quasi-static solver that the quasi-static and tolerance evaluators
    call.  Reads the cache's index only: nothing is loaded or compiled here."""
    from .._cache_guard import compiled_or_cached

    engine = getattr(engine, "kernel_engine", engine)   # a robust study's row evaluator
    if engine == "dynamic":
        from ..dynamics._kernel import integrate as entry
    else:
        from ..quasistatic._solver import sweep as entry
    return compiled_or_cached(entry)


def _scheduler_address(scheduler: str) -> tuple[str, int]:
    """(host, port) of a Dask scheduler address; InputFileError if it is not one."""
    from urllib.parse import urlsplit

    bad = InputFileError(f"--scheduler: '{scheduler}' is not a scheduler address "
                         "(e.g. tcp://host:8786)")
    parts = urlsplit(scheduler if "://" in scheduler else f"tcp://{scheduler}")
    try:
        port = parts.port
    except ValueError:
        raise bad from None
    if parts.scheme not in ("tcp", "tls") or not parts.hostname or parts.path not in ("", "/"):
        raise bad
    return parts.hostname, port or 8786


def check_scheduler(scheduler: str) -> None:
    """InputFileError unless ``scheduler`` is an address that accepts connections."""
    import socket

    try:  # fail fast with a clear message instead of the client's 20 s timeout
        socket.create_connection(_scheduler_address(scheduler), timeout=3).close()
    except (OSError, ValueError) as exc:
        raise InputFileError(f"cannot reach the Dask scheduler at {scheduler} ({exc})") from None


def run_dask(todo: dict, options: tuple, scheduler: str, store_result) -> None:
    """As :func:`run_local`, on the workers of the Dask cluster at ``scheduler``."""
    from distributed import Client, as_completed as dask_completed

    try:
        client = Client(scheduler, timeout="20s")
    except (OSError, ValueError, TypeError) as exc:
        raise InputFileError(f"cannot reach the Dask scheduler at {scheduler} ({exc})") from None
    with client:
        futures = {client.submit(evaluate_task, key, reducer, *options, key=f"rvsim-{key}",
                                 pure=False): key for key, reducer in todo.items()}
        try:
            for future in dask_completed(futures):
                store_result(*_dask_outcome(future, futures[future]))
        except BaseException:
            client.cancel(list(futures), force=True)
            raise


def _dask_outcome(future, key: str) -> tuple[str, dict]:
    """A finished future's (key, outcome); a lost worker is a failed run with the reason."""
    try:
        return future.result()
    except Exception as exc:  # noqa: BLE001 - evaluate never raises: this is the cluster
        name = type(exc).__name__
        status = "worker_died" if name == "KilledWorker" else "error"
        reason = str(exc).splitlines()[0] if str(exc) else name
        return key, {"status": status, "metrics": {},
                     "error": f"Dask {name}: {reason}"[:500]}


def _other_schemes(study: Study, first: Reducer) -> dict[str, dict]:
    """The definitions ``study`` has with each other integration scheme (its own step, or the
    other scheme's default), for the refusal of a folder that holds one of them."""
    if study.engine != "dynamic":
        return {}
    out = {}
    for scheme in SCHEMES:
        if scheme != study.scheme:
            other = dataclasses.replace(study, scheme=scheme)
            out[scheme] = _definition(other, other.time_step or default_time_step(scheme), first)
    return out


def _definition(study: Study, time_step: float, first: Reducer) -> dict:
    return {
        "name": study.name, "design": study.design, "samples": study.samples,
        "seed": study.seed, "time_step": time_step,
        "engine": study.engine, "hysteresis": study.hysteresis,
        # the scheme only where it is not the default: earlier studies' folders resume
        **({"scheme": study.scheme} if study.scheme != EXPLICIT else {}),
        "reducer": f"{study.base.name} ({study.base.citation})" if study.base.citation
        else study.base.name,
        "steady_start": first.operating.steady_start,   # fixed settings included
        # what the report's spectrum marks (orders of the crank rotation, the load fluctuation)
        "pin_count": first.cycloid.pin_count,
        "planet_teeth": first.gears.planet_teeth if first.layout.stages == 2 else None,
        "fluctuation_frequency": first.operating.fluctuation_frequency,
        "factors": [{"label": f.label, "parameter": f.parameter, "levels": list(f.levels),
                     "low": f.low, "high": f.high} for f in study.factors],
        "fixed": [[k, v] for k, v in study.fixed],
        # a robust study's noise factors (issue 33): absent for a plain study (its folders
        # resume as before)
        **({"noise": study.noise.definition()} if study.noise is not None else {}),
    }


def _results_table(study: Study, table: pd.DataFrame, keys: list[str], done: dict
                   ) -> pd.DataFrame:
    rows = []
    for (_, row), key in zip(table.iterrows(), keys):
        outcome = done.get(key, {"status": "missing", "metrics": {}})
        metrics = {k: v for k, v in outcome["metrics"].items()     # ate_note: ate_arcmin's
                   if k not in ("status", "reducer", "ate_note")}   # null says it per row
        rows.append({**row.to_dict(), **metrics, "status": outcome["status"],
                     "error": outcome.get("error") or "", "key": key[:16]})
    frame = pd.DataFrame(rows)
    frame["run"] = frame["run"].astype(int)
    return frame
