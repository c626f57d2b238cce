"""``rvsim testrig`` (bench recordings: the standard numbers, the model beside them) and
``rvsim calibrate`` (fit uncertain parameters to the recordings).

Every input problem is one line naming the file, exit 2, and nothing is written; a model run
that fails prints its status and exits 1.
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import math
import sys
from pathlib import Path

from .._json import to_json_safe
from ..errors import ParameterError
from ._common import (number, add_command, add_reducer_options, check_input_speeds, check_load,
                      check_output_file, check_output_folder, path_text, print_json,
                      reducer_from_args, whole)

__all__ = ["register"]


def _column_map(args: argparse.Namespace):
    from ..testrig.recording import ColumnMap, parse_column_option, read_column_map

    column_map = read_column_map(args.map) if args.map else ColumnMap()
    extra = dict(parse_column_option(text) for text in args.columns)
    ratio = args.ratio
    if ratio is not None and not (math.isfinite(ratio) and ratio > 1):
        raise ParameterError("--ratio", f"must be a finite number above 1 (got {ratio:g})")
    return column_map.merged(ColumnMap(extra, ratio))


def _points_option(value: int) -> int:
    from ..testrig.analysis import check_points

    return check_points(value, "--points")


def _check_model_loads(analysed, reducer) -> None:
    """The largest torque the model is loaded with (the recordings' points, and the rated
    torque of a torque-reversal test) against the reducer's rating."""
    loads = [abs(float(p.point.get("torque_nm", 0.0))) for p in analysed]
    if loads:
        check_load(reducer, max(loads), "torque_nm (of the recordings)")


def _testrig(args: argparse.Namespace) -> int:
    report = None
    if args.report:
        if Path(args.report).suffix.lower() != ".html":
            raise ParameterError("--report", f"{args.report}: must be a .html file")
        report = check_output_file(args.report, "--report")
    points = _points_option(args.points)
    reducer = reducer_from_args(args)
    column_map = _column_map(args)
    from ..testrig.bench import analyse_path
    from ..testrig.model import compare_point, point_summary

    if args.compare:
        from ..analysis.sampling import check_positions

        check_positions(reducer, points, "--points")   # the model's TE at that many
    analysed = analyse_path(args.path, reducer, column_map, positions=points)
    if args.compare:
        _check_model_loads(analysed, reducer)
    results, code = [], 0
    for point in analysed:
        if args.compare:
            summary, simulated = compare_point(point, reducer, points=points)
            if simulated is None:
                code = 1
                print(f"rvsim: model failed at {point.point}: status "
                      f"{summary['simulated']['status']}", file=sys.stderr)
        else:
            summary, simulated = point_summary(point, reducer), None
        results.append((summary, point, simulated))
    if report:
        from ..testrig.report import write_testrig_report

        write_testrig_report(results, reducer, report)
    for summary, _, _ in results:
        if args.json:
            # one JSON object per operating point, one per line
            print(json.dumps(to_json_safe(summary), allow_nan=False))
        else:
            _print_point(summary)
    return code


def _fmt(value, spec: str) -> str:
    return "-" if value is None else format(value, spec)


def _print_point(s: dict) -> None:
    point = ", ".join(f"{k} {v:g}" for k, v in s["point"].items())
    print(f"[{point}] " * bool(point) + ", ".join(s["files"]))
    if s.get("ate_pp_arcmin") is not None:
        lines = ", ".join(f"{o['order']:g} ({o['name'] or '-'}) {o['amplitude_arcsec']:.3g}\""
                          for o in s["orders"][:4])
        print(f"  TE peak-to-peak {s['ate_pp_arcmin']:.4f} arcmin, RMS "
              f"{s['te_rms_arcsec']:.3f} arcsec; leading orders: {lines}")
    if "forward_backward_offset_arcmin" in s:
        print(f"  forward/backward offset {s['forward_backward_offset_arcmin']:.4f} arcmin")
        if "forward_backward_offset_note" in s:
            print(f"    ({s['forward_backward_offset_note']})")
    if "lost_motion_arcmin" in s:
        print(f"  lost motion {s['lost_motion_arcmin']:.4f} arcmin, backlash "
              f"{s['backlash_arcmin']:.4f} arcmin, hysteresis loss "
              f"{s['hysteresis_loss_arcmin']:.4f} arcmin, torsional rigidity "
              f"{s['torsional_rigidity_nm_per_arcmin']:.2f} N*m/arcmin")
        if "note" in s:
            print(f"    ({s['note']})")
    if "efficiency_pct" in s:
        print(f"  efficiency {s['efficiency_pct']:.2f} %")
    for note in s.get("notes", []):
        print(f"  note: {note}")
    sim, diff = s.get("simulated"), s.get("difference") or {}
    if sim and sim.get("status") == "ok":
        # efficiency in % (its fraction is the JSON's other key)
        keys = [k for k in diff if k not in ("te_curve_rms_arcsec", "efficiency")]
        print("  model: " + ", ".join(f"{k} {_fmt(sim.get(k), '.4g')} (difference "
                                         f"{diff[k]:+.4g})" for k in keys))
        if "torque_nm" not in s["point"] and s.get("ate_pp_arcmin") is not None:
            print("  note: no torque in the recording, its name or the manifest: the model ran "
                  "at 0 N*m")


