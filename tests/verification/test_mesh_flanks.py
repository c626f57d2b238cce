"""The sun-planet mesh acts on both flanks (docs/model.md section 3, docs/decisions.md).

With zero backlash a crank pressed towards the sun by r touches both flanks with the same
approach r sin(alpha_w): equal forces, no torque, the energy of two springs; a small turn of
the crank then loads one flank more than the other, continuously (no switch).  Measured
2026-11-22: the two flanks' force sum equals 2 k r sin(alpha_w) within 6e-12 (round-off of
the centre-distance change; tolerance 1e-9), the stiffness matrix equals central differences of
the forces within 2.9e-6 of its largest entry (the line-of-centres curvature left out;
tolerance 1e-5).
"""

import functools
import math

import numpy as np
import pytest

from rvsim.physics import _layout as L
from rvsim.physics._gear_mesh import gear_mesh
from rvsim.dynamics.model import build_model
from rvsim.parameters import RV40E



@functools.cache
def _model():
    """The RV-40E's model, built at the first test (not at collection: building it calls
    compiled functions, which the warm-up compiles while the tests are collected)."""
    return build_model(RV40E, 1e-5)


B = L.CRANK0                       # crank 0


def _mesh(q, want_stiffness=False):
    Q = np.zeros(L.N_DOF)
    K = np.zeros((L.N_DOF, L.N_DOF) if want_stiffness else (0, 0))
    line = q[L.CARRIER] + _model().crank_angles[0]
    out = gear_mesh(_model().P, q, np.zeros(L.N_DOF), Q, K, want_stiffness, 0,
                    _model().crank_angles[0],
                    _model().mesh_phase[0], 0.0, 0.0, 1.0, 0.0,   # one tooth pair held
                    math.cos(line), math.sin(line))
    return out, Q, K


def _pressed(inward, turn=0.0):
    q = _model().q0.copy()
    for node in (0, 2):             # both support nodes: the gear's station moves as well
        q[B + node] -= inward       # crank 0 sits on +x: towards the sun is -x
    q[B + 4] += turn
    return q


def test_a_crank_pressed_towards_the_sun_touches_both_flanks_equally():
    inward = 1e-6
    (force, torque, energy, _, stiffness, deflection, _, _), Q, _ = _mesh(_pressed(inward))
    approach = inward * _model().P[L.SIN_AW]
    assert force == pytest.approx(2.0 * stiffness * approach, rel=1e-9)   # measured 6e-12
    assert abs(torque) < 1e-12 * force * _model().P[L.RB1]
    assert energy == pytest.approx(stiffness * approach ** 2, rel=1e-9)
    assert deflection == pytest.approx(math.sqrt(2.0) * approach, rel=1e-9)
    assert abs(Q[B + 4]) < 1e-12 * force * _model().P[L.RB2]           # no net moment on the planet
    # pushed back out along +x by the radial components of both flank forces
    assert Q[B] + Q[B + 2] == pytest.approx(force * _model().P[L.SIN_AW], rel=1e-9)


def test_turning_the_pressed_crank_shifts_load_between_the_flanks_continuously():
    inward = 1e-6
    forces = []
    for turn in np.linspace(-2e-5, 2e-5, 41):
        out, Q, _ = _mesh(_pressed(inward, turn))
        forces.append((out[0], out[1]))
    total, torque = np.array(forces).T
    assert np.all(np.diff(torque) > 0.0) or np.all(np.diff(torque) < 0.0)  # monotonic
    assert np.max(np.abs(np.diff(torque))) < 3.0 * np.abs(np.diff(torque)).min()  # no jump


def test_stiffness_matrix_is_the_derivative_of_the_forces_on_both_flanks():
    q = _pressed(1e-6, 3e-6)
    _, _, K = _mesh(q, True)
    h = 1e-10
    numeric = np.zeros((L.N_DOF, L.N_DOF))
    for i in range(L.N_DOF):
        dq = np.zeros(L.N_DOF)
        dq[i] = h
        numeric[:, i] = -(_mesh(q + dq)[1] - _mesh(q - dq)[1]) / (2.0 * h)
    crank = slice(B, B + 5)
    # the curvature of the line-of-centres angle is left out of K (docs/model.md section 12):
    # measured 2.9e-6 of the largest entry
    assert np.max(np.abs(K[crank, crank] - numeric[crank, crank])) < 1e-5 * np.abs(K).max()
