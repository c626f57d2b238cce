"""Re-create docs/validation_data/fe_disc_dynamic.json: the paper's L36 through the dynamic
engine, once with the closed-form compliances and once with the finite-element disc (issue 13,
item 6; the quasi-static counterpart is make_fe_disc.py).

Each of the 36 rows (Table 3 with the Table 2 levels) is a default 4 s run (steady window
from 1.5 s); range analysis of the mean TE and of its peak-to-peak, factor order.  Rows are
appended to the JSON as they finish, so an interrupted run keeps what it did; ``--resume``
skips the rows already there.

Usage:  python docs/validation_data/make_fe_disc_dynamic.py [--resume]
"""

from __future__ import annotations

import argparse
import json
import time
from pathlib import Path

import pandas as pd

#: the figures of the FE disc alone (the FE crank and carrier, on by default since, are
#: make_fe_carrier.py's and make_fe_bodies_l36.py's).  With switch B the pins are the FE pin
#: since issue 13's pin work; the JSON beside this script was made before, with Roark's pin.
DISC_ONLY = {"flexibility.fe_crank": False, "flexibility.fe_carrier": False}

PATH = Path(__file__).with_name("fe_disc_dynamic.json")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--resume", action="store_true")
    args = parser.parse_args()

    from rvsim.analysis import range_analysis
    from rvsim.dynamics import simulate
    from rvsim.parameters import RV40E, paper_l36_scheme, paper_run_values, with_values

    out = json.loads(PATH.read_text()) if args.resume and PATH.exists() else {"runs": []}
    done = {rec["run"] for rec in out["runs"]}
    scheme = paper_l36_scheme()
    for run in scheme["run"]:
        if int(run) in done:
            continue
        values = paper_run_values(int(run))
        row = scheme[scheme["run"] == run].iloc[0]
        rec = {"run": int(run), **{f: int(row[f]) for f in "ABCDEFGHIJKLMNO"}}
        for model in ("closed-form", "fe"):
            start = time.process_time()
            s = simulate(with_values(RV40E, {**values, "flexibility.model": model, **DISC_ONLY})).summary()
            rec[f"te_mean_{model}"] = s["te_mean_arcmin"]
            rec[f"te_pp_{model}"] = s["te_pp_arcmin"]
            rec[f"status_{model}"] = s["status"]
            rec[f"energy_residual_{model}"] = s["energy_residual"]
            rec[f"cpu_s_{model}"] = time.process_time() - start
        out["runs"].append(rec)
        PATH.write_text(json.dumps(out, indent=1))
        print(rec, flush=True)
    table = pd.DataFrame(out["runs"])
    factors = list("ABCDEFGHIJKLMNO")
    out["ranges"] = {}
    for response in ("te_mean_closed-form", "te_mean_fe", "te_pp_closed-form", "te_pp_fe"):
        ra = range_analysis(table[factors + [response]], response, factors)
        out["ranges"][response] = {"ranges": ra.ranges, "order": ra.order}
    PATH.write_text(json.dumps(out, indent=1))
    print(f"wrote {PATH}")


if __name__ == "__main__":
    main()
