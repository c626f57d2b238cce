"""``rvsim ltca`` and ``rvsim hysteresis``: the quasi-static engine and the catalogue tests.

Arguments and output paths are checked before anything is computed (one-line error, exit 2);
a solve that does not converge prints its status and exits 1.
"""

from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path

from ..errors import InputFileError, ParameterError
from ..analysis.sampling import MAX_POSITIONS, check_positions
from ..units import TO_SI
from ._common import (number, add_command, add_reducer_options, check_load, check_output_file,
                      compile_time_text, print_json, reducer_from_args, warn,
                      with_compile_time)

__all__ = ["register", "MIN_POSITIONS", "MAX_POSITIONS"]

#: equally spaced input positions over one output revolution: at least enough for a spectrum
#: up to a few orders, at most what a user could mean (0.01 deg of output per step at 36000);
#: the reducer's own floor (its pin order unaliased) is rvsim.analysis.sampling's
MIN_POSITIONS = 8
RPM = TO_SI["rpm"]



def _output_path(option: str, value: str | None, suffix: str) -> Path | None:
    """A file the command will write: right suffix, not a folder, in a folder where a file can
    really be created (probed with a temporary file: permission bits say nothing for root, nor
    for /proc or a read-only mount)."""
    if value is None:
        return None
    if Path(value).suffix.lower() != suffix:
        raise ParameterError(option, f"{value}: must be a {suffix} file")
    return check_output_file(value, option)


def _write(option: str, path: Path, write) -> None:
    """Write an output file; a failure that the probe could not foresee (disk full, quota) is
    the one-line error of that file, and no partial file stays (rvsim._files.atomic_write)."""
    try:
        write()
    except OSError as exc:
        raise InputFileError(f"{option} {path}: cannot write ({exc.strerror or exc})") from None


def _finite(option: str, value: float | None) -> None:
    if value is not None and not math.isfinite(value):
        raise ParameterError(option, f"must be a finite number (got {value})")


def _failed(args: argparse.Namespace, what: str, status: str, summary: dict | None) -> int:
    if args.json:
        print_json({**(summary or {}), "status": status})
    print(f"rvsim: {what} failed: status {status}", file=sys.stderr)
    return 1


def _solve(call, args: argparse.Namespace, what: str):
    """(result, exit code or None) of one engine call; a raised SimulationError is a failure."""
    from ..errors import SimulationError

    try:
        result = call()
    except SimulationError as exc:
        return None, _failed(args, what, exc.status, {"error": str(exc)})
    if result.status != "ok":
        return None, _failed(args, what, result.status, _safe_summary(result))
    return result, None


def _safe_summary(result) -> dict | None:
    from ..errors import RvsimError

    try:
        return result.summary()
    except RvsimError:     # a failed run's curve may not give every quantity
        return None


def _ltca(args: argparse.Namespace) -> int:
    _finite("--torque", args.torque)
    if not MIN_POSITIONS <= args.positions <= MAX_POSITIONS:
        raise ParameterError("--positions", f"must be {MIN_POSITIONS} to {MAX_POSITIONS} "
                             f"(got {args.positions})")
    report = _output_path("--report", args.report, ".html")
    reducer = reducer_from_args(args)
    check_positions(reducer, args.positions, "--positions")
    check_load(reducer, reducer.operating.load_torque if args.torque is None else args.torque,
               "operating.load_torque" if args.torque is None else "--torque")
    from ..quasistatic import ltca

    result, code = _solve(lambda: ltca(reducer, torque=args.torque, positions=args.positions),
                          args, "ltca")
    if result is None:
        return code
    if report:
        from ..report import write_ltca_report

        _write("--report", report, lambda: write_ltca_report(result, reducer, report))
    summary = with_compile_time(result.summary())
    if args.json:
        print_json(summary)
    else:
        print(f"{reducer.name} at {result.torque:g} N*m, {summary['positions']} positions over "
              f"one output revolution ({summary['wall_s']:.3f} s{compile_time_text()}), status "
              f"{summary['status']}")
        print(f"TE mean {summary['te_mean_arcmin']:.4f} arcmin (from the nominal assembly), "
              f"peak-to-peak {summary['te_pp_arcmin']:.4f} arcmin (ATE "
              f"{summary['ate_arcmin']:.4f} arcmin); max pin force "
              f"{summary['max_pin_force_n']:.1f} N, max contact stress "
              f"{summary['max_contact_stress_mpa']:.0f} MPa, pins in contact "
              f"{summary['pins_in_contact_min']}..{summary['pins_in_contact_max']}; "
              f"torsional stiffness {summary['torsional_stiffness_nm_per_arcmin']:.2f} "
              "N*m/arcmin")
        print(f"largest contact stress {summary['max_contact_stress_mpa']:.0f} MPa: "
              f"{summary['contact_stress_verdict']}")
    warning = result.contact_stress_warning()
    if warning:
        warn(warning)
    return 0


