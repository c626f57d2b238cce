"""Benchmark the quasi-static engine (issue 9, item 8).

Targets: one RV-40E TE curve of 360 positions at rated torque <= 50 ms warm on one core; a
torque-reversal (hysteresis) test <= 100 ms; the first call in a new process <= 1.5 s with a
warm numba cache.  Prints the median of ``--repeat`` warm runs (wall and CPU time), the first
call of a fresh interpreter (import + cache load + one TE curve; run twice, so the cache is
warm for the second), the machine and the date.  BLAS threads are limited to one.

Usage:  python benchmarks/bench_quasistatic.py [--repeat 20]
"""

from __future__ import annotations

import os

from _timing import one_thread

one_thread()

import argparse  # noqa: E402
import json  # noqa: E402
import subprocess  # noqa: E402
import sys  # noqa: E402
import time  # noqa: E402

from _timing import machine, timed  # noqa: E402

FIRST_CALL = """
import time
start = time.perf_counter()
from rvsim.parameters import RV40E
from rvsim.quasistatic import ltca
ltca(RV40E, torque=RV40E.rating.rated_torque)
print(time.perf_counter() - start)
"""


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=20)
    args = parser.parse_args()

    first = []
    for _ in range(2):        # the first fills the cache if it is cold; the second is measured
        out = subprocess.run([sys.executable, "-c", FIRST_CALL], capture_output=True, text=True,
                             check=True, env=os.environ)
        first.append(float(out.stdout.strip().splitlines()[-1]))

    from rvsim.parameters import RV40E, paper_run_values, with_values
    from rvsim.quasistatic import hysteresis, ltca

    rated = RV40E.rating.rated_torque
    report = {
        "machine": machine(),
        "date": time.strftime("%Y-%m-%d"),
        "repeat": args.repeat,
        "first_call_new_process_warm_cache_s": round(first[1], 3),
        "first_call_new_process_first_try_s": round(first[0], 3),
    }
    cases = {"rv40e": RV40E, **{f"paper_run_{k}": with_values(RV40E, paper_run_values(k))
                                for k in (1, 2, 3)}}
    for name, reducer in cases.items():
        ltca(reducer, torque=rated)
        hysteresis(reducer)
        wall, cpu = timed(lambda: ltca(reducer, torque=rated), args.repeat)
        result = ltca(reducer, torque=rated)
        report[f"{name}_ltca_360_rated_ms"] = {"wall": round(1e3 * wall, 2),
                                               "cpu": round(1e3 * cpu, 2),
                                               "newton_iterations_per_position": round(
                                                   float(result.iterations.mean()), 2)}
        wall, cpu = timed(lambda: hysteresis(reducer), args.repeat)
        report[f"{name}_hysteresis_ms"] = {"wall": round(1e3 * wall, 2),
                                           "cpu": round(1e3 * cpu, 2),
                                           "points": len(hysteresis(reducer).torque)}
    print(json.dumps(report, indent=2))


if __name__ == "__main__":
    main()
