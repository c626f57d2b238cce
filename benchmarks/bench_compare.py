"""Compare the dynamic run's CPU time of two or more source trees on a noisy machine (issue 14).

Runs ``bench_simulate.py --repeat K`` in a fresh process per tree, the trees alternating for
``--rounds`` rounds (so that a change of the machine's load falls on every tree alike), each
tree's ``src`` put first on ``PYTHONPATH``, and prints every process's CPU times with its
answers, then per tree the fastest, the lower quartile and the median of all its runs.  On a
shared VM single timings scatter by tens of %, so a change of a few % shows only in these
order statistics of many runs.  Warm each tree's numba cache first (one run of
``bench_simulate.py`` with that ``PYTHONPATH``): the first call's compilation is not counted
but takes the first process's time.

Usage:  python benchmarks/bench_compare.py NAME=TREE/src NAME=TREE/src [--rounds 5]
                                           [--repeat 4] [--run 3] [--time-step 5e-6]
                                           [--scheme explicit]
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("trees", nargs="+", help="NAME=path of a tree's src folder")
    parser.add_argument("--rounds", type=int, default=5)
    parser.add_argument("--repeat", type=int, default=4, help="runs per process")
    parser.add_argument("--run", type=int, default=3, help="paper L36 run (default 3)")
    parser.add_argument("--time-step", type=float, default=None)
    parser.add_argument("--scheme", default="explicit",
                        choices=("explicit", "implicit-bearings"), help="integration scheme")
    args = parser.parse_args()
    trees = []
    for item in args.trees:
        name, sep, path = item.partition("=")
        if not sep or not os.path.isdir(path):
            sys.exit(f"bench_compare: {item!r} is not NAME=an existing src folder")
        trees.append((name, path))
    extra = ["--repeat", str(args.repeat), "--run", str(args.run)]
    if args.time_step is not None:
        extra += ["--time-step", str(args.time_step)]
    if args.scheme != "explicit":
        extra += ["--scheme", args.scheme]
    cpus: dict[str, list[float]] = {name: [] for name, _ in trees}
    for _ in range(args.rounds):
        for name, path in trees:
            env = {**os.environ, "PYTHONPATH": path}
            out = subprocess.run([sys.executable, os.path.join(HERE, "bench_simulate.py"),
                                  *extra], env=env, capture_output=True, text=True,
                                 check=True).stdout
            report = json.loads(out[out.index("{"):])
            cpus[name] += report["cpu_runs"]
            print(json.dumps({"tree": name, "cpu_runs": report["cpu_runs"],
                              "te_mean_arcmin": report["te_mean_arcmin"],
                              "te_pp_arcmin": report["te_pp_arcmin"],
                              "max_pin_force_n": report["max_pin_force_n"],
                              "load_average_1min": report["load_average_1min"]}), flush=True)
    for name, values in cpus.items():
        values.sort()
        print(json.dumps({"tree": name, "runs": len(values), "fastest_cpu_s": values[0],
                          "lower_quartile_cpu_s": values[len(values) // 4],
                          "median_cpu_s": statistics.median(values)}))


if __name__ == "__main__":
    main()
