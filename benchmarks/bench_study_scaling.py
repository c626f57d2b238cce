"""Scaling of the study runner (issue 14, item 3): speed-up with workers, memory of 1,000 runs.

``--local 1,2``: the paper's L36 rows on a 0.5 s schedule (every element and factor as in the
paper, ramps shortened: about 0.1-0.2 s of simulation CPU per run), with 1 and 2 local worker
processes; ``--dask 1,2,4``: the same on a Dask LocalCluster of 1, 2, 4 worker processes (one
thread each, the JIT cache loaded in every worker first).  Each configuration runs
``--repeat`` studies into fresh folders; the JSON gives the median wall time, the speed-up
against the first configuration, the CPU time of every process involved and the load average
before and after each study (the machine is shared: a wall time is only as good as its load).

``--memory N``: one study of N runs (a Latin hypercube over the paper's numeric factors E-O,
0.05 s runs: the runner's bookkeeping, not the simulation, is what is measured) with
``--workers`` local workers, sampling the resident memory of the parent and of each worker
(/proc VmRSS) as the store fills; the JSON gives the samples at 100, 500, ... N runs.

Usage:  python benchmarks/bench_study_scaling.py --local 1,2 --dask 1,2,4 --repeat 3
        python benchmarks/bench_study_scaling.py --memory 1000 --workers 2
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import os
import sqlite3
import statistics
import tempfile
import threading
import time

from _timing import machine, one_thread

one_thread()

from bench_study import SHORT_SCHEDULE  # noqa: E402

#: the paper's schedule compressed to 0.5 s: speed ramp, load step, then a steady window
HALF_SECOND = (("operating.duration", 0.5), ("operating.speed_ramp_time", 0.1),
               ("operating.load_start", 0.1), ("operating.load_ramp_end", 0.2),
               ("operating.steady_start", 0.25))


def _load() -> float:
    return round(os.getloadavg()[0], 2)


def _warm() -> None:
    """Load the compiled kernel and the runner's modules in this process (a Dask worker:
    before it is timed; its first task would otherwise import them, about 1 s)."""
    import importlib

    from rvsim.dynamics import simulate
    from rvsim.parameters import RV40E, with_values

    importlib.import_module("rvsim.doe.runner")
    simulate(with_values(RV40E, dict(SHORT_SCHEDULE)))


def _cpu_self() -> float:
    times = os.times()
    return times.user + times.system


def _studies(run_one, repeat: int, workers: int, cpu_of_workers=None) -> dict:
    """``repeat`` studies by ``run_one(folder)``: walls, CPU (this process and its reaped
    children, or ``cpu_of_workers()`` for a cluster), load before and after each, and the
    share of the ``workers``' time spent inside ``simulate`` (the rest: start, dispatch,
    store, result compaction, and workers idle at the tail of the study)."""
    walls, cpus, loads, shares = [], [], [], []
    for _ in range(repeat):
        with tempfile.TemporaryDirectory() as folder:
            load_before = _load()
            before = os.times()
            workers_before = cpu_of_workers() if cpu_of_workers else 0.0
            start = time.perf_counter()
            results = run_one(folder)
            walls.append(time.perf_counter() - start)
            after = os.times()
            cluster_cpu = cpu_of_workers() - workers_before if cpu_of_workers else 0.0
            cpus.append(sum(after[:4]) - sum(before[:4]) + cluster_cpu)
            loads.append([load_before, _load()])
            assert (results["status"] == "ok").all(), results["status"].value_counts()
            shares.append(round(results["wall_s"].sum() / (walls[-1] * workers), 2))
    return {"median_wall_s": round(statistics.median(walls), 2),
            "walls_s": [round(w, 2) for w in walls], "cpu_s": [round(c, 1) for c in cpus],
            "load_1min_before_after": loads, "solver_share_of_worker_time": shares}


def _speed_ups(table: dict) -> None:
    first = next(iter(table.values()))["median_wall_s"]
    for entry in table.values():
        entry["speed_up"] = round(first / entry["median_wall_s"], 2)


def _half_second_l36():
    from rvsim.doe import paper_l36

    study = paper_l36()
    # the runner's scaling as recorded since 2026-11-25: the explicit scheme
    study = dataclasses.replace(study, scheme="explicit")
    return dataclasses.replace(study, fixed=study.fixed + HALF_SECOND)


def local_scaling(sizes: list[int], repeat: int) -> dict:
    from rvsim.doe import run

    study = _half_second_l36()
    table = {}
    for n in sizes:
        table[n] = _studies(lambda folder: run(study, folder, workers=n, progress=False),
                            repeat, n)
    _speed_ups(table)
    return table


def dask_scaling(sizes: list[int], repeat: int) -> dict:
    import distributed

    from rvsim.doe import run

    study = _half_second_l36()
    table = {}
    for n in sizes:
        with distributed.LocalCluster(n_workers=n, threads_per_worker=1, processes=True,
                                      host="127.0.0.1", dashboard_address=None) as cluster, \
                distributed.Client(cluster) as client:
            client.run(_warm)

            def cpu_of_workers() -> float:
                return sum(client.run(_cpu_self).values())

            table[n] = _studies(lambda folder: run(study, folder, progress=False,
                                                   scheduler=cluster.scheduler_address),
                                repeat, n, cpu_of_workers)
    _speed_ups(table)
    return table


def _rss_mb(pid: int | str = "self") -> float:
    """Resident memory of a process (MB), from /proc (0 once it has ended)."""
    try:
        with open(f"/proc/{pid}/status") as status:
            for line in status:
                if line.startswith("VmRSS:"):
                    return int(line.split()[1]) / 1024
    except OSError:
        pass
    return 0.0


def memory(runs: int, workers: int) -> dict:
    import multiprocessing

    from rvsim.doe import run
    from rvsim.doe.study import Study, StudyFactor
    from rvsim.parameters import TABLE2_FACTORS

    factors = tuple(StudyFactor(label, spec.parameter, low=min(spec.levels),
                                high=max(spec.levels))
                    for label, spec in TABLE2_FACTORS.items()
                    if not isinstance(spec.levels[0], bool))
    study = Study(name=f"memory-{runs}", factors=factors, design="lhs", samples=runs,
                  fixed=SHORT_SCHEDULE)
    samples: list[dict] = []
    stop = threading.Event()

    def sample(database: str) -> None:
        reader = None
        while not stop.wait(0.25):
            if reader is None:
                if not os.path.exists(database):
                    continue
                reader = sqlite3.connect(database, timeout=5)
            try:
                done = reader.execute("SELECT count(*) FROM runs").fetchone()[0]
            except sqlite3.Error:
                continue
            children = multiprocessing.active_children()
            samples.append({"runs_stored": done, "t_s": round(time.perf_counter() - start, 1),
                            "parent_rss_mb": round(_rss_mb(), 1),
                            "worker_rss_mb": [round(_rss_mb(c.pid), 1) for c in children],
                            "load_1min": _load()})
        if reader is not None:
            reader.close()

    with tempfile.TemporaryDirectory() as folder:
        rss_before = _rss_mb()
        start = time.perf_counter()
        sampler = threading.Thread(target=sample, args=(os.path.join(folder, "results.sqlite"),))
        sampler.start()
        try:
            results = run(study, folder, workers=workers, progress=False)
        finally:
            stop.set()
            sampler.join()
        wall = time.perf_counter() - start
    marks, picked = sorted({100, 500, *range(1000, runs + 1, 1000), runs}), {}
    for mark in marks:
        hit = next((s for s in samples if s["runs_stored"] >= mark),
                   samples[-1] if mark == runs and samples else None)   # the last sample
        if hit:
            picked[mark] = hit
    import resource

    return {"runs": runs, "workers": workers, "wall_s": round(wall, 1),
            "statuses": results["status"].value_counts().to_dict(),
            "parent_rss_mb_before_study": round(rss_before, 1),
            "at_runs": picked, "parent_rss_mb_after_study": round(_rss_mb(), 1),
            "peak_rss_mb": {"parent": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024,
                            "largest_worker": resource.getrusage(
                                resource.RUSAGE_CHILDREN).ru_maxrss / 1024},
            "samples_taken": len(samples)}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--local", default=None, help="comma-separated local worker counts")
    parser.add_argument("--dask", default=None, help="comma-separated Dask worker counts")
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--memory", type=int, default=None, help="runs of the memory study")
    parser.add_argument("--workers", type=int, default=None, help="workers of --memory")
    args = parser.parse_args()
    _warm()
    info = {"machine": machine(),
            "date": time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime())}
    if args.local:
        info["local_0.5s_l36"] = local_scaling([int(x) for x in args.local.split(",")],
                                               args.repeat)
    if args.dask:
        info["dask_0.5s_l36"] = dask_scaling([int(x) for x in args.dask.split(",")],
                                             args.repeat)
    if args.memory:
        info["memory"] = memory(args.memory, args.workers or os.cpu_count() or 1)
    print(json.dumps(info, indent=2))


if __name__ == "__main__":
    main()
