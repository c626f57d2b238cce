"""The finite-element crank in the engines (docs/model.md section 17, "Crankshaft"): the
table's rotation, the coupled bushings' energy and its gradient, the dynamic sweep's
contraction, limits, the crank's share of the torsional compliance against Castigliano, and
the two engines against each other.  Coarse crank mesh (6 mm: 7 100 dofs, ~3 s CPU once per
module, the 3 mm default's compliances within 2.5 %)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from tests.conftest import HAS_FE, NO_FE

if not HAS_FE:
    pytest.skip(NO_FE, allow_module_level=True)

from rvsim.physics import _crank_bearings as Cb, _frames as Fr
from rvsim.physics import _layout as L
from rvsim.physics._bearings import conforming_approach
from rvsim.physics._fe_crank import (coupled_arm_forces, compliance_torque, crank_compliance,
                                     lagged_arm_forces, pack_table)
from rvsim.parameters import RV40E, with_values

SIZE = 6.0                       # crank element size [mm]
TORQUE = 300.0
# the crank's figures: the finite-element carrier (on by default with model = fe) left out
BASE = {"flexibility.model": "fe", "flexibility.fe_crank_element_size": SIZE,
        "flexibility.fe_carrier": False}
ANGLES = np.linspace(0.0, 2.0 * np.pi, 4)[:-1]


@pytest.fixture(scope="module")
def solved():
    """RV-40E at 300 N*m, three input angles: FE crank and rigid crank (both model = fe)."""
    from rvsim.dynamics.model import build_model
    from rvsim.quasistatic.transmission import solve_path

    fe = with_values(RV40E, BASE)
    rigid = with_values(RV40E, {**BASE, "flexibility.fe_crank": False})
    load = np.full(ANGLES.size, TORQUE)
    return build_model(fe, 1e-5), solve_path(fe, ANGLES, load), solve_path(rigid, ANGLES, load)


def _crank_state(model, q, crank):
    """Rigid relative positions r (2, 2) of crank ``crank``'s eccentrics and its A(phi)."""
    r = np.empty((2, 2))
    for disc in range(2):
        wl, wu, hx, hy = Fr.arm_station(model.P, model.holes, crank, disc)
        r[disc] = Cb.arm_geometry(model.P, q, np.zeros(L.N_DOF), crank, disc, hx, hy, wl,
                                  wu, *Fr.arm_trig(model.P, q, crank, disc))[:2]
    A = np.empty((4, 4))
    crank_compliance(model.P, q[L.CRANK0 + L.CRANK_STRIDE * crank + 4], A)
    return r, A


def _coupled(P, A, r):
    force, stiffness = np.empty((2, 2)), np.empty((4, 4))
    energy, _, converged = coupled_arm_forces(P, A, r, np.zeros((2, 2)), force, stiffness)
    assert converged
    return force, stiffness, energy


def test_the_table_turns_with_the_crank():
    """A(phi) = R C R^T: the crank-frame table at phi = 0, x and y exchanged at a quarter
    turn, invariants kept at any angle."""
    rng = np.random.default_rng(1)
    m = rng.normal(size=(4, 4))
    c = m @ m.T * 1e-10
    P = np.zeros(L.N_PARAMS)
    P[L.FE_CRANK_XX1:L.FE_CRANK_XX1 + 10] = pack_table(c)
    A = np.empty((4, 4))
    crank_compliance(P, 0.0, A)
    assert np.allclose(A, c, rtol=1e-14, atol=0)
    crank_compliance(P, 0.5 * math.pi, A)
    swap = [1, 0, 3, 2]
    sign = np.array([1, -1, 1, -1])
    assert np.allclose(A, np.outer(sign, sign) * c[np.ix_(swap, swap)], rtol=0, atol=1e-24)
    crank_compliance(P, 0.7, A)
    R = np.array([[math.cos(0.7), -math.sin(0.7)], [math.sin(0.7), math.cos(0.7)]])
    R4 = np.kron(np.eye(2), R)
    assert np.allclose(A, R4 @ c @ R4.T, rtol=0, atol=1e-24)


def test_forces_and_torque_are_the_energy_gradient(solved):
    """U(r, phi) = sum E_k + S^T A S / 2: dU/dr = S and -dU/dphi the compliance torque
    (central differences); the stiffness (I + D A)^-1 D is dS/dr and symmetric."""
    model, fe, _ = solved
    q = fe.q[1].copy()
    r, A = _crank_state(model, q, 0)
    S, stiffness, _ = _coupled(model.P, A, r)
    assert np.abs(S).max() > 1e3
    h = 1e-9
    for i in range(4):
        up, down = r.copy(), r.copy()
        up.flat[i] += h
        down.flat[i] -= h
        (su, _, eu), (sd, _, ed) = _coupled(model.P, A, up), _coupled(model.P, A, down)
        assert (eu - ed) / (2 * h) == pytest.approx(S.flat[i], rel=2e-6)
        assert np.allclose((su - sd).ravel() / (2 * h), stiffness[:, i], rtol=0,
                           atol=1e-4 * np.abs(stiffness).max())
    assert np.array_equal(stiffness, stiffness.T)
    phi = q[L.CRANK0 + 4]
    energies = []
    for dphi in (1e-4, -1e-4):
        B = np.empty((4, 4))
        crank_compliance(model.P, phi + dphi, B)
        energies.append(_coupled(model.P, B, r)[2])
    torque = compliance_torque(A, S)
    assert -(energies[0] - energies[1]) / 2e-4 == pytest.approx(torque, rel=1e-3)


