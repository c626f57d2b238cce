"""Benchmark the finite-element disc's modes in the dynamic engine (issue 13, items 2-4).

Times a default 4 s run (RV-40E, 300 N*m, step 5e-6 s) with the rigid disc, the FE disc as a
massless condensed table (``flexibility.fe_modes = 0``) and the FE disc with 4 and 12 modes
(12: the most the step admits), the crankshafts rigid (``flexibility.fe_crank = false``: the
disc's cost alone); target: the flexible disc <= 2 x the rigid one.  Also 0 and 12 modes with
the FE crankshafts as well.  Carrier and flange rigid (``flexibility.fe_carrier = false``).  Also the
first build of the 12-mode model (eigenproblem of the disc held at its crank holes, after its
mesh).  Runs are interleaved (rigid, 0, 4, 12, rigid, ...) so that the other processes' load
falls on all alike; prints the medians (CPU and wall), the machine and the date as JSON.
BLAS threads are limited to one; the FE cache is a fresh temporary folder.

Usage:  python benchmarks/bench_fe_modes.py [--repeat 3]
"""

from __future__ import annotations

from _timing import one_thread

one_thread("rvsim-bench-fe-modes-")

import argparse  # noqa: E402
import os  # noqa: E402
import json  # noqa: E402
import statistics  # noqa: E402
import time  # noqa: E402

from _timing import SHORT, machine, once, samples  # noqa: E402


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=3)
    args = parser.parse_args()

    from rvsim.dynamics import simulate
    from rvsim.fe.disc import disc_table
    from rvsim.fe.modes import disc_free_interface
    from rvsim.parameters import RV40E, with_values

    def fe(modes, crank=False):
        return with_values(RV40E, {"A": 1, "flexibility.model": "fe",
                                   "flexibility.fe_crank": crank,
                                   "flexibility.fe_carrier": False,
                                   "flexibility.fe_modes": modes})

    disc_table(fe(0))
    _, wall, cpu = once(lambda: disc_free_interface(fe(12), 12))
    out = {"date": time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime()),
           "machine": machine(),
           "load_average": round(os.getloadavg()[0], 1),
           "modes_12_first_build_wall_s": wall,
           "modes_12_first_build_cpu_s": cpu}
    cases = {"rigid": RV40E, "fe_0_modes": fe(0), "fe_4_modes": fe(4), "fe_12_modes": fe(12),
             "fe_crank_0_modes": fe(0, True), "fe_crank_12_modes": fe(12, True)}
    for r in cases.values():
        simulate(with_values(r, SHORT))         # compile, load the caches
    times = {name: ([], []) for name in cases}
    for _ in range(args.repeat):
        for name, r in cases.items():
            walls, cpus = samples(lambda: simulate(r), 1)
            times[name][0].extend(walls)
            times[name][1].extend(cpus)
    for name, (walls, cpus) in times.items():
        out[f"simulate4s_{name}_wall_s"] = statistics.median(walls)
        out[f"simulate4s_{name}_cpu_s"] = statistics.median(cpus)
        out[f"simulate4s_{name}_cpu_all_s"] = cpus
    for name in list(cases)[1:]:
        out[f"{name}_over_rigid_cpu"] = (out[f"simulate4s_{name}_cpu_s"]
                                         / out["simulate4s_rigid_cpu_s"])
    out["load_average_end"] = os.getloadavg()[0]
    print(json.dumps(out, indent=2))


if __name__ == "__main__":
    main()
