"""Re-create docs/validation_data/fe_disc_modes.json: the finite-element disc's modes in the
dynamic engine (issue 13, items 2-3; docs/model.md section 17).

The RV-40E with the FE disc (A on, default mesh h = 1.6 mm, 8 segments per tooth) at its
default 300 N*m, and the paper's run 3 (Table 3 row 3, 400 N*m, every error and clearance of
its levels), default 4 s runs (steady window from 1.5 s), with 0, 2, 4, 8, 10, 12 disc modes
at the default step 5e-6 s (12 is the most that step admits) and 0, 12, 20 modes at 2.5e-6 s,
the crankshafts rigid (``flexibility.fe_crank = false``: the disc's modes alone); then 0, 4, 12
modes at 5e-6 s with the FE crankshafts as well; the carrier and flange rigid
(``flexibility.fe_carrier = false``; the runs were made before the FE carrier merged).
Per run: mean and peak-to-peak TE, largest pin force, energy residual, CPU time.  Records
are appended as they finish; ``--resume`` skips those already there.

Usage:  python docs/validation_data/make_fe_disc_modes.py [--resume]
"""

from __future__ import annotations

import argparse
import json
import time
from pathlib import Path

PATH = Path(__file__).with_name("fe_disc_modes.json")
CASES = [(False, step, modes) for step, counts in ((5e-6, (0, 2, 4, 8, 10, 12)),
                                                   (2.5e-6, (0, 12, 20))) for modes in counts]
CASES += [(True, 5e-6, modes) for modes in (0, 4, 12)]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--resume", action="store_true")
    args = parser.parse_args()

    from rvsim.dynamics import simulate
    from rvsim.parameters import RV40E, paper_run_values, with_values

    out = json.loads(PATH.read_text()) if args.resume and PATH.exists() else {"runs": []}
    done = {(rec["case"], rec.get("fe_crank", False), rec["time_step"], rec["modes"])
            for rec in out["runs"]}
    bases = {"rv40e_300nm": {"A": 1}, "paper_run_3": paper_run_values(3)}
    for case, values in bases.items():
        for crank, step, modes in CASES:
            if (case, crank, step, modes) in done:
                continue
            r = with_values(RV40E, {**values, "flexibility.model": "fe",
                                    "flexibility.fe_crank": crank,
                                    "flexibility.fe_carrier": False,
                                    "flexibility.fe_modes": modes})
            cpu = time.process_time()
            res = simulate(r, time_step=step, raise_on_failure=False)
            m = res.metrics
            out["runs"].append({
                "case": case, "fe_crank": crank, "time_step": step, "modes": modes,
                "status": res.status,
                "te_mean_arcmin": m["te_mean_arcmin"], "te_pp_arcmin": m["te_pp_arcmin"],
                "max_pin_force_n": m["max_pin_force_n"],
                "energy_relative_residual": res.energy["relative_residual"],
                "cpu_s": time.process_time() - cpu})
            out["date"] = time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime())
            PATH.write_text(json.dumps(out, indent=1) + "\n")
            print(json.dumps(out["runs"][-1]), flush=True)


if __name__ == "__main__":
    main()