def test_the_dynamic_sweep_contracts_to_the_coupled_solution(solved):
    """One Gauss-Seidel sweep per step: from a perturbed start the error shrinks by a factor
    0.08-0.12 per sweep (measured on the RV-40E at 300 N*m, 6 positions, 3 mm mesh: largest
    0.119), to the Newton solution."""
    model, fe, _ = solved
    factors = []
    for k in range(ANGLES.size):
        for crank in range(2):
            r, A = _crank_state(model, fe.q[k], crank)
            star = _coupled(model.P, A, r)[0]
            s = 1.2 * star + np.array([[50.0, -80.0], [-60.0, 40.0]])
            errors = []
            for _ in range(6):
                new, series = np.empty((2, 2)), np.empty(2)
                lagged_arm_forces(model.P, A, r, s, new, series)
                errors.append(np.abs(new - star).max())
                s = new
            factors += [errors[i + 1] / errors[i] for i in range(1, 5)]
            assert errors[-1] < 1e-4 * errors[0]
            # the damping's stiffness: the bushing's tangent in series with its own crank
            # compliance along its force, 1 / (d delta / dF + n^T A_kk n)
            for k in range(2):
                f = math.hypot(*s[k])
                n = s[k] / f
                law = conforming_approach(f, *(model.P[i] for i in (L.ARM_J1, L.ARM_A1,
                                                                     L.ARM_J2, L.ARM_A2,
                                                                     L.ARM_CB)))[1]
                own = n @ A[2 * k:2 * k + 2, 2 * k:2 * k + 2] @ n
                assert series[k] == pytest.approx(1.0 / (law + own), rel=1e-6)
    assert 0.05 < max(factors) < 0.13


def test_crank_adds_its_complementary_energy_to_the_output_lag(solved):
    """Castigliano: the output turns further by sum_j S_j^T A_j S_j / T (the crank's
    complementary energy per unit torque, from the table and the bushing forces): measured
    41.52 urad against 41.54 (ratio 1.0005, 6 mm mesh), a third of the rigid-crank reducer's
    compliance."""
    model, fe, rigid = solved
    lag = rigid.q[:, L.CARRIER] - fe.q[:, L.CARRIER]
    estimate = np.zeros(ANGLES.size)
    for k in range(ANGLES.size):
        for crank in range(2):
            r, A = _crank_state(model, fe.q[k], crank)
            s = _coupled(model.P, A, r)[0].ravel()
            estimate[k] += s @ A @ s / TORQUE
    assert lag == pytest.approx(estimate, rel=1.5e-3)
    assert lag.mean() == pytest.approx(41.5e-6, rel=0.01)
    # the tangent stiffness (ltca's, 3.40e6 -> 2.31e6 N*m/rad) is the rigid crank's in series
    # with the same compliance, sum S^T A S / T^2 (forces proportional to the torque)
    assert rigid.torsional_stiffness.mean() == pytest.approx(3.404e6, rel=0.01)
    assert fe.torsional_stiffness.mean() == pytest.approx(2.313e6, rel=0.01)
    assert 1.0 / fe.torsional_stiffness == pytest.approx(
        1.0 / rigid.torsional_stiffness + estimate / TORQUE, rel=2e-3)


def _patched_table(monkeypatch, table):
    import rvsim.dynamics.model as model

    monkeypatch.setattr(model, "_fe_crank_constants", lambda r: pack_table(table))


def test_a_nearly_rigid_table_gives_the_rigid_crank(solved, monkeypatch):
    from rvsim.quasistatic.transmission import solve_path

    _, fe, rigid = solved
    crank = with_values(RV40E, BASE)
    _patched_table(monkeypatch, 1e-8 * np.eye(4) * 6e-10)
    stiff = solve_path(crank, ANGLES, np.full(ANGLES.size, TORQUE))
    assert stiff.q[:, L.CARRIER] == pytest.approx(rigid.q[:, L.CARRIER], rel=1e-6, abs=1e-11)


def test_without_coupling_the_crank_is_a_series_compliance(monkeypatch):
    """An isotropic table without coupling, c I, is the same as switch C's series compliance
    c (the bushing law with cb = c)."""
    import rvsim.dynamics.model as model
    from rvsim.quasistatic.transmission import solve_path

    c = 6.4e-10
    _patched_table(monkeypatch, c * np.eye(4))
    crank = solve_path(with_values(RV40E, BASE), ANGLES, np.full(ANGLES.size, TORQUE))
    monkeypatch.setattr(model, "ring_compliance", lambda *args: c)
    series = solve_path(with_values(RV40E, {**BASE, "flexibility.fe_crank": False,
                                            "flexibility.arm_bushing": True}),
                        ANGLES, np.full(ANGLES.size, TORQUE))
    assert crank.q == pytest.approx(series.q, rel=0, abs=1e-11)


def test_the_engines_agree_on_the_mean_te_with_the_fe_crank():
    """Dynamic 0.3 s run (steady window 0.1 s) against the quasi-static curve: measured
    0.5933 against 0.5945 arcmin (6 mm crank); energy balance closes (status ok)."""
    import rvsim

    r = with_values(RV40E, {**BASE, "operating.duration": 0.3,
                            "operating.speed_ramp_time": 0.1, "operating.load_start": 0.1,
                            "operating.load_ramp_end": 0.2, "operating.steady_start": 0.2})
    dynamic = rvsim.simulate(r).summary()
    quasi = rvsim.ltca(r, positions=24, allow_aliasing=True).summary()
    assert dynamic["status"] == "ok" and quasi["status"] == "ok"
    assert dynamic["te_mean_arcmin"] == pytest.approx(quasi["te_mean_arcmin"], rel=4e-3)
    assert quasi["te_mean_arcmin"] == pytest.approx(0.5945, rel=2e-3)
