"""Re-create docs/validation_data/fe_disc.json: the finite-element disc against the tooth model
(issue 13, item 6).

1. The RV-40E at rated torque, 360 positions: rigid disc (A off), the closed-form tooth (A on,
   flexibility.model = closed-form) and the FE disc (A on, fe) at two element sizes: TE mean
   and peak-to-peak, torsional stiffness, largest pin force.
2. The paper's L36 (Table 3 rows with Table 2 levels) through the quasi-static engine
   (``--positions`` per run, each run's own load torque E), once with the closed-form
   compliances and once with the FE disc: range analysis of the mean TE and of its peak-to-
   peak, factor order.  The FE tables are cached per disc geometry (the I and J levels).

Usage:  python docs/validation_data/make_fe_disc.py [--positions 90]
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

import pandas as pd

#: the figures of the FE disc alone (the FE crank and carrier, on by default since, are
#: make_fe_carrier.py's and make_fe_bodies_l36.py's).  With switch B the pins are the FE pin
#: since issue 13's pin work; the JSON beside this script was made before, with Roark's pin.
DISC_ONLY = {"flexibility.fe_crank": False, "flexibility.fe_carrier": False}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--positions", type=int, default=90)
    parser.add_argument("--skip-l36", action="store_true")
    args = parser.parse_args()

    from rvsim.analysis import range_analysis
    from rvsim.parameters import RV40E, paper_l36_scheme, paper_run_values, with_values
    from rvsim.quasistatic import ltca

    out: dict = {"rated": {}}
    torque = RV40E.rating.rated_torque
    cases = {"rigid": {}, "tooth (closed-form)": {"A": 1},
             "fe h=1.6 mm": {"A": 1, "flexibility.model": "fe", **DISC_ONLY},
             "fe h=0.8 mm": {"A": 1, "flexibility.model": "fe",
                             "flexibility.fe_element_size": 0.8, **DISC_ONLY}}
    for name, values in cases.items():
        s = ltca(with_values(RV40E, values), torque=torque).summary()
        out["rated"][name] = {k: s[k] for k in ("te_mean_arcmin", "te_pp_arcmin",
                                                "torsional_stiffness_nm_per_arcmin",
                                                "max_pin_force_n", "pins_in_contact_max")}
        print(name, out["rated"][name], flush=True)
    if not args.skip_l36:
        scheme = paper_l36_scheme()
        rows = []
        for run in scheme["run"]:
            values = paper_run_values(int(run))
            row = scheme[scheme["run"] == run].iloc[0]
            rec = {"run": int(run), **{f: int(row[f]) for f in "ABCDEFGHIJKLMNO"}}
            for model in ("closed-form", "fe"):
                r = with_values(RV40E, {**values, "flexibility.model": model, **DISC_ONLY})
                s = ltca(r, positions=args.positions, raise_on_failure=False).summary()
                rec[f"te_mean_{model}"] = s["te_mean_arcmin"]
                rec[f"te_pp_{model}"] = s["te_pp_arcmin"]
                rec[f"status_{model}"] = s["status"]
            rows.append(rec)
            print(rec, flush=True)
        table = pd.DataFrame(rows)
        out["l36"] = {"positions": args.positions, "runs": rows, "ranges": {}}
        factors = list("ABCDEFGHIJKLMNO")
        for response in ("te_mean_closed-form", "te_mean_fe", "te_pp_closed-form", "te_pp_fe"):
            ra = range_analysis(table[factors + [response]], response, factors)
            out["l36"]["ranges"][response] = {"ranges": ra.ranges, "order": ra.order}
    path = Path(__file__).with_name("fe_disc.json")
    path.write_text(json.dumps(out, indent=1))
    print(f"wrote {path}")


if __name__ == "__main__":
    main()
