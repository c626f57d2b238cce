"""``rvsim simulate``: one dynamic run of the reducer."""

from __future__ import annotations

import argparse
import sys

from ..errors import ParameterError, SimulationError
from ._common import (number, add_command, add_reducer_options, check_load, check_output_file,
                      compile_time_text, path_text, print_json, reducer_from_args,
                      with_compile_time)

__all__ = ["register"]


def _simulate(args: argparse.Namespace) -> int:
    from ..dynamics import simulate

    if args.save and not args.save.lower().endswith(".npz"):
        raise ParameterError("--save", "histories are written as .npz (numpy.load reads them)")
    if args.report and not args.report.lower().endswith(".html"):
        raise ParameterError("--report", "the report is an .html file")
    for option, path in (("--save", args.save), ("--report", args.report)):
        if path is not None:
            check_output_file(path, option)     # before the run, not after it
    reducer = reducer_from_args(args)
    from ..parameters.rating import peak_load

    check_load(reducer, *peak_load(reducer))
    try:
        # a progress bar only for a person watching (stderr is a terminal)
        result = simulate(reducer, duration=args.duration, time_step=args.time_step,
                          scheme=args.scheme, progress=sys.stderr.isatty())
    except SimulationError as exc:
        if args.json:
            print_json({"status": exc.status, "error": str(exc)})
        print(f"rvsim: simulation failed ({exc.status}): {exc}", file=sys.stderr)
        return 1
    from .._files import atomic_outputs

    with atomic_outputs(args.save, args.report) as (save, report):   # both files or neither
        if save:
            result.save(save)
        if report:
            from ..report import write_run_report

            write_run_report(result, reducer, report)
    summary = with_compile_time(result.summary())
    if args.json:
        print_json(summary)
    else:
        print(f"{reducer.name}: {summary['sim_time_s']:.3f} s simulated in {summary['wall_s']:.2f}"
              f" s ({summary['steps']} steps{compile_time_text()}), status {summary['status']}")
        print(f"mean TE (t >= {reducer.operating.steady_start:g} s): "
              f"{summary['te_mean_arcmin']:.4f} arcmin, peak-to-peak "
              f"{summary['te_pp_arcmin']:.4f}, RMS {summary['te_rms_arcmin']:.4f}; speed ratio "
              f"{summary['speed_ratio']:.4f}; largest pin force {summary['max_pin_force_n']:.1f}"
              f" N")
        print(_ate_line(summary))
    return 0


def _ate_line(summary: dict) -> str:
    """The bench's index (ATE) or why the run has none."""
    import math

    ate, covered = summary["ate_arcmin"], summary["te_window_revolutions"]
    if math.isfinite(ate):
        return (f"ATE (peak-to-peak TE over one output revolution, what a bench measures): "
                f"{ate:.4f} arcmin; the steady window covers {covered:.3g} revolutions")
    if math.isfinite(covered):
        return ("ATE: none: the steady window covers "
                f"{covered:.3g} of an output revolution (raise --duration)")
    return "ATE: none"


def register(sub) -> None:
    p = add_command(sub, "simulate", "simulate the reducer's dynamics and report TE",
                    "Simulate the whole reducer (both stages, 80 pin contacts, "
                    "bushings with clearances, flexibility) and report the transmission "
                    "error TE = theta_in/i - theta_out (paper Eq. 22).  Without options: "
                    "the RV-40E, every error zero, 300 N*m.",
                    ["rvsim simulate --json",
                    "rvsim simulate --paper-run 2 --save run2.npz",
                    "rvsim simulate --set E=400 --set H=0.02 --json",
                    "rvsim simulate --paper-run 3 --scheme implicit-bearings --json"])
    add_reducer_options(p, paper_run=True)
    p.add_argument("--save", metavar="FILE.npz", type=path_text,
                   help="write the time histories (numpy .npz)")
    p.add_argument("--report", metavar="FILE.html", type=path_text,
                   help="write a self-contained HTML report")
    p.add_argument("--duration", type=number, help="simulated time [s] (default: "
                   "operating.duration, 4 s)")
    p.add_argument("--time-step", type=number,
                   help="integration step [s] (default: the scheme's, 5e-6 s explicit, 2e-5 s "
                   "implicit-bearings)")
    p.add_argument("--scheme", choices=("explicit", "implicit-bearings"), default="explicit",
                   help="integration scheme: explicit (default), or implicit-bearings: the "
                   "bearings' stiffness taken implicitly, a 4x larger step, about 40 %% of the "
                   "CPU time (closed-form bodies only; docs/model.md section 9)")
    p.add_argument("--json", action="store_true", help="print one JSON object")
    p.set_defaults(func=_simulate)
