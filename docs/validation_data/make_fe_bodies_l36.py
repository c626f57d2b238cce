"""Re-create docs/validation_data/fe_bodies_l36.json: the paper's conclusion 2 on the L36 with
every finite-element body (issue 13, item 6).

The 36 rows (Table 3 with the Table 2 levels) in three models: the closed-form compliances
(``closed-form``), the FE disc alone (``fe_disc``: crankshafts, carrier and flange rigid; with
switch B the pins are the FE pin) and every FE body (``fe_all``: disc, pins, crankshafts,
carrier and flange, the default of ``flexibility.model = fe``).  Factor A switches the disc in
all three; B the pins; the crankshafts and plates are flexible at both levels of every factor
in ``fe_all``.  Engines: the quasi-static one (``--positions`` per run at the run's load
torque E) and the dynamic one (default 4 s runs, steady window from 1.5 s; ``--dynamic``).
Range analysis of the mean TE and of its peak-to-peak, factor order.  Rows go to the JSON as
they finish; ``--resume`` skips those there.

Usage:  python docs/validation_data/make_fe_bodies_l36.py [--positions 90] [--dynamic]
        [--workers 2] [--resume]
"""

from __future__ import annotations

import argparse
import json
import time
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

import pandas as pd

PATH = Path(__file__).with_name("fe_bodies_l36.json")
FACTORS = list("ABCDEFGHIJKLMNO")
MODELS = {"closed-form": {"flexibility.model": "closed-form"},
          "fe_disc": {"flexibility.model": "fe", "flexibility.fe_crank": False,
                      "flexibility.fe_carrier": False},
          "fe_all": {"flexibility.model": "fe"}}


def one_row(job: tuple[str, int, int]) -> dict:
    """Run ``run`` of the L36 in every model with ``engine``."""
    engine, run, positions = job
    from rvsim.parameters import RV40E, paper_l36_scheme, paper_run_values, with_values

    scheme = paper_l36_scheme()
    row = scheme[scheme["run"] == run].iloc[0]
    rec = {"engine": engine, "run": run, **{f: int(row[f]) for f in FACTORS}}
    for name, model in MODELS.items():
        reducer = with_values(RV40E, {**paper_run_values(run), **model})
        start = time.process_time()
        if engine == "dynamic":
            from rvsim.dynamics import simulate

            s = simulate(reducer).summary()
            rec[f"energy_residual_{name}"] = s["energy_residual"]
        else:
            from rvsim.quasistatic import ltca

            s = ltca(reducer, positions=positions, raise_on_failure=False).summary()
        rec[f"te_mean_{name}"] = s["te_mean_arcmin"]
        rec[f"te_pp_{name}"] = s["te_pp_arcmin"]
        rec[f"status_{name}"] = s["status"]
        rec[f"cpu_s_{name}"] = time.process_time() - start
    return rec


def ranges(rows: list[dict]) -> dict:
    """Range analysis of each response over the rows of one engine."""
    from rvsim.analysis import range_analysis

    table = pd.DataFrame(rows)
    out = {}
    for name in MODELS:
        for response in (f"te_mean_{name}", f"te_pp_{name}"):
            ra = range_analysis(table[FACTORS + [response]], response, FACTORS)
            out[response] = {"ranges": ra.ranges, "order": ra.order,
                             "rank_A": ra.order.index("A") + 1,
                             "mean": float(table[response].mean())}
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--positions", type=int, default=90)
    parser.add_argument("--dynamic", action="store_true")
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--resume", action="store_true")
    args = parser.parse_args()
    engine = "dynamic" if args.dynamic else "quasistatic"

    out = json.loads(PATH.read_text()) if PATH.exists() else {}
    block = out.get(engine, {}) if args.resume else {}
    rows = block.get("runs", [])
    done = {rec["run"] for rec in rows}
    jobs = [(engine, run, args.positions) for run in range(1, 37) if run not in done]
    with ProcessPoolExecutor(args.workers) as pool:
        for rec in pool.map(one_row, jobs):
            rows.append(rec)
            out[engine] = {"positions": args.positions, "runs": rows}
            PATH.write_text(json.dumps(out, indent=1))
            print({k: v for k, v in rec.items() if k.startswith(("run", "te_", "status"))},
                  flush=True)
    rows.sort(key=lambda rec: rec["run"])
    out[engine] = {"positions": args.positions, "runs": rows, "ranges": ranges(rows)}
    PATH.write_text(json.dumps(out, indent=1))
    for response, r in out[engine]["ranges"].items():
        print(response, "rank of A", r["rank_A"], "range A %.4f" % r["ranges"]["A"],
              "order", "".join(r["order"]), "mean %.4f" % r["mean"])
    print(f"wrote {PATH}")


if __name__ == "__main__":
    main()
