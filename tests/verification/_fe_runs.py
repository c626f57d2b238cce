"""Shared by the FE verification files: a shorter schedule of the low-speed case on which the
two engines' mean TE are compared (issue 30 item 2: the suite's time)."""

from __future__ import annotations

from rvsim.parameters import with_values
from tests.verification.test_quasistatic import low_speed


def quick_low_speed(reducer, ramp: float = 0.1, steady: float = 0.3, window: float = 0.311):
    """tests/verification/test_quasistatic.py's ``low_speed`` case (its input speed, constant
    load, no load inertia) on a shorter schedule: the speed and the load ramp over ``ramp`` s
    each, the steady window starts at ``steady`` s and lasts ``window`` s (low_speed: 0.2 s,
    0.8 s, 1.245 s, i.e. 2.05 s simulated; 0.61 s with the defaults here).  Both engines' TE
    are compared at the same input angles, so the window need not hold whole periods; it must
    hold the settled run (each test states the difference measured on its case)."""
    return with_values(low_speed(reducer), {
        "operating.speed_ramp_time": ramp, "operating.load_start": ramp,
        "operating.load_ramp_end": 2 * ramp, "operating.steady_start": steady,
        "operating.duration": steady + window})
