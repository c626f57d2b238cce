"""Benchmark the paper's whole 36-run L36 study on this machine (issue 4, item 5).

Runs ``rvsim.doe.run(paper_l36(), folder)`` into a fresh temporary folder with the default
local workers (one per core), after a warm-up simulation so the JIT cache is loaded, and
reports the median wall time of ``--repeat`` studies, the CPU time of the parent and its
worker processes (those it has ended) and the load average.

``--short`` runs the same 36 rows with a 0.05 s schedule (about 20 ms of simulation each):
what remains is the runner's own cost per run (processes, dispatch, store), which a loaded
machine disturbs far less than the full study.

``--time-step`` sets every run's step (a study's ``time_step``; e.g. 1e-5 with the stability guard).
``--scheme`` runs the study with that integration scheme (a study's ``scheme``, with its own
step unless ``--time-step`` says otherwise); default: the study's, implicit-bearings since
2026-11-26 (fifth session; explicit before).

Usage:  python benchmarks/bench_study.py [--repeat 3] [--workers N] [--short] [--time-step S]
                                          [--scheme explicit|implicit-bearings]
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import os
import statistics
import tempfile
import time

from _timing import machine

SHORT_SCHEDULE = (("operating.duration", 0.05), ("operating.speed_ramp_time", 0.01),
                  ("operating.load_start", 0.01), ("operating.load_ramp_end", 0.02),
                  ("operating.steady_start", 0.03))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--workers", type=int, default=None)
    parser.add_argument("--short", action="store_true", help="0.05 s runs: runner overhead")
    parser.add_argument("--scheme", default=None, choices=("explicit", "implicit-bearings"),
                        help="integration scheme (default: the study's)")
    parser.add_argument("--time-step", type=float, default=None,
                        help="integration step [s] of every run (default: the model's)")
    args = parser.parse_args()

    from rvsim.doe import paper_l36, run
    from rvsim.dynamics import simulate
    from rvsim.parameters import RV40E, with_values

    simulate(with_values(RV40E, dict(SHORT_SCHEDULE)))  # load the JIT cache in this process
    study = paper_l36()
    if args.short:
        study = dataclasses.replace(study, fixed=study.fixed + SHORT_SCHEDULE)
    if args.time_step is not None:
        study = dataclasses.replace(study, time_step=args.time_step)
    if args.scheme is not None:
        study = dataclasses.replace(study, scheme=args.scheme)
    walls, cpus = [], []
    for _ in range(args.repeat):
        with tempfile.TemporaryDirectory() as folder:
            start = time.perf_counter()
            before = os.times()
            results = run(study, folder, workers=args.workers, progress=False)
            walls.append(time.perf_counter() - start)
            after = os.times()
            # CPU of this process and of the worker processes it has reaped
            cpus.append(sum(after[:4]) - sum(before[:4]))
            # the short runs are too short to settle (their status may say so): only the
            # runner's cost is measured then
            assert args.short or (results["status"] == "ok").all()
    print(json.dumps({
        "machine": machine(),
        "date": time.strftime("%Y-%m-%d"),
        "runs_per_study": 36,
        "schedule": "short (0.05 s)" if args.short else "paper (4 s)",
        "time_step_s": study.time_step,
        "scheme": study.scheme,
        "workers": args.workers or os.cpu_count(),
        "median_study_wall_s": round(statistics.median(walls), 2),
        "studies": [round(w, 2) for w in walls],
        "cpu_s_all_processes": [round(c, 1) for c in cpus],
        "load_average_1min": round(os.getloadavg()[0], 2),
    }, indent=2))


if __name__ == "__main__":
    main()