def _hysteresis(args: argparse.Namespace) -> int:
    _finite("--rated-torque", args.rated_torque)
    if args.rated_torque is not None and args.rated_torque <= 0:
        raise ParameterError("--rated-torque", f"must be positive (got {args.rated_torque:g})")
    _check_budget_options(args)
    report = _output_path("--report", args.report, ".html")
    export = _output_path("--export", args.export, ".json")
    csv = _output_path("--csv", args.csv, ".csv")
    reducer = reducer_from_args(args)
    check_load(reducer, reducer.rating.rated_torque if args.rated_torque is None
               else args.rated_torque,
               "rating.rated_torque" if args.rated_torque is None else "--rated-torque")
    from ..quasistatic import hysteresis, ltca

    result, code = _solve(lambda: hysteresis(reducer, rated_torque=args.rated_torque), args,
                          "hysteresis")
    if result is None:
        return code
    from ..analysis.catalogue import CurveError

    try:
        summary = result.summary()
    except CurveError as exc:   # the engine's curve cannot give a catalogue quantity
        print(f"rvsim: hysteresis failed: status invalid_curve ({exc})", file=sys.stderr)
        if args.json:
            print_json({"status": "invalid_curve", "error": str(exc)})
        return 1
    budget = None
    if args.budget:
        budget, code = _budget(reducer, result, args, summary)
        if budget is None:
            return code
        summary["budget"] = budget.summary()
    model = None
    if export:
        from ..joint_model import joint_model

        te_run, code = _solve(lambda: ltca(reducer, torque=result.rated_torque), args,
                              "ltca at rated torque (for --export)")
        if te_run is None:
            return code
        model = joint_model(result, te_run, reducer)
    from .._files import atomic_outputs

    with atomic_outputs(export, report, csv) as (export_tmp, report_tmp, csv_tmp):  # all or none
        if csv:
            from ..testrig.curves import loop_table

            _write("--csv", csv, lambda: loop_table(result).to_csv(csv_tmp, index=False))
        if export:
            from ..joint_model import write_joint_model

            _write("--export", export, lambda: write_joint_model(export_tmp, model))
        if report:
            from ..report import write_hysteresis_report

            _write("--report", report,
                   lambda: write_hysteresis_report(result, reducer, report_tmp, budget=budget))
    if args.json:
        print_json(with_compile_time(summary))
    else:
        print(f"{reducer.name}: torque-reversal test to +-{summary['rated_torque_nm']:g} N*m "
              f"({summary['wall_s']:.3f} s{compile_time_text()}), status {summary['status']}")
        print(f"torsional rigidity {summary['torsional_rigidity_nm_per_arcmin']:.2f} "
              f"N*m/arcmin (50-100 % of rated), lost motion {summary['lost_motion_arcmin']:.4f}"
              f" arcmin (+-3 %), backlash {summary['backlash_arcmin']:.4f} arcmin, hysteresis "
              f"loss {summary['hysteresis_loss_arcmin']:.4f} arcmin")
        if budget is not None:
            _print_budget(budget)
    return 0


