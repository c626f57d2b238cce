"""``rvsim grid``: TE over input speed and output torque on the dynamic engine (issue 33 item 4).

Every argument, every point's parameters, load and run length are checked before anything is
written (one line, exit 2); the points run on the study's local workers, stored as they finish
(a second call reuses them).
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from ..errors import ParameterError
from ._common import (add_command, add_reducer_options, check_input_speeds, check_load,
                      check_output_file, check_output_folder, number, path_text, positive_int,
                      print_json, reducer_from_args, stopped_line)
from ._efficiency import parse_list

__all__ = ["register", "MAX_GRID_POINTS"]

#: most points of one grid: each is a dynamic run of one output revolution (seconds to a
#: minute of CPU each), so 400 points are already hours on two cores
MAX_GRID_POINTS = 400


def _check_loads(points) -> None:
    """The heaviest point against the rating: refused above the momentary maximum torque,
    one warning above the rated torque (rvsim.parameters.rating.check_torque)."""
    from ..parameters.rating import peak_load

    point = max(points, key=lambda p: peak_load(p["reducer"])[0])
    torque, field = peak_load(point["reducer"])
    where = "--torques" if field == "operating.load_torque" else f"--torques + {field[10:]}"
    check_load(point["reducer"], torque, where)


def _check_runs(points, time_step: float, scheme: str) -> None:
    from ..dynamics.simulate import check_run_options

    for point in points:
        try:
            check_run_options(point["reducer"], time_step=time_step, scheme=scheme)
        except ParameterError as exc:
            field = "--time-step" if exc.field == "time_step" else exc.field
            raise ParameterError(field, f"{exc.reason} (grid point {point['input_speed_rpm']:g} "
                                        f"rpm, {point['output_torque_nm']:g} N*m)") from None


def _grid(args: argparse.Namespace) -> int:
    from ..quasistatic.efficiency import MAX_SPEED_RPM

    speeds = parse_list("--speeds", args.speeds)
    torques = parse_list("--torques", args.torques)
    temperatures = parse_list("--temperatures", args.temperatures, positive=False,
                              example="20,40,60")
    if max(speeds) > MAX_SPEED_RPM:
        raise ParameterError("--speeds", f"input speeds up to {MAX_SPEED_RPM:g} rpm (got "
                                         f"{max(speeds):g})")
    count = len(speeds) * len(torques) * len(temperatures or (1,))
    if count > MAX_GRID_POINTS:
        raise ParameterError("--speeds", f"{count} points: at most {MAX_GRID_POINTS} speeds x "
                                         "torques x temperatures")
    report = check_output_file(args.report, "--report") if args.report else None
    if report is not None and report.suffix.lower() != ".html":
        raise ParameterError("--report", f"{report}: the report is an .html file")
    base = reducer_from_args(args)
    check_input_speeds(base, speeds, "--speeds")
    from ..doe._workers import WorkerStartError
    from ..doe.grid import grid_points, progress_to_stderr, run_grid, write_outputs
    from ..dynamics.simulate import default_time_step

    scheme = args.scheme or "explicit"
    time_step = args.time_step if args.time_step is not None else default_time_step(scheme)
    points = grid_points(base, speeds, torques, temperatures)
    _check_loads(points)
    _check_runs(points, time_step, scheme)
    check_output_folder(args.out, "--out")
    folder = Path(args.out)
    progress = progress_to_stderr if not args.no_progress else None
    try:
        table = run_grid(base, points, folder, time_step=time_step, scheme=scheme,
                         workers=args.workers, progress=progress)
    except KeyboardInterrupt as exc:            # Ctrl-C, or SIGTERM / SIGHUP (Terminated)
        line, code = stopped_line(exc, folder, "points")
        print(line, file=sys.stderr)
        return code
    except WorkerStartError as exc:             # as rvsim study says it
        print(f"rvsim: error: {exc}; finished points are kept in {folder}", file=sys.stderr)
        return 1
    summary = _summary(base, points, table, time_step, scheme)
    write_outputs(folder, table, summary)
    if report is not None:
        from ..doe.grid_report import write_grid_report

        write_grid_report(report, base, table, summary)
    if args.json:
        print_json({**summary, "folder": str(folder)})
    else:
        _print(table, summary, folder, report)
    if summary["failed"] == len(table):     # nothing measured: a failure, said in one line
        first = table.iloc[0]
        reason = f"{first['status']}" + (f": {first['error']}" if first["error"] else "")
        print(f"rvsim: error: grid: all {len(table)} points failed (first: "
              f"{reason.splitlines()[0][:300]}); their rows are in {folder}/grid.csv",
              file=sys.stderr)
        return 1
    return 0


def _summary(base, points, table, time_step: float, scheme: str) -> dict:
    from ..analysis.catalogue import reducer_orders
    from ..doe.grid import REVOLUTION_MARGIN

    modes = (table.groupby(["output_torque_nm", "temperature_c"], sort=False)
             [["natural_frequency_hz", "natural_frequency_min_hz", "natural_frequency_max_hz"]]
             .first().reset_index())
    return {"reducer": base.name, "engine": "dynamic", "time_step_s": time_step,
            "scheme": scheme, "points": int(len(table)),
            "failed": int((table["status"] != "ok").sum()),
            "duration_rule": f"operating.steady_start + {1 + REVOLUTION_MARGIN:g} output "
                             "revolutions at the point's input speed",
            "orders": reducer_orders(base),
            "natural_frequencies": modes.to_dict(orient="records"),
            "resonances": table.loc[table["resonance"] != "",
                                    ["input_speed_rpm", "output_torque_nm", "temperature_c",
                                     "resonance"]].to_dict(orient="records")}


def _print(table, summary: dict, folder: Path, report) -> None:
    points = summary["points"]
    print(f"{summary['reducer']}: grid of {points} point{'s' if points != 1 else ''}, "
          f"{summary['failed']} failed "
          f"-> {folder}/grid.csv, grid.json" + (f", {report}" if report else ""))
    shown = table[["input_speed_rpm", "output_torque_nm", "temperature_c", "status",
                   "ate_arcmin", "te_mean_arcmin", "order1", "natural_frequency_hz",
                   "nearest_order", "nearest_order_ratio", "resonance"]]
    print(shown.round(4).to_string(index=False))
    if summary["resonances"]:
        print("resonance (an order inside the natural frequency's half-power band) at: "
              + "; ".join(f"{r['input_speed_rpm']:g} rpm, {r['output_torque_nm']:g} N*m: "
                          f"{r['resonance']}" for r in summary["resonances"]))


def register(sub) -> None:
    p = add_command(sub, "grid", "TE over input speed and output torque (dynamic engine)",
                    "Simulate every point of speeds x torques (x temperatures) on the dynamic "
                    "engine for one output revolution in its steady window and write, per "
                    "point, the ATE (peak-to-peak TE over that revolution, what a bench "
                    "records), the largest orders of the TE, the mean twist (mean TE) and the "
                    "output's torsional natural frequency at the point's torque with the "
                    "frequency of each order of the reducer at the point's speed "
                    "(DIR/grid.csv, DIR/grid.json). Points are stored as they finish: a second "
                    "call reuses them (docs/user_guide.md).",
                    ["rvsim grid --speeds 500,1000,1500 --torques 100,200,412 --out grid",
                     "rvsim grid --speeds 1000,2000 --torques 200 --temperatures 20,60 "
                     "--out grid --workers 2 --report grid.html"])
    add_reducer_options(p)
    p.add_argument("--speeds", "--speeds-rpm", required=True, metavar="RPM,...", dest="speeds",
                   help="input speeds [rpm], comma-separated")
    p.add_argument("--torques", required=True, metavar="NM,...",
                   help="output torques [N*m], comma-separated (above the rated torque: a "
                        "warning; above the momentary maximum: refused)")
    p.add_argument("--temperatures", "--temperatures-c", metavar="DEGC,...",
                   dest="temperatures",
                   help="lubricant temperatures [degC], comma-separated (default: the "
                        "parameter set's operating.temperature)")
    p.add_argument("--out", required=True, metavar="DIR", type=path_text,
                   help="grid folder (its store keeps the finished points)")
    p.add_argument("--workers", type=positive_int,
                   help="local worker processes (default: one per core)")
    p.add_argument("--scheme", choices=("explicit", "implicit-bearings"),
                   help="integration scheme (default explicit; implicit-bearings: about 40 %% "
                        "of the CPU time, RV reducers with closed-form bodies)")
    p.add_argument("--time-step", type=number, metavar="SECONDS",
                   help="integration step [s] (default: the scheme's)")
    p.add_argument("--report", metavar="FILE.html", type=path_text,
                   help="write a self-contained HTML report")
    p.add_argument("--no-progress", action="store_true", help="no progress lines")
    p.add_argument("--json", action="store_true", help="print a JSON summary")
    p.set_defaults(func=_grid)