def _calibrate(args: argparse.Namespace) -> int:
    out = check_output_folder(args.out, "--out")
    if not 32 <= args.positions <= 8192:
        raise ParameterError("--positions", f"must be 32 to 8192 (got {args.positions})")
    names = [n.strip() for n in args.fit.split(",") if n.strip()]
    if args.path is None and not args.loops and args.efficiency is None:
        raise ParameterError("FILE_OR_FOLDER", "give recordings, --loop FILE.csv or "
                             "--efficiency FILE.csv to fit")
    reducer = reducer_from_args(args)
    from ..analysis.sampling import check_positions

    check_positions(reducer, args.positions, "--positions")
    column_map = _column_map(args)
    from ..parameters._io import toml_text
    from ..testrig.bench import analyse_path
    from ..testrig.calibration import calibrate, fitted_names
    from ..testrig.curves import check_efficiency_points, read_efficiency, read_loop

    fitted_names(names)                    # before the recordings are read
    given = [Path(path).resolve() for path in args.loops]
    if len(set(given)) != len(given):      # the same data twice narrowed every interval
        raise ParameterError("--loop", f"{next(p for p in given if given.count(p) > 1)}: "
                             "given twice")
    loops = [read_loop(path) for path in args.loops]
    for loop in loops:
        check_load(reducer, float(abs(loop.torque).max()), f"--loop {loop.path.name}")
    efficiency = None if args.efficiency is None else read_efficiency(args.efficiency)
    if efficiency is not None:
        check_load(reducer, float(efficiency.torque.max()), "--efficiency output_torque_nm")
        check_efficiency_points(efficiency, reducer)
        check_input_speeds(reducer, efficiency.speed_rpm, "--efficiency input_speed_rpm")
    analysed = [] if args.path is None else analyse_path(args.path, reducer, column_map)
    _check_model_loads(analysed, reducer)
    result = calibrate(analysed, reducer, names, positions=args.positions, loops=loops,
                       efficiency=efficiency)
    from .._files import atomic_outputs

    out.mkdir(parents=True, exist_ok=True)
    payload = result.to_dict()
    # only a fit is written as a parameter file: a guess under the name "calibrated" would be
    # used with --params as one (an earlier run's fitted.toml is removed with it)
    fitted = out / "fitted.toml" if payload["status"] == "ok" else None
    # the fitted set says what it is (its name shows in every report made with it)
    sources = ([Path(args.path).name] if args.path else []) + [Path(p).name for p in args.loops] \
        + ([Path(args.efficiency).name] if args.efficiency else [])
    calibrated = dataclasses.replace(result.reducer, name=f"{reducer.name}, calibrated to "
                                     f"{', '.join(sources)}")
    payload["fitted_params"] = None if fitted is None else str(fitted)
    with atomic_outputs(fitted, out / "calibration.json") as (fitted_tmp, payload_tmp):
        if fitted_tmp is not None:
            fitted_tmp.write_text(toml_text(calibrated), encoding="utf-8")  # both or neither
        payload_tmp.write_text(json.dumps(to_json_safe(payload), indent=2, allow_nan=False)
                               + "\n", encoding="utf-8")
    if fitted is None:
        (out / "fitted.toml").unlink(missing_ok=True)
    if args.json:
        print_json(payload)
    else:
        unit = payload["residual_unit"]
        key = "arcsec" if unit == "arcsec" else "percent"
        print(f"fitted {len(names)} parameters to {payload['residuals']} residuals "
              f"({payload['evaluations']} model evaluations): RMS "
              f"{payload[f'rms_start_{key}']:.3f} -> {payload[f'rms_{key}']:.3f} "
              f"{'arcsec' if unit == 'arcsec' else 'percentage points'}, status "
              f"{payload['status']}")
        for name, p in payload["parameters"].items():
            lo, hi = p["ci95"]
            interval = "not identifiable" if lo is None else f"95 % CI {lo:.6g} .. {hi:.6g}"
            print(f"  {name} = {p['estimate']:.6g} {p['unit']} ({interval})")
        for note in payload["notes"]:
            print(f"  note: {note}")
        if fitted is None:
            print(f"wrote {out / 'calibration.json'}; no fitted.toml: status "
                  f"{payload['status']} is not a fit")
        else:
            print(f"wrote {fitted} (use it with --params) and {out / 'calibration.json'}")
    return 0 if payload["status"] == "ok" else 1


