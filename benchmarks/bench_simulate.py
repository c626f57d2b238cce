"""Benchmark one 4 s RV-40E run with every element active (issue 3, item 6).

"Every element active": the paper's L36 run 3 (all three flexibility switches on, fluctuating
400 N*m load, every error, modification and clearance at its highest level), so all contacts,
clearances and compliances take part.  Prints, for a cold process, the first-call time
(compilation or cache load included) and then the median of warm runs: wall time, integration
steps per second and pin-contact evaluations per second (80 pin contacts per step; pins that the
kernel proves open are skipped, so the evaluation rate counts the nominal 80 per step).
Besides the solver's wall time (``Result.wall_s``) it reports the thread's CPU time of each
run (``time.thread_time`` around ``simulate``: the solver plus a few ms of set-up and
metrics), which other processes on a shared machine disturb far less, and the load average.

``--scheme implicit-bearings``: that integration scheme (at its own step unless
``--time-step`` says otherwise; a tree without the option runs the explicit scheme).

Usage:  python benchmarks/bench_simulate.py [--repeat 5] [--run 3] [--time-step 5e-6]
                                            [--scheme explicit]
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import time

from _timing import machine


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=5)
    parser.add_argument("--run", type=int, default=3, help="paper L36 run (default 3)")
    parser.add_argument("--time-step", type=float, default=None,
                        help="integration step [s] (default: the model's default)")
    parser.add_argument("--scheme", default="explicit",
                        choices=("explicit", "implicit-bearings"), help="integration scheme")
    args = parser.parse_args()

    start = time.perf_counter()
    from rvsim.dynamics import simulate
    from rvsim.parameters import RV40E, paper_run_values, with_values

    options = {} if args.time_step is None else {"time_step": args.time_step}
    if args.scheme != "explicit":
        options["scheme"] = args.scheme
    reducer = with_values(RV40E, paper_run_values(args.run))
    first = simulate(reducer, **options)
    first_call = time.perf_counter() - start
    walls, cpus = [], []
    for _ in range(args.repeat):
        cpu = time.thread_time()
        result = simulate(reducer, **options)
        cpus.append(time.thread_time() - cpu)
        walls.append(result.wall_s)
    wall = statistics.median(walls)
    pins = 2 * reducer.cycloid.pin_count
    report = {
        "machine": machine(),
        "date": time.strftime("%Y-%m-%d"),
        "paper_run": args.run,
        "scheme": args.scheme,
        "first_call_s_including_import_and_jit": round(first_call, 2),
        "median_wall_s": round(wall, 3),
        "runs": [round(w, 3) for w in walls],
        "median_cpu_s": round(statistics.median(cpus), 3),
        "cpu_runs": [round(c, 3) for c in cpus],
        "load_average_1min": round(os.getloadavg()[0], 2),
        "steps": result.steps,
        "steps_per_s": round(result.steps / wall),
        "pin_contact_evaluations_per_s": round(result.steps * pins / wall),
        "te_mean_arcmin": round(first.metrics["te_mean_arcmin"], 6),
        "te_pp_arcmin": round(first.metrics["te_pp_arcmin"], 6),
        "max_pin_force_n": round(first.metrics["max_pin_force_n"], 3),
        "energy_relative_residual": float(f"{first.energy['relative_residual']:.3g}"),
    }
    print(json.dumps(report, indent=2))


if __name__ == "__main__":
    main()
