"""Benchmark the tolerance Monte Carlo (issue 11, item 6).

``python benchmarks/bench_tolerance.py --samples 10000`` runs the built-in ``rv40e-tolerances``
study (RV-40E, ten toleranced features, 360 positions at rated torque + the torque-reversal
test) into a fresh folder with the local workers (default one per core) and reports the wall
time, the time per reducer and the extrapolation to 10 000 reducers.

``--dask 1,2,4`` instead runs ``--samples`` reducers on a Dask LocalCluster of 1, 2 and 4
worker processes each (one thread each) and reports the speed-up against one worker.

``--seconds S`` stops the local run after S seconds (the store keeps what finished) and
reports the throughput of what finished.  ``--positions P`` overrides the study's 360
positions (a cheap run for the memory figure: ``--workers 1 --positions 12`` at two N).
Every run reports the peak resident memory of this process and of its largest worker
(``resource.getrusage``) and the CPU time.  Prints one JSON object.
"""

from __future__ import annotations

import argparse
import json
import os
import tempfile
import threading
import time

from _timing import machine


def _local(samples: int, workers: int | None, seconds: float | None,
           positions: int | None = None) -> dict:
    import dataclasses
    import signal

    from rvsim.doe.store import ResultStore
    from rvsim.tolerance import rv40e_tolerances, tolerance_analysis

    study = rv40e_tolerances()
    if positions:
        study = dataclasses.replace(study, positions=positions)
    with tempfile.TemporaryDirectory() as folder:
        timer = None
        if seconds:
            # SIGTERM, not SIGINT: a job started in the background of a script ignores SIGINT;
            # the study runner turns SIGTERM into StudyTerminated (a KeyboardInterrupt)
            timer = threading.Timer(seconds, os.kill, (os.getpid(), signal.SIGTERM))
            timer.start()
        start = time.perf_counter()
        complete = True
        try:
            summary = tolerance_analysis(study, folder, samples=samples, workers=workers,
                                         report=False)
        except KeyboardInterrupt:
            complete, summary = False, None
        wall = time.perf_counter() - start
        if timer:
            timer.cancel()
        store = ResultStore(folder, readonly=True)
        done = len(store.finished())
        store.close()
    out = {"samples_asked": samples, "samples_done": done, "complete": complete,
           "wall_s": wall, "s_per_reducer": wall / max(done, 1),
           "extrapolated_10000_s": wall / max(done, 1) * 10000, "workers": workers or
           os.cpu_count(), "positions": study.positions}
    if summary:
        out["p95"] = {k: v["p95"] for k, v in summary["metrics"].items()}
        out["binding_share"] = summary["binding_share"]
    return out


def _dask(samples: int, sizes: list[int]) -> dict:
    import distributed

    from rvsim.tolerance import rv40e_tolerances, tolerance_analysis

    study = rv40e_tolerances()
    walls = {}
    for n in sizes:
        with distributed.LocalCluster(n_workers=n, threads_per_worker=1, processes=True,
                                      host="127.0.0.1", dashboard_address=None) as cluster:
            with tempfile.TemporaryDirectory() as warm:   # load the JIT cache in each worker
                tolerance_analysis(study, warm, samples=max(2, n), report=False,
                                   scheduler=cluster.scheduler_address)
            with tempfile.TemporaryDirectory() as folder:
                start = time.perf_counter()
                tolerance_analysis(dataclasses_replace_seed(study), folder, samples=samples,
                                   report=False, scheduler=cluster.scheduler_address)
                walls[n] = time.perf_counter() - start
    return {"samples": samples, "wall_s": walls,
            "speed_up": {n: walls[sizes[0]] / w for n, w in walls.items()}}


def dataclasses_replace_seed(study):
    import dataclasses

    return dataclasses.replace(study, seed=study.seed + 1000)   # not the warm-up's samples


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--samples", type=int, default=10000)
    parser.add_argument("--workers", type=int, default=None)
    parser.add_argument("--seconds", type=float, default=None)
    parser.add_argument("--dask", default=None, help="comma-separated worker counts")
    parser.add_argument("--positions", type=int, default=None)
    args = parser.parse_args()
    info = {"machine": machine(),
            "date": time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime()),
            "load_average_at_start": os.getloadavg()}
    if args.dask:
        info.update(_dask(args.samples, [int(x) for x in args.dask.split(",")]))
    else:
        info.update(_local(args.samples, args.workers, args.seconds, args.positions))
    info["load_average_at_end"] = os.getloadavg()
    import resource

    own = resource.getrusage(resource.RUSAGE_SELF)
    children = resource.getrusage(resource.RUSAGE_CHILDREN)
    info["max_rss_mb"] = {"this_process": own.ru_maxrss / 1024,    # Linux: kilobytes
                          "largest_worker": children.ru_maxrss / 1024}
    info["cpu_s"] = {"this_process": own.ru_utime + own.ru_stime,
                     "workers": children.ru_utime + children.ru_stime}
    print(json.dumps(info, indent=2))


if __name__ == "__main__":
    main()
