"""Benchmark the paper's whole 36-run L36 study on this machine (issue 4, item 5).

Runs ``rvsim.doe.run(paper_l36(), folder)`` into a fresh temporary folder with the default
local workers (one per core), after a warm-up simulation so the JIT cache is loaded, and
reports the median wall time of ``--repeat`` studies.

Usage:  python benchmarks/bench_study.py [--repeat 3] [--workers N]
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import statistics
import tempfile
import time


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--workers", type=int, default=None)
    args = parser.parse_args()

    from rvsim.doe import paper_l36, run
    from rvsim.dynamics import simulate
    from rvsim.parameters import RV40E

    simulate(RV40E, duration=0.01)  # load the JIT cache in this process
    walls = []
    for _ in range(args.repeat):
        with tempfile.TemporaryDirectory() as folder:
            start = time.perf_counter()
            results = run(paper_l36(), folder, workers=args.workers, progress=False)
            walls.append(time.perf_counter() - start)
            assert (results["status"] == "ok").all()
    print(json.dumps({
        "machine": f"{platform.machine()} {os.cpu_count()} cpu, Python "
                   f"{platform.python_version()}",
        "date": time.strftime("%Y-%m-%d"),
        "runs_per_study": 36,
        "workers": args.workers or os.cpu_count(),
        "median_study_wall_s": round(statistics.median(walls), 2),
        "studies": [round(w, 2) for w in walls],
    }, indent=2))


if __name__ == "__main__":
    main()
