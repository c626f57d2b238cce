"""Re-create docs/validation_data/fe_carrier.json: what the finite-element carrier and flange
change (issue 13; docs/model.md section 17, "Carrier / flange").

The RV-40E at 300 N*m through the quasi-static engine: ltca (360 positions: TE mean and
peak-to-peak, mean local torsional stiffness) and the torque reversal (catalogue rigidity,
lost motion), rigid bodies against flexibility.model = fe with and without the carrier
(flexibility.fe_carrier), the disc rigid (A off) and finite-element (A on), the crank rigid
(flexibility.fe_crank = false) and finite-element.

Usage:  python docs/validation_data/make_fe_carrier.py
"""

from __future__ import annotations

import json
from pathlib import Path

NO_CRANK = {"flexibility.fe_crank": False}
CASES = {"rigid (closed-form, A off)": {},
         "fe, carrier only (A off, no crank)": {"flexibility.model": "fe", **NO_CRANK},
         "fe disc (A on), no crank, no carrier": {"A": 1, "flexibility.model": "fe", **NO_CRANK,
                                                  "flexibility.fe_carrier": False},
         "fe disc + carrier, no crank": {"A": 1, "flexibility.model": "fe", **NO_CRANK},
         "fe disc + crank, no carrier": {"A": 1, "flexibility.model": "fe",
                                         "flexibility.fe_carrier": False},
         "fe disc + crank + carrier (A on, the default fe)": {"A": 1, "flexibility.model": "fe"}}


def main() -> None:
    from rvsim.parameters import RV40E, with_values
    from rvsim.quasistatic import ltca
    from rvsim.quasistatic.torque_reversal import hysteresis

    out = {"torque_nm": 300.0, "cases": {}}
    for name, values in CASES.items():
        r = with_values(RV40E, values)
        s = ltca(r, torque=300.0).summary()
        h = hysteresis(r).summary()
        out["cases"][name] = {
            "te_mean_arcmin": s["te_mean_arcmin"], "te_pp_arcmin": s["te_pp_arcmin"],
            "stiffness_nm_per_arcmin": s["torsional_stiffness_nm_per_arcmin"],
            "rigidity_nm_per_arcmin": h["torsional_rigidity_nm_per_arcmin"],
            "lost_motion_arcmin": h["lost_motion_arcmin"], "status": [s["status"], h["status"]]}
        print(name, out["cases"][name], flush=True)
    path = Path(__file__).with_name("fe_carrier.json")
    path.write_text(json.dumps(out, indent=1) + "\n")
    print(f"wrote {path}")


if __name__ == "__main__":
    main()