def _check_budget_options(args: argparse.Namespace) -> None:
    """--budget-factor only with --budget, and a finite number >= budget.MIN_FACTOR."""
    if args.budget_factor is None:
        return
    if not args.budget:
        raise ParameterError("--budget-factor", "needs --budget")
    from ..quasistatic.budget import MIN_FACTOR

    if not (math.isfinite(args.budget_factor) and args.budget_factor >= MIN_FACTOR):
        raise ParameterError("--budget-factor", f"must be a finite number >= {MIN_FACTOR:g} "
                             f"(got {args.budget_factor:g}): a less stiffened element keeps "
                             "part of its compliance and its share says nothing")


def _budget(reducer, result, args: argparse.Namespace, summary: dict):
    """(the compliance budget of the test ``result``, exit code or None): a stiffened test that
    fails is the command's failure, with the budget's status naming the element."""
    from ..quasistatic.budget import DEFAULT_FACTOR, compliance_budget, rigidity_of

    rigidity, _ = rigidity_of(result)
    budget = compliance_budget(reducer, rated_torque=result.rated_torque,
                               factor=args.budget_factor or DEFAULT_FACTOR, rigidity=rigidity)
    if budget.status != "ok":
        return None, _failed(args, "hysteresis --budget", budget.status,
                             {**summary, "budget": budget.summary()})
    return budget, None


def _print_budget(budget) -> None:
    """The budget as text, the softest element first (arcmin at the output)."""
    from ..units import ARCMIN

    shares, stiffness = budget.shares, budget.element_stiffness
    order = budget.order()
    first = order[0]
    print(f"compliance budget (each element {budget.factor:g} x stiffer in turn, 50-100 % "
          f"secant): softest {budget.labels[first]}, {100 * shares[first]:.1f} % of the "
          "compliance")
    width = max(len(label) for label in budget.labels)
    print(f"  {'element':<{width}}   share   own stiffness [N*m/arcmin]")
    for i in order:
        own = (f"{stiffness[i] * ARCMIN:.0f}" if math.isfinite(stiffness[i])
               and stiffness[i] > 0 else "-")
        print(f"  {budget.labels[i]:<{width}}  {100 * shares[i]:5.1f} %  {own}")
    print(f"  sum {100 * (1 - budget.residual):.1f} %, residual {100 * budget.residual:.1f} % "
          f"(what a stiffened element keeps, load sharing of parallel elements); "
          f"rigidity {budget.rigidity * ARCMIN:.2f} N*m/arcmin ({budget.wall_s:.2f} s)")
