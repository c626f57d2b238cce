"""How many evaluations of a bushing's law Newton takes per step, by its start (issue 14).

A synthetic history of paper run 3's arm bushing (the conforming law of docs/model.md section
16 with run 3's constants): a 10 % swing of 2 kN at 250 Hz plus a ripple at 22 kHz (the crank
nodes' mode) of a chosen amplitude, sampled at the default step.  For each step the script
counts the law's evaluations Newton needs, with the kernel's stopping rule
(``_bearings.NEWTON_CLOSE``), from three starts: the previous force (the kernel before the
second session of 2026-11-26), its first-order tangent prediction, and the second-order
Taylor expansion that ``_bearings.conforming_force_from`` uses (``conforming_start``).  Prints one JSON line per
ripple amplitude: the largest relative change of the force per step and, per start, how many
steps took 1, 2, 3 or more evaluations.

Usage:  python benchmarks/bench_newton_starts.py [--ripple 1e-4 1e-3 1e-2] [--time-step 5e-6]
"""

from __future__ import annotations

import argparse
import json
import math

import numpy as np


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--ripple", type=float, nargs="+", default=[1e-4, 1e-3, 1e-2])
    parser.add_argument("--time-step", type=float, default=5e-6)
    args = parser.parse_args()
    from rvsim.physics import _layout as L
    from rvsim.physics._bearings import NEWTON_CLOSE, conforming_approach, conforming_start
    from rvsim.dynamics.model import build_model
    from rvsim.parameters import RV40E, paper_run_values, with_values

    P = build_model(with_values(RV40E, paper_run_values(3)), args.time_step).P
    law = (P[L.ARM_J1], P[L.ARM_A1], P[L.ARM_J2], P[L.ARM_A2], P[L.ARM_CB])

    def evaluations(delta, start):
        f = start
        for n in range(1, 60):
            d, c, _ = conforming_approach(f, *law)
            step = (d - delta) / c
            if abs(step) <= NEWTON_CLOSE * (f - step):
                return n
            f -= step
        return 60

    t = np.arange(0.0, 0.02, args.time_step)
    for ripple in args.ripple:
        force = 2000.0 * (1.0 + 0.1 * np.sin(2 * math.pi * 250 * t)
                          + ripple * np.sin(2 * math.pi * 22000 * t))
        approach = [conforming_approach(f, *law)[0] for f in force]
        counts = {"previous force": [0] * 4, "first order": [0] * 4, "second order": [0] * 4}
        for i in range(1, len(force)):
            f0, d0, dd = force[i - 1], approach[i - 1], approach[i] - approach[i - 1]
            k0 = 1.0 / conforming_approach(f0, *law)[1]
            starts = {"previous force": f0, "first order": f0 + k0 * dd,
                      "second order": f0 * (1 + conforming_start(
                          approach[i], f0, d0, k0, law[1], law[0], law[3], law[2]))}
            for name, start in starts.items():
                counts[name][min(evaluations(approach[i], start), 4) - 1] += 1
        change = float(np.max(np.abs(np.diff(force) / force[:-1])))
        print(json.dumps({"ripple": ripple, "largest_change_per_step": round(change, 7),
                          "steps_by_evaluations_1_2_3_4+": counts}))


if __name__ == "__main__":
    main()
