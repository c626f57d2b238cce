"""Benchmark a 4 s run of RV-40E-bearings (every needle and tapered roller evaluated each step)
against the same run with the paper's bushings (issue 10, item 7: target <= 2x).

Both runs use the same schedule, step and errors (paper L36 run ``--run``, default 3: every
element active); the built-in sets differ in their bearings and, since RV-40E-bearings
carries the friction of a greased reducer, in friction too (the issue's comparison: the set
as users get it against the paper's model).  Prints the median wall and CPU time of
``--repeat`` warm runs of each model (the kernel is compiled / loaded from cache first) and
their ratios.

Usage:  python benchmarks/bench_bearings.py [--repeat 5] [--run 3]
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
    args = parser.parse_args()

    from rvsim.dynamics import simulate
    from rvsim.parameters import BUILT_IN_SETS, paper_run_values, with_values

    values = paper_run_values(args.run)
    models = {"bushings": with_values(BUILT_IN_SETS["RV-40E"], values),
              "bearings": with_values(BUILT_IN_SETS["RV-40E-bearings"], values)}
    walls = {name: [] for name in models}
    cpus = {name: [] for name in models}
    metrics = {}
    for name, reducer in models.items():
        metrics[name] = simulate(reducer).metrics          # compile / cache load
    for _ in range(args.repeat):                           # interleaved: same machine load
        for name, reducer in models.items():
            start = time.process_time()
            walls[name].append(simulate(reducer).wall_s)
            cpus[name].append(time.process_time() - start)
    median = {name: statistics.median(w) for name, w in walls.items()}
    median_cpu = {name: statistics.median(c) for name, c in cpus.items()}
    report = {
        "machine": machine(),
        "date": time.strftime("%Y-%m-%d"),
        "paper_run": args.run,
        "median_wall_s": {name: round(v, 3) for name, v in median.items()},
        "runs": {name: [round(w, 3) for w in v] for name, v in walls.items()},
        "ratio_bearings_to_bushings": round(median["bearings"] / median["bushings"], 3),
        "median_cpu_s": {name: round(v, 3) for name, v in median_cpu.items()},
        "cpu_runs": {name: [round(c, 3) for c in v] for name, v in cpus.items()},
        "cpu_ratio_bearings_to_bushings": round(median_cpu["bearings"]
                                                / median_cpu["bushings"], 3),
        "load_average_1min": round(os.getloadavg()[0], 2),
        "te_mean_arcmin": {name: round(m["te_mean_arcmin"], 4) for name, m in metrics.items()},
    }
    print(json.dumps(report, indent=2))


if __name__ == "__main__":
    main()