def _life(args: argparse.Namespace) -> int:
    for option, value in (("--torque", args.torque), ("--output-speed", args.output_speed)):
        _finite(option, value)
        if value is not None and value <= 0:
            raise ParameterError(option, f"must be positive (got {value:g})")
    external = {"radial_load": args.radial_load, "moment": args.moment, "thrust": args.thrust}
    for name, value in external.items():
        option = "--" + name.replace("_", "-")
        _finite(option, value)
        if value < 0:
            raise ParameterError(option, f"must be zero or positive (got {value:g})")
    if not MIN_POSITIONS <= args.positions <= MAX_POSITIONS:
        raise ParameterError("--positions", f"must be {MIN_POSITIONS} to {MAX_POSITIONS} "
                             f"(got {args.positions})")
    reducer = reducer_from_args(args)
    from ..quasistatic.bearing_life import check_life_inputs

    rpm = reducer.rating.rated_output_speed / RPM if args.output_speed is None \
        else args.output_speed
    from ..parameters.rating import check_output_speed

    check_output_speed(reducer, rpm * RPM, "rating.rated_output_speed" if args.output_speed
                       is None else "--output-speed", refuse=True)
    check_life_inputs(reducer, 1.0, rpm * RPM)      # the reducer: RV with rolling bearings
    if args.radial_load or args.moment or args.thrust:
        from ..physics.rating_life import angular_contact_factors
        from ..quasistatic.bearing_life import check_static_capacity

        angular_contact_factors(reducer.bearings.main_contact_angle,
                                "bearings.main_contact_angle")
        check_static_capacity(reducer, args.radial_load, args.moment, args.thrust,
                              ("--radial-load", "--moment", "--thrust"))
    check_positions(reducer, args.positions, "--positions")
    check_load(reducer, reducer.rating.rated_torque if args.torque is None else args.torque,
               "rating.rated_torque" if args.torque is None else "--torque")
    from ..quasistatic import life

    result, code = _solve(lambda: life(reducer, torque=args.torque,
                                       output_speed=None if args.output_speed is None
                                       else args.output_speed * RPM,
                                       positions=args.positions, **external), args, "life")
    if result is None:
        return code
    summary = result.summary()
    if args.json:
        print_json(summary)
        return 0
    print(f"{reducer.name} at {summary['torque_nm']:g} N*m, output {summary['output_speed_rpm']:g}"
          f" rpm (cranks {summary['crank_speed_rpm']:g} rpm relative to the carrier), "
          f"{summary['positions']} positions ({summary['wall_s']:.2f} s), status "
          f"{summary['status']}")
    print(f"{'bearing':<32} {'C [N]':>8} {'P [N]':>8} {'L10 [1e6 rev]':>14} {'L10h [h]':>10}")
    for b in summary["bearings"]:
        if b["status"] != "ok":
            print(f"{b['name']:<32} {b['dynamic_rating_n']:8.0f}  {b['status']}")
            continue
        print(f"{b['name']:<32} {b['dynamic_rating_n']:8.0f} {b['equivalent_load_n']:8.0f} "
              f"{b['l10_million_revolutions']:14.4g} {b['l10_hours']:10.4g}")
    print(f"rating life {summary['life_hours']:.4g} h (shortest: {summary['limiting_bearing']});"
          f" all rated bearings together {summary['system_life_hours']:.4g} h")
    print(f"crank bearings {summary['crank_life_hours']:.4g} h against the catalogue rule "
          f"K (N0/N) (T0/T)^(10/3): {summary['catalogue_life_hours']:.4g} h (ratio "
          f"{summary['life_ratio_to_catalogue']:.3g})")
    return 0


def _common(p: argparse.ArgumentParser) -> None:
    add_reducer_options(p, paper_run=True)
    p.add_argument("--json", action="store_true", help="print one JSON object")
    p.add_argument("--report", metavar="FILE.html", help="write a self-contained HTML report")


