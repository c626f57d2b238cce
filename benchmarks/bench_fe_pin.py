"""Benchmark and measure the finite-element pin in its groove (issue 13, item 1; docs/model.md
sections 6 and 17).

Prints as JSON: the table c_pin(psi) of the RV-40E against Roark's closed form, its build time
(fresh temporary cache) and load time, the quasi-static TE (360 positions, 300 N*m) and
torsional stiffness with FE pins against Roark's pins (model = fe; Roark's constant put in
the table, which the tests show is the closed-form model exactly), with the rigid and the FE
disc, and the time of a 4 s dynamic run with each pin model.

Usage:  python benchmarks/bench_fe_pin.py [--dynamic]
"""

from __future__ import annotations

import os

from _timing import SHORT, machine, once, one_thread

one_thread("rvsim-bench-fe-pin-")

import argparse  # noqa: E402
import json  # noqa: E402
import time  # noqa: E402


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--dynamic", action="store_true", help="also time 4 s dynamic runs")
    args = parser.parse_args()

    import numpy as np

    import rvsim.fe.pin as fe_pin
    from rvsim.physics import _layout as L
    from rvsim.dynamics.model import build_model
    from rvsim.parameters import RV40E, with_values
    from rvsim.quasistatic import ltca

    # the crank and the plates stay rigid: the pins and the disc are what is compared
    rigid_rest = {"flexibility.fe_crank": False, "flexibility.fe_carrier": False}
    fe = with_values(RV40E, {"B": 1, "flexibility.model": "fe", **rigid_rest})
    table, wall, cpu = once(lambda: fe_pin.pin_table(fe))
    out = {"date": time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime()),
           "machine": machine(),
           "load_average": round(os.getloadavg()[0], 1),
           "table_build_wall_s": wall, "table_build_cpu_s": cpu,
           "table_from_cache_s": once(lambda: fe_pin.pin_table(fe))[1]}
    model = fe_pin.PinModel(fe_pin.pin_geometry(fe))
    out.update({"pin_dofs": table.n_dofs, "pin_triangles": table.n_triangles,
                "boundary_edges": model.n_edges,
                "load_width_mm": 1e3 * fe_pin.pin_geometry(fe)["load_width"],
                "psi_deg": np.degrees(table.psi).round(3).tolist(),
                "c_pin": table.compliance.tolist()})
    roark = build_model(with_values(RV40E, {"B": 1}), 1e-5).P[L.PIN_CB]
    out["roark"] = roark
    real = fe_pin.pin_table
    constant = fe_pin.PinTable(table.psi, np.full(len(table.psi), roark), 0, 0, 0.0, True)

    def run(values, pins, torque=300.0):
        fe_pin.pin_table = real if pins == "fe" else (lambda reducer: constant)
        r = with_values(RV40E, values)
        ltca(r, torque=torque, positions=8, allow_aliasing=True)    # compile, tables
        cpu = time.process_time()
        result = ltca(r, torque=torque, positions=360)
        m = result.summary()
        return {"te_mean_arcmin": m["te_mean_arcmin"], "te_pp_arcmin": m["te_pp_arcmin"],
                "stiffness_nm_per_arcmin": m["torsional_stiffness_nm_per_arcmin"],
                "max_pin_force_n": m["max_pin_force_n"],
                "ltca_cpu_ms": 1e3 * (time.process_time() - cpu)}

    cases = {}
    for disc in (0, 1):
        base = {"A": disc, "flexibility.model": "fe", **rigid_rest}
        cases[f"disc{'_fe' if disc else '_rigid'}_pins_rigid"] = run(base, "fe")
        cases[f"disc{'_fe' if disc else '_rigid'}_pins_roark"] = run({**base, "B": 1}, "roark")
        cases[f"disc{'_fe' if disc else '_rigid'}_pins_fe"] = run({**base, "B": 1}, "fe")
    out["ltca_300nm"] = cases
    if args.dynamic:
        from rvsim.dynamics import simulate

        dyn = {}
        both = {"B": 1, "A": 1, "flexibility.model": "fe", **rigid_rest}
        for name, values, pins in (("roark", both, "roark"), ("fe", both, "fe")):
            fe_pin.pin_table = real if pins == "fe" else (lambda reducer: constant)
            r = with_values(RV40E, values)
            simulate(with_values(r, SHORT))                 # compile and warm
            result, wall, cpu = once(lambda: simulate(r))
            dyn[name] = {"cpu_s": cpu, "wall_s": wall,
                         "te_mean_arcmin": result.metrics["te_mean_arcmin"],
                         "status": result.status}
        out["dynamic_4s_fe_disc"] = dyn
    fe_pin.pin_table = real
    print(json.dumps(out, indent=1))


if __name__ == "__main__":
    main()
