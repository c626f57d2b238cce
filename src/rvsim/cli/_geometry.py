"""``rvsim params``, ``rvsim profile`` and ``rvsim sensitivity``."""

from __future__ import annotations

import argparse

from ..parameters import parameter_table
from ..errors import ParameterError
from ..parameters._io import toml_text
from ._common import (add_command, add_reducer_options, check_output_file, path_text,
                      print_json, reducer_from_args)

__all__ = ["register", "MAX_PROFILE_POINTS"]

#: most points ``rvsim profile`` writes: the chordal deviation is then below 1e-4 um for the
#: RV-40E, and the check evaluates 8x as many points (about 100 MB of memory)
MAX_PROFILE_POINTS = 1_000_000


def _params(args: argparse.Namespace) -> int:
    reducer = reducer_from_args(args)
    rows = parameter_table(reducer)
    if args.json:
        print_json({"name": reducer.name, "citation": reducer.citation, "parameters": rows})
        return 0
    if args.toml:
        print(toml_text(reducer), end="")
        return 0
    print(f"{reducer.name}: {reducer.citation}")
    width = max(len(r["name"]) for r in rows)
    for row in rows:
        value = row["value"]
        text = (("yes" if value else "no") if isinstance(value, bool)
                else value if isinstance(value, str) else f"{value:.6g}")
        print(f"{row['name']:<{width}}  {text:>12}  {row['unit']:<7} {row['description']}")
    return 0


def _profile(args: argparse.Namespace) -> int:
    from ..geometry.export import export_profile, least_points
    from ..geometry.layout import disc_count

    reducer = reducer_from_args(args)
    least = least_points(reducer)
    if not least <= args.points <= MAX_PROFILE_POINTS:
        raise ParameterError("--points", f"must be between {least:,} (3 per tooth of the "
                             f"{reducer.cycloid.disc_teeth}-tooth disc) and "
                             f"{MAX_PROFILE_POINTS:,} (got {args.points:,})")
    if args.disc > disc_count(reducer):
        raise ParameterError("--disc", f"the reducer has {disc_count(reducer)} disc "
                             f"(layout.disc_count = 1); got {args.disc}")
    check_output_file(args.out, "--out")
    summary = export_profile(reducer, args.out, points=args.points, disc=args.disc - 1)
    if args.json:
        print_json(summary)
    else:
        holes = "".join(f", {n} {layer.lower().replace('_', ' ')}"
                        for layer, n in summary["holes"].items())
        print(f"wrote {summary['file']}: disc {summary['disc']}, {summary['teeth']}-tooth "
              f"profile, {summary['points']} points, max chordal deviation "
              f"{summary['chordal_deviation_mm'] * 1e3:.3f} um{holes}")
    return 0


def _sensitivity(args: argparse.Namespace) -> int:
    from ..analytical import reducer_errors, sensitivity_table

    reducer = reducer_from_args(args)
    table = sensitivity_table(reducer, reducer_errors(reducer))
    if args.json:
        print_json(table.to_dict())
        return 0
    print(f"K1 = {table.curtate_ratio:.4f}")
    print(f"{'symbol':<14}{'error [mm]':>11}{'coefficient':>13}{'sensitivity':>13}"
          f"{'TE [arcmin]':>13}  {'value from':<33}error")
    for t in table.terms:
        print(f"{t.symbol:<14}{t.error * 1e3:>11.4f}{t.coefficient:>13.5g}"
              f"{t.sensitivity_index:>13.5g}{t.te_arcmin:>13.4f}  {t.source:<33}{t.name}")
    print(f"mean TE, Eq. (11): {table.mean_te_arcmin:.4f} arcmin")
    return 0


def register(sub) -> None:
    p = add_command(sub, "params", "list every parameter with its unit and value",
                    "List every reducer parameter: dotted name, value, unit.",
                    ["rvsim params",
                    "rvsim params --toml > my_reducer.toml",
                    "rvsim params --set cycloid.eccentricity=1.4 --json"])
    add_reducer_options(p)
    fmt = p.add_mutually_exclusive_group()
    fmt.add_argument("--json", action="store_true", help="print one JSON object")
    fmt.add_argument("--toml", action="store_true",
                     help="print a complete TOML file to edit and pass to --params")
    p.set_defaults(func=_params)

    p = add_command(sub, "profile", "export the cycloid disc (CSV profile, DXF or SVG drawing)",
                    "Write the (modified) cycloid disc in millimetres. The format follows "
                    "the extension: .csv (the profile's x_mm,y_mm), .dxf or .svg (the whole "
                    "disc: the profile as a closed polyline on layer CYCLOID_PROFILE, the "
                    "holes as circles on layers BORE, CRANK_HOLES, PILLAR_HOLES, or for the "
                    "single-stage drive BORE and OUTPUT_PIN_HOLES).",
                    ["rvsim profile --out disc.dxf",
                    "rvsim profile --out disc.svg --disc 2",
                    "rvsim profile --set I=0.016 --set J=0.026 --out disc.csv --points 7200"])
    add_reducer_options(p)
    p.add_argument("--out", required=True, metavar="FILE", type=path_text,
                   help="output file (.csv, .dxf or .svg)")
    p.add_argument("--disc", type=int, choices=(1, 2), default=1,
                   help="which disc (default 1; disc 2's teeth are cut half a pitch turned, "
                   "so it is disc 1 turned half a turn only for an odd tooth count and an "
                   "even pillar count)")
    p.add_argument("--points", type=int, default=36000, help="points on the profile "
                   "(default 36000: chordal deviation about 0.13 um for the RV-40E)")
    p.add_argument("--json", action="store_true", help="print a JSON summary")
    p.set_defaults(func=_profile)

    p = add_command(sub, "sensitivity", "the paper's analytical error model (Table 1)",
                    "Error terms of Eqs. (2)-(10), their sensitivity indices "
                    "(Eq. 15) and the mean transmission error of Eq. (11).  Each error "
                    "value is the reducer's own where its parameter is set (non-zero: H, F, "
                    "I, J, errors.disc_runout, G), else the paper's Table 1 value; the "
                    "'value from' column says which.",
                    ["rvsim sensitivity",
                    "rvsim sensitivity --set H=0.01 --set I=0.032",
                    "rvsim sensitivity --json"])
    add_reducer_options(p)
    p.add_argument("--json", action="store_true", help="print one JSON object")
    p.set_defaults(func=_sensitivity)
