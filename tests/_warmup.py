"""Compile rvsim's numba kernels once, before the tests run (``python -m tests._warmup KIND``).

The kernels are cached on disk (numba's ``cache=True``, guarded by
``rvsim._cache_guard``), so what one process compiles every later process loads.
Without this, the first test of each kernel in each pytest-xdist worker compiled it, both
workers the same kernels at once (a unit test took 68 s).  ``tests/conftest.py`` runs the two
kinds in two processes side by side, one per core: the dynamic engine's kernel, and the
quasi-static solver (which compiles the force elements into its own module) with the geometry's
curve functions.  Each call is the smallest run that reaches every compiled function of its
engine's schemes; with a warm cache a kind takes a few seconds.
"""

from __future__ import annotations

import sys

#: a short schedule of the dynamic model (the integration tests' own, tests/integration)
SHORT = {"operating.duration": 0.05, "operating.speed_ramp_time": 0.01,
         "operating.load_start": 0.01, "operating.load_ramp_end": 0.02,
         "operating.steady_start": 0.03}


def dynamic() -> None:
    from rvsim.dynamics import simulate
    from rvsim.parameters import BUILT_IN_SETS, RV40E, with_values

    short = with_values(RV40E, SHORT)
    simulate(short, raise_on_failure=False)
    simulate(short, scheme="implicit-bearings", raise_on_failure=False)
    simulate(short, time_step=7e-6, raise_on_failure=False)        # the step guard
    simulate(with_values(BUILT_IN_SETS["cycloid-drive"], SHORT), raise_on_failure=False)
    simulate(with_values(RV40E, {**SHORT, "bearings.arm_needles": True,
                                 "bearings.support_rollers": True}), raise_on_failure=False)


def quasistatic() -> None:
    from rvsim.geometry.cycloid import pin_gaps, undercut_ratio
    from rvsim.parameters import BUILT_IN_SETS, RV40E, with_values
    from rvsim.quasistatic import efficiency, hysteresis, ltca

    pin_gaps(RV40E, 0.0)                     # the geometry's compiled curve functions
    undercut_ratio(RV40E, samples=50)
    ltca(RV40E, positions=16, raise_on_failure=False)
    ltca(BUILT_IN_SETS["cycloid-drive"], positions=16, raise_on_failure=False)
    hysteresis(RV40E, points_per_branch=6, raise_on_failure=False)
    bearings = with_values(RV40E, {"bearings.arm_needles": True, "bearings.support_rollers": True})
    hysteresis(bearings, points_per_branch=6, raise_on_failure=False)
    friction = with_values(RV40E, {"friction.mesh_coefficient": 0.05,
                                   "contact.friction_coefficient": 0.05})
    efficiency(friction, speeds_rpm=[500.0], torques=[200.0], positions=8)


KINDS = {"dynamic": dynamic, "quasistatic": quasistatic}

if __name__ == "__main__":
    KINDS[sys.argv[1]]()