def register(sub) -> None:
    p = add_command(sub, "ltca", "quasi-static loaded contact analysis over one output revolution",
                    "Static equilibrium of the whole reducer at equally spaced input angles over "
                    "one output revolution, one direction, under a constant output torque: "
                    "TE = theta_in/i - theta_out (mean from the nominal assembly, and "
                    "peak-to-peak = the catalogue's angular transmission error), pin forces, "
                    "contact stress, local torsional stiffness.",
                    ["rvsim ltca --json",
                     "rvsim ltca --torque 412 --positions 720 --report ltca.html",
                     "rvsim ltca --paper-run 2 --json"])
    _common(p)
    p.add_argument("--torque", type=number, metavar="NM",
                   help="output torque [N*m] (default: operating.load_torque; negative: the load "
                        "on the other flanks, as in a torque reversal)")
    p.add_argument("--positions", type=int, default=360, metavar="N",
                   help=f"input positions over one output revolution ({MIN_POSITIONS} to "
                        f"{MAX_POSITIONS}, default 360; at least 2 zp + 1, 81 for the "
                        "RV-40E: fewer alias the pin order)")
    p.set_defaults(func=_ltca)

    p = add_command(sub, "hysteresis", "torque-reversal test: rigidity, lost motion, backlash",
                    "Input locked, output torque 0 -> -rated -> 0 -> +rated -> 0 -> -rated "
                    "(GB/T 35089-2018): torsional rigidity (secant 50-100 % of rated), lost "
                    "motion (+-3 % of rated), backlash and hysteresis loss (at 0 N*m).",
                    ["rvsim hysteresis --json",
                     "rvsim hysteresis --paper-run 5 --report loop.html",
                     "rvsim hysteresis --export joint.json",
                     "rvsim hysteresis --params RV-40E-bearings --budget"])
    _common(p)
    p.add_argument("--rated-torque", type=number, metavar="NM",
                   help="rated torque [N*m] (default: the reducer's rating.rated_torque, "
                        "412 N*m for the RV-40E)")
    p.add_argument("--csv", metavar="FILE.csv",
                   help="write the loop: torque_nm [N*m], twist_arcmin [arcmin], branch "
                        "(+1 rising, -1 falling), what rvsim calibrate --loop reads")
    p.add_argument("--export", metavar="FILE.json",
                   help="write the joint model for robot simulators (docs/joint_model.md)")
    p.add_argument("--budget", action="store_true",
                   help="where the compliance goes: each machine element's share of the "
                        "torsional compliance (secant 50-100 %% of rated), each element "
                        "stiffened in turn (docs/model.md section 12)")
    p.add_argument("--budget-factor", type=number, metavar="S",
                   help="stiffening factor of one element for --budget (>= 100, default 1e4)")
    p.set_defaults(func=_hysteresis)

    p = add_command(sub, "life", "L10 rating life of the crank bearings (ISO 281)",
                    "Basic rating life L10 of every needle and tapered crank bearing at an "
                    "output torque and output speed: dynamic load rating C from the bearing's "
                    "geometry (ISO 281), mean equivalent load P over one output revolution from "
                    "the quasi-static model, speed of the crank relative to the carrier.  The "
                    "reducer's life is its shortest bearing life, beside the catalogue rule "
                    "K (N0/N) (T0/T)^(10/3).  Main bearings: their life under the external "
                    "--moment, --thrust and --radial-load on the output flange (none given: C "
                    "only).  Needs rolling crank bearings (--params RV-40E-bearings).",
                    ["rvsim life --params RV-40E-bearings",
                     "rvsim life --params RV-40E-bearings --torque 300 --output-speed 10 "
                     "--json",
                     "rvsim life --params RV-40E-bearings --moment 800 --thrust 2000"])
    add_reducer_options(p)
    p.add_argument("--json", action="store_true", help="print one JSON object")
    p.add_argument("--torque", type=number, metavar="NM",
                   help="output torque [N*m] (default: rating.rated_torque, 412 N*m for the "
                        "RV-40E)")
    p.add_argument("--output-speed", "--output-speed-rpm", type=number, metavar="RPM",
                   dest="output_speed",
                   help="output speed [rpm] (default: rating.rated_output_speed, 15 rpm)")
    p.add_argument("--positions", type=int, default=360, metavar="N",
                   help=f"input positions over one output revolution whose loads are averaged "
                        f"({MIN_POSITIONS} to {MAX_POSITIONS}, default 360)")
    p.add_argument("--moment", type=number, default=0.0, metavar="NM",
                   help="external tilting moment on the output flange [N*m], carried by the "
                        "main bearings (default 0: no main-bearing life)")
    p.add_argument("--thrust", type=number, default=0.0, metavar="N",
                   help="external axial force on the output flange [N] (default 0)")
    p.add_argument("--radial-load", type=number, default=0.0, metavar="N",
                   help="external radial force on the output flange, midway between the main "
                        "bearings [N] (default 0)")
    p.set_defaults(func=_life)
