"""``rvsim efficiency``: efficiency map, no-load running torque and starting torque.

Arguments and output paths are checked before anything is computed (one-line error, exit 2);
a point that does not converge prints its status and exits 1.
"""

from __future__ import annotations

import argparse
import math
import sys

from ..errors import ParameterError
from ..parameters import plain_number
from ._common import (add_command, add_reducer_options, check_input_speeds, check_load,
                      compile_time_text, print_json, reducer_from_args, with_compile_time)
from ._quasistatic import _output_path, _solve, _write

__all__ = ["register", "parse_list", "MAX_POINTS"]

#: largest map (speeds x torques) a user could mean: ~2 min at 0.03 s a point
MAX_POINTS = 4000


def parse_list(option: str, text: str | None, *, positive: bool = True,
               example: str = "500,1000") -> list[float] | None:
    """Comma-separated numbers, each once, positive unless ``positive`` is False (then any
    finite number, e.g. temperatures); None: the default."""
    if text is None:
        return None
    parts = [p.strip() for p in text.split(",")]
    if any(not p for p in parts):
        raise ParameterError(option, f"'{text}': give comma-separated numbers, e.g. {example}")
    values = []
    for p in parts:
        try:
            value = plain_number(p)           # as --torque: no digit groups
        except ValueError:
            raise ParameterError(option, f"'{p}' is not a number") from None
        if positive and not (math.isfinite(value) and value > 0):
            raise ParameterError(option, f"every value must be a positive number (got {p})")
        if not math.isfinite(value):
            raise ParameterError(option, f"'{p}' is not a finite number")
        values.append(value)
    if len(set(values)) != len(values):
        raise ParameterError(option, f"'{text}': a value is given twice")
    return values


def _efficiency(args: argparse.Namespace) -> int:
    speeds = parse_list("--speeds", args.speeds)
    torques = parse_list("--torques", args.torques)
    from ..quasistatic.efficiency import MAX_SPEED_RPM

    if speeds and max(speeds) > MAX_SPEED_RPM:
        raise ParameterError("--speeds", f"input speeds up to {MAX_SPEED_RPM:g} rpm (got "
                             f"{max(speeds):g})")
    count = len(speeds or (1,) * 5) * len(torques or (1,) * 5)
    if count > MAX_POINTS:
        raise ParameterError("--speeds", f"{count} points: at most {MAX_POINTS} speeds x torques")
    report = _output_path("--report", args.report, ".html")
    csv = _output_path("--csv", args.csv, ".csv")
    reducer = reducer_from_args(args)
    if torques:
        check_load(reducer, max(torques), "--torques")
    if speeds:
        check_input_speeds(reducer, speeds, "--speeds")
    from ..quasistatic import efficiency

    result, code = _solve(lambda: efficiency(reducer, speeds_rpm=speeds, torques=torques),
                          args, "efficiency")
    if result is None:
        return code
    if report:
        from .._efficiency_report import write_efficiency_report

        _write("--report", report, lambda: write_efficiency_report(result, reducer, report))
    if csv:
        from .._files import atomic_outputs

        # the points as rvsim calibrate --efficiency reads them, with their temperature
        frame = result.to_frame().assign(temperature_c=result.temperature)
        with atomic_outputs(csv) as (csv_tmp,):
            _write("--csv", csv, lambda: frame.to_csv(csv_tmp, index=False))
    summary = result.summary()
    if not result.friction:
        note = ("no friction in this parameter set: efficiency 1 (set "
                "contact.friction_coefficient and friction.*)")
        summary["note"] = note
        print(f"rvsim: note: {note}", file=sys.stderr)
    if args.json:
        print_json(with_compile_time(summary))
        return 0
    print(f"{reducer.name}: efficiency at {len(result.input_speed)} speeds x "
          f"{len(result.output_torque)} torques ({summary['wall_s']:.2f} s"
          f"{compile_time_text()}), status "
          f"{summary['status']}")
    table = result.percent_table()
    table.columns = [f"{c:g} rpm" for c in table.columns]
    table.index = [f"{t:g} N*m" for t in table.index]
    print("efficiency [%]: output torque \\ input speed")
    print(table.to_string())
    running = ", ".join(f"{r['torque_nm']:.4g} N*m at {r['input_speed_rpm']:g} rpm"
                        for r in summary["no_load_running_torque"])
    print(f"no-load running torque (input): {running}")
    print(f"starting torque (input): {summary['starting_torque_nm']:.4g} N*m")
    print(f"lubricant at {summary['temperature_c']:g} degC: "
          f"{summary['oil_viscosity_mm2_s']:.4g} mm^2/s; lip seals' drag: "
          f"{summary['seal_torque_input_nm']:.4g} N*m on the input, "
          f"{summary['seal_torque_output_nm']:.4g} N*m on the output")
    return 0


def register(sub) -> None:
    p = add_command(sub, "efficiency", "efficiency map, no-load running and starting torque",
                    "Efficiency (output power / input power) over input speed and output "
                    "torque as catalogues draw it, the no-load running torque at each speed and "
                    "the starting torque, from the quasi-static engine with friction "
                    "(docs/model.md section 15). The default RV-40E has no friction "
                    "(efficiency 1): set contact.friction_coefficient and friction.*.",
                    ["rvsim efficiency --set friction.mesh_coefficient=0.05 --json",
                     "rvsim efficiency --params my_reducer.toml --speeds 500,1500,3000 "
                     "--torques 100,200,412 --report efficiency.html"])
    add_reducer_options(p)
    p.add_argument("--speeds", "--speeds-rpm", metavar="RPM,...", dest="speeds",
                   help="input speeds [rpm], comma-separated (default 500,1000,1500,2000,3000)")
    p.add_argument("--torques", metavar="NM,...",
                   help="output torques [N*m], comma-separated (default 20..100 %% of the "
                        "rated torque in 5 steps)")
    p.add_argument("--json", action="store_true", help="print one JSON object")
    p.add_argument("--report", metavar="FILE.html", help="write a self-contained HTML report")
    p.add_argument("--csv", metavar="FILE.csv",
                   help="write the points: input_speed_rpm, output_torque_nm, "
                        "input_torque_nm, efficiency, temperature_c (what rvsim calibrate "
                        "--efficiency reads)")
    p.set_defaults(func=_efficiency)
