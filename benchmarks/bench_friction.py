"""Benchmark friction and efficiency (issue 10, item 7).

Targets: a torque-reversal (hysteresis) test with friction <= 200 ms; an efficiency map of 5
speeds x 5 torques <= 30 s on 2 cores.  The RV-40E with rvsim.friction.TYPICAL_FRICTION;
prints the median of ``--repeat`` warm runs (wall and CPU time), the machine, the date and the
load average.  BLAS threads are limited to one (the map runs on one core).

Usage:  python benchmarks/bench_friction.py [--repeat 15]
"""

from __future__ import annotations

import os

from _timing import one_thread

one_thread()

import argparse  # noqa: E402
import json  # noqa: E402
import time  # noqa: E402

from _timing import machine, timed  # noqa: E402


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=15)
    args = parser.parse_args()

    from rvsim.friction import TYPICAL_FRICTION
    from rvsim.parameters import RV40E, with_values
    from rvsim.quasistatic import efficiency, hysteresis

    reducer = with_values(RV40E, TYPICAL_FRICTION)
    report = {
        "machine": machine(),
        "date": time.strftime("%Y-%m-%d %H:%M"),
        "load_average_1min_before": round(os.getloadavg()[0], 2),
        "repeat": args.repeat,
    }
    for name, r in (("frictionless", RV40E), ("typical_friction", reducer)):
        hysteresis(r)
        wall, cpu = timed(lambda: hysteresis(r), args.repeat)
        report[f"hysteresis_{name}_ms"] = {"wall": round(1e3 * wall, 1),
                                           "cpu": round(1e3 * cpu, 1)}
    efficiency(reducer)
    wall, cpu = timed(lambda: efficiency(reducer), max(3, args.repeat // 3))
    report["efficiency_map_5x5_s"] = {"wall": round(wall, 3), "cpu": round(cpu, 3)}
    report["load_average_1min_after"] = round(os.getloadavg()[0], 2)
    print(json.dumps(report, indent=2))


if __name__ == "__main__":
    main()
