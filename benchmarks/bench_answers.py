"""How much the answers of a dynamic run move: rounding spread and time step (issue 14).

For each paper L36 run asked for, simulates at each ``--time-step`` and, with ``--perturb K``,
K + 1 times with the step changed by k * 1e-12 relative (k = 0 .. K): physically the same run,
other rounding.  Prints one JSON line per simulation (status, mean and peak-to-peak TE,
largest pin force (every step's, and the 2 kHz samples' beside it), energy residual, CPU time)
and, per run and step, the range of each metric.
The spread under ``--perturb`` is the floor below which a change of the kernel's arithmetic
cannot be judged (docs/benchmarks.md, issue 14).

``--scheme implicit-bearings`` runs that integration scheme (``--time-step`` then defaults to
its own step, 2e-5 s).  ``--node-mass-factor F`` scales the crank nodes' mass matrix by F: a
probe of how the answers depend on the crank modes (docs/decisions.md, "The largest pin force
at every step"), not a model option.

Usage:  python benchmarks/bench_answers.py [--runs 1-3] [--time-step 5e-6 7.8125e-6]
                                            [--perturb 4] [--scheme explicit]
                                            [--node-mass-factor 4]
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import time

from _timing import one_thread, run_numbers

one_thread()


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", default="1-3", help="paper L36 runs, e.g. 1-3 or 1,5,28")
    parser.add_argument("--time-step", type=float, nargs="+", default=None,
                        help="steps [s] (default: the scheme's)")
    parser.add_argument("--scheme", default="explicit",
                        choices=("explicit", "implicit-bearings"), help="integration scheme")
    parser.add_argument("--perturb", type=int, default=0,
                        help="extra runs with the step changed by k * 1e-12 relative")
    parser.add_argument("--node-mass-factor", type=float, default=1.0,
                        help="scale the crank nodes' mass matrix (a probe, not a model option)")
    args = parser.parse_args()

    import rvsim.dynamics.model as model
    from rvsim.dynamics import simulate
    from rvsim.dynamics.simulate import default_time_step
    from rvsim.parameters import RV40E, paper_run_values, with_values

    if args.node_mass_factor != 1.0:
        masses = model.mass_properties
        factor = args.node_mass_factor
        model.mass_properties = lambda r: dataclasses.replace(
            masses(r), crank_node_mass=masses(r).crank_node_mass * factor)
    steps = args.time_step or [default_time_step(args.scheme)]
    names = ("te_mean_arcmin", "te_pp_arcmin", "max_pin_force_n")
    for run in run_numbers(args.runs):
        reducer = with_values(RV40E, paper_run_values(run))
        for step in steps:
            seen: dict[str, list[float]] = {name: [] for name in names}
            for k in range(args.perturb + 1):
                cpu = time.thread_time()
                result = simulate(reducer, time_step=step * (1.0 + k * 1e-12),
                                  raise_on_failure=False, scheme=args.scheme)
                cpu = time.thread_time() - cpu
                line = {"run": run, "scheme": args.scheme, "time_step": step, "k": k,
                        "node_mass_factor": args.node_mass_factor, "status": result.status,
                        "energy_relative_residual": result.energy["relative_residual"],
                        "cpu_s": round(cpu, 3)}
                for name in names:
                    line[name] = result.metrics.get(name, float("nan"))
                    seen[name].append(line[name])
                window = result.time >= reducer.operating.steady_start - 1e-12
                line["max_pin_force_sampled_n"] = (float(result.pin_forces[window].max())
                                                   if window.any() else float("nan"))
                print(json.dumps(line), flush=True)
            if args.perturb:
                spread = {name: [min(v), max(v), (max(v) - min(v)) / abs(min(v))]
                          for name, v in seen.items()}
                print(json.dumps({"run": run, "time_step": step, "range": spread}), flush=True)


if __name__ == "__main__":
    main()
