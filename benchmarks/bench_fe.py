"""Benchmark the finite-element disc, crank and carrier (issue 13, item 4).

Also times (CPU and wall) building the disc's Craig-Bampton model with 20 modes (verified, not
used by the engines), the 3-D crank's table at 3 mm and the carrier plate's table.

Targets: meshing and condensing the RV-40E disc <= 10 s once per geometry (then loaded from the
cache); a 360-position quasi-static TE curve with FE bodies <= 3 x the rigid-body one; a 4 s
dynamic run with them <= 2 x the rigid-disc run.  Cases: ``fe`` the FE disc alone,
``fe_crank`` with the FE cranks, ``fe_carrier`` with the FE carrier and flange, ``fe_all``
all three (the default with model = fe), ``fe_holes`` all three with the disc's crank holes as
load points (``flexibility.fe_disc_holes``).  Prints medians (wall and CPU time), the machine and
the date as JSON.  BLAS threads are limited to one; the cache is a fresh
temporary folder.

The 360-position curves are timed interleaved (each case in turn, ``--repeat`` rounds);
``--dynamic-repeat 0`` leaves the 4 s runs out.

Usage:  python benchmarks/bench_fe.py [--repeat 5] [--dynamic-repeat 1]
"""

from __future__ import annotations

from _timing import one_thread

one_thread("rvsim-bench-fe-")

import argparse  # noqa: E402
import os  # noqa: E402
import json  # noqa: E402
import time  # noqa: E402

from _timing import SHORT, interleaved, machine, timed  # noqa: E402


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=5)
    parser.add_argument("--dynamic-repeat", type=int, default=1)
    args = parser.parse_args()

    from rvsim.dynamics import simulate
    from rvsim.fe.carrier import carrier_table
    from rvsim.fe.crank import crank_table
    from rvsim.fe.disc import disc_table
    from rvsim.fe.modes import disc_craig_bampton
    from rvsim.parameters import RV40E, with_values
    from rvsim.quasistatic import ltca

    rigid = RV40E
    tooth = with_values(RV40E, {"A": 1})
    alone = {"flexibility.fe_crank": False, "flexibility.fe_carrier": False}
    fe = with_values(RV40E, {"A": 1, "flexibility.model": "fe", **alone})
    fe_crank = with_values(fe, {"flexibility.fe_crank": True})
    fe_carrier = with_values(fe, {"flexibility.fe_carrier": True})
    fe_all = with_values(RV40E, {"A": 1, "flexibility.model": "fe"})
    # the disc's crank holes as load points (flexibility.fe_disc_holes; off by default)
    fe_holes = with_values(fe_all, {"flexibility.fe_disc_holes": True})
    start, cpu = time.perf_counter(), time.process_time()
    table = disc_table(fe)
    first_build = time.perf_counter() - start
    first_build_cpu = time.process_time() - cpu
    start = time.perf_counter()
    disc_table(fe)
    from_cache = time.perf_counter() - start
    out_bodies = {}
    for name, build in (("disc_craig_bampton_20_modes", lambda: disc_craig_bampton(fe, 20)),
                        ("crank_3mm", lambda: crank_table(fe)),
                        ("carrier", lambda: carrier_table(fe))):
        wall, cpu = time.perf_counter(), time.process_time()
        build()
        out_bodies[f"{name}_wall_s"] = time.perf_counter() - wall
        out_bodies[f"{name}_cpu_s"] = time.process_time() - cpu
    torque = RV40E.rating.rated_torque
    crank_table(fe_crank)                   # (timed above, now from the cache)
    for r in (rigid, tooth, fe, fe_crank, fe_carrier, fe_all, fe_holes):  # compile and warm
        ltca(r, torque=torque, positions=8, allow_aliasing=True)
    out = {"date": time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime()),
           "machine": machine(),
           "load_average": round(os.getloadavg()[0], 1),
           "disc_mesh_and_condense_s": first_build,
           "disc_mesh_and_condense_cpu_s": first_build_cpu, "disc_from_cache_s": from_cache,
           "disc_dofs": table.n_dofs, "disc_triangles": table.n_triangles,
           "segments": table.segments, **out_bodies}
    cases = (("rigid", rigid), ("tooth", tooth), ("fe", fe), ("fe_crank", fe_crank),
             ("fe_carrier", fe_carrier), ("fe_all", fe_all), ("fe_holes", fe_holes))
    fe_cases = ("fe", "fe_crank", "fe_carrier", "fe_all", "fe_holes")
    times = interleaved({name: (lambda r=r: ltca(r, torque=torque)) for name, r in cases},
                        args.repeat)
    for name, _ in cases:
        out[f"ltca360_{name}_wall_s"], out[f"ltca360_{name}_cpu_s"] = times[name]
    for name in fe_cases:
        out[f"ltca_{name}_over_rigid_cpu"] = (out[f"ltca360_{name}_cpu_s"]
                                              / out["ltca360_rigid_cpu_s"])
    if args.dynamic_repeat > 0:
        for name, r in cases:
            simulate(with_values(r, SHORT))         # load the compiled kernel
            out[f"simulate4s_{name}_wall_s"], out[f"simulate4s_{name}_cpu_s"] = timed(
                lambda: simulate(r), args.dynamic_repeat)
        for name in fe_cases:
            out[f"simulate_{name}_over_rigid_cpu"] = (out[f"simulate4s_{name}_cpu_s"]
                                                      / out["simulate4s_rigid_cpu_s"])
    print(json.dumps(out, indent=2))


if __name__ == "__main__":
    main()
