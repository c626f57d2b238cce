"""The compiled kernel's pin gaps equal the geometry's (issue 8, item 7: one implementation).

The kernel's gaps are read back from its contact forces: with every pin pushed into the disc
by a known amount (profile offset reduced by 1 mm), no damping and no body compliance, the
Palmgren law F = (delta / C)**(1/0.9) gives delta = C F**0.9 exactly.  Both its robust foot
search (first step) and its tracked Newton step (next step, the disc moved a little) are
compared with :func:`rvsim.geometry.pin_gaps` at several poses of a modified disc with runout
and random pin position errors.
"""

import numpy as np
import pytest

from rvsim.dynamics import _layout as L
from rvsim.dynamics._contact_law import EXPONENT
from rvsim.dynamics._kernel import pin_contacts
from rvsim.dynamics.model import build_model
from rvsim.geometry import nominal_disc_pose, pin_gaps
from rvsim.parameters import RV40E, with_values

PUSH = 1e-3  # every pin pushed 1 mm into the disc [m]
REDUCER = with_values(RV40E, {"I": 0.02, "J": 0.03, "errors.rotation_modification": 0.5,
                              "errors.disc_runout": 0.014, "errors.pin_position_tolerance": 0.005,
                              "errors.pin_position_seed": 11})


def _kernel_gaps(model, q, disc, step, u, next_eval):
    P = model.P.copy()
    P[L.PROFILE_OFFSET] -= PUSH     # a thinner disc profile: every gap 1 mm smaller
    P[L.PIN_CB] = 0.0
    P[L.ZETA] = 0.0
    P[L.MU] = 0.0
    n = model.pins.shape[0]
    pin_angle = 2.0 * np.pi * np.arange(n) / n
    forces = np.zeros((2, n))
    elastic = np.zeros((2, n))
    pin_contacts(P, q, np.zeros(L.N_DOF), np.zeros(L.N_DOF), np.zeros((0, 0)), disc,
                 model.pins, pin_angle, u, next_eval, step, forces, elastic, model.fe,
                 np.zeros((2, 0, 0)))
    assert np.all(forces[disc] > 0.0)           # every pin was evaluated and in contact
    return PUSH - P[L.PIN_C] * forces[disc] ** EXPONENT


@pytest.mark.parametrize("disc", [0, 1])
@pytest.mark.parametrize("crank_angle, turn, shift", [
    (0.0, 0.0, (0.0, 0.0)), (0.7, 2e-4, (3e-6, -2e-6)), (2.9, -3e-4, (-5e-6, 4e-6)),
    (-1.3, 1e-4, (1e-6, 6e-6))])
def test_kernel_gaps_equal_geometry_gaps(disc, crank_angle, turn, shift):
    model = build_model(REDUCER, 1e-5)
    n = model.pins.shape[0]
    u = np.zeros((2, n))
    next_eval = np.zeros((2, n), dtype=np.int64)
    q = model.q0.copy()
    d = L.DISC0 + L.DISC_STRIDE * disc
    worst = 0.0
    for step, scale in ((0, 1.0), (1, 1.02)):     # robust search, then one tracked step
        x, y, theta = nominal_disc_pose(REDUCER, crank_angle, disc)
        q[d:d + 3] = x + scale * shift[0], y + scale * shift[1], theta + scale * turn
        kernel = _kernel_gaps(model, q, disc, step, u, next_eval)
        geometry = pin_gaps(REDUCER, crank_angle, disc=disc, extra_rotation=scale * turn,
                            offset=(scale * shift[0], scale * shift[1]))
        worst = max(worst, float(np.max(np.abs(kernel - geometry))))
    assert worst < 1e-12  # metres (measured: at most 5e-14)