def _inputs(p: argparse.ArgumentParser, optional: bool = False) -> None:
    p.add_argument("path", metavar="FILE_OR_FOLDER", type=path_text,
                   nargs="?" if optional else None,
                   help="a recording (.csv, .parquet) or a folder of them (with an optional "
                        "manifest.csv)" + (" (optional with --loop or --efficiency)"
                                           if optional else ""))
    p.add_argument("--map", metavar="FILE.toml", type=path_text,
                   help="column names, units and ratio (docs/user_guide.md, Test-bench data)")
    p.add_argument("--column", metavar="QUANTITY=COLUMN[:UNIT[:COUNTS]]", action="append",
                   default=[], dest="columns",
                   help="map one quantity, e.g. input_angle=enc1:counts:4096 (repeatable; "
                        "wins over --map)")
    p.add_argument("--ratio", type=number, metavar="I",
                   help="reduction ratio of the bench reducer (default: the parameter set's)")
    add_reducer_options(p)
    p.add_argument("--json", action="store_true", help="machine-readable output")


def register(sub) -> None:
    p = add_command(sub, "testrig", "bench recordings: TE, spectrum, lost motion, rigidity",
                    "Analyse encoder recordings of a test bench the standard way: TE over each "
                    "complete output revolution per direction (peak-to-peak, RMS, order "
                    "spectrum), forward/backward offset, lost motion, backlash, hysteresis "
                    "loss and torsional rigidity of a torque reversal, efficiency. One JSON "
                    "object per operating point (--json: one per line).",
                    ["rvsim testrig docs/examples/testrig --json",
                     "rvsim testrig run.csv --column input_angle=enc1:counts:4096 --json",
                     "rvsim testrig bench/ --map columns.toml --compare --report bench.html"])
    _inputs(p)
    p.add_argument("--compare", action="store_true",
                   help="run the model (quasi-static) at the same operating points")
    p.add_argument("--report", metavar="FILE.html",
                   help="write an HTML report (measured and model curves on the same axes)")
    p.add_argument("--points", "--positions", type=whole, default=4096, metavar="N",
                   dest="points",
                   help="positions (nodes) per output revolution of the measured and the "
                        "model TE (64 to 65536, default 4096); --positions is its name in "
                        "every other command and in Python")
    p.set_defaults(func=_testrig)

    p = add_command(sub, "calibrate", "fit uncertain parameters to bench recordings",
                    "Least-squares fit of the named parameters to the measured TE curves and "
                    "torque-reversal loops, loop curves (--loop) or, on their own, efficiency "
                    "points (--efficiency) (quasi-static model), with 95 % confidence "
                    "intervals from the Jacobian and the correlation of the fitted "
                    "parameters; writes OUT/fitted.toml (for --params) and "
                    "OUT/calibration.json.",
                    ["rvsim calibrate docs/examples/testrig --params base.toml "
                     "--fit errors.disc_runout,clearances.crank_arm_bushing --out fit",
                     "rvsim calibrate --loop docs/examples/hysteresis_loop.csv "
                     "--fit stiffness.pins,stiffness.support_bearings --out fit",
                     "rvsim calibrate --efficiency points.csv --params RV-40E-bearings "
                     "--fit friction.arm_bearing_f0,contact.friction_coefficient --out fit",
                     "rvsim calibrate bench/ --fit contact.bushing_stiffness_factor --out fit "
                     "--json"])
    _inputs(p, optional=True)
    p.add_argument("--loop", metavar="FILE.csv", action="append", default=[], dest="loops",
                   type=path_text,
                   help="a torque-reversal curve: columns torque_nm [N*m], twist_arcmin "
                        "[arcmin], optional branch (+1/-1), as rvsim hysteresis --csv writes "
                        "(repeatable)")
    p.add_argument("--efficiency", metavar="FILE.csv", type=path_text,
                   help="efficiency points: columns input_speed_rpm, output_torque_nm, "
                        "efficiency (fraction), optional temperature_c [degC] and "
                        "input_torque_nm; fitted on their own")
    p.add_argument("--fit", required=True, metavar="NAME,NAME,...",
                   help="parameters to fit (dotted names as --set takes)")
    p.add_argument("--out", required=True, metavar="DIR", type=path_text,
                   help="folder for fitted.toml and calibration.json")
    p.add_argument("--positions", type=int, default=1024, metavar="N",
                   help="model positions per output revolution (32 to 8192, default 1024; "
                        "at least 2 zp + 1, 81 for the RV-40E: fewer alias the pin order)")
    p.set_defaults(func=_calibrate)
