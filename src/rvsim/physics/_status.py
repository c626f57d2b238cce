"""The one table of status codes of both engines (issue 31 step 10; docs/architecture.md).

A compiled run returns an integer code: the dynamic kernel and the checks of a finished run
(:mod:`rvsim.dynamics.simulate`, docs/model.md section 9) for a run, the quasi-static solver
and :mod:`rvsim.quasistatic.transmission` for each point of a path.  Every code is defined
here once, with the status string a result and the JSON / CSV files carry (``name``) and the
words a stop message uses (``message``).  Both engines use the same code for the same
meaning ("diverged", "runaway_penetration"); the numbers are internal (never written to a
file), the strings are public and must not change.  The compiled code reads the integer
constants only (frozen into the machine code at compile time); :data:`STATUS_TEXT` and
:data:`STATUS_MESSAGE` are for the Python side.
"""

from __future__ import annotations

STATUS_OK = 0
#: a coordinate or a force became NaN or infinite (both engines)
STATUS_NONFINITE = 1
#: a contact penetrated beyond ``P[PEN_LIMIT]`` (both engines)
STATUS_PENETRATION = 2
#: the finished run's energy balance is off (dynamic: rvsim.dynamics.simulate)
STATUS_ENERGY = 3
#: the finished run's steady speed ratio is off the design ratio (dynamic)
STATUS_SPEED_RATIO = 4
#: the Newton / friction iteration of a point did not converge (quasi-static)
STATUS_NOT_CONVERGED = 5
#: a point's condensed stiffness could not be inverted (quasi-static: solve_path; the
#: compliance budget's word)
STATUS_SINGULAR = 6

#: every status: (code, name, message); the names are the public status strings
STATUSES = (
    (STATUS_OK, "ok", "ok"),
    (STATUS_NONFINITE, "diverged", "diverged"),
    (STATUS_PENETRATION, "runaway_penetration", "runaway penetration"),
    (STATUS_ENERGY, "energy_imbalance", "energy imbalance"),
    (STATUS_SPEED_RATIO, "speed_ratio_off", "speed ratio off"),
    (STATUS_NOT_CONVERGED, "not_converged", "not converged"),
    (STATUS_SINGULAR, "singular_stiffness", "singular stiffness"),
)
#: code -> public status string
STATUS_TEXT = {code: name for code, name, _ in STATUSES}
#: code -> the words of a stop message ("simulation stopped at t = ...: <message>")
STATUS_MESSAGE = {code: message for code, _, message in STATUSES}
