"""The finite-element disc's modes in the dynamic kernel (``flexibility.fe_modes``; docs/model.md
section 17): the arrays the kernel gets, the modal integrator, the contacts' statics, the runs.
Coarse meshes and short runs (the tests stay fast with an empty FE cache)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from tests.conftest import HAS_FE, NO_FE

if not HAS_FE:
    pytest.skip(NO_FE, allow_module_level=True)

from rvsim.physics._fe_contacts import coupled_forces, lagged_forces
from rvsim.physics._fe_modes import (ETA, FORCE, HEADER, OMEGA2, RATE, add_modal_force,
                                     advance_modes, foot_modes, modal_array)
from rvsim.physics.compliance import palmgren_coefficient
from rvsim.errors import ParameterError
from rvsim.parameters import RV40E, with_values

#: coarse disc (h = 4 mm, 2 segments per tooth: 78 segments; meshed and solved in ~1 s)
COARSE = {"A": 1, "flexibility.model": "fe", "flexibility.fe_element_size": 4.0,
          "flexibility.fe_segments_per_tooth": 2, "flexibility.fe_crank": False,
          "flexibility.fe_carrier": False}
SHORT = {"operating.duration": 0.3, "operating.speed_ramp_time": 0.1,
         "operating.load_start": 0.1, "operating.load_ramp_end": 0.2,
         "operating.steady_start": 0.2}


def test_kernel_arrays_hold_the_disc_modes_and_keep_the_statics():
    """Omega^2 of the modal array is the supported disc's own eigenproblem's (solved again here,
    measured equal to 1e-13); for both discs (disc 2 shifted by whole teeth) residual + modes
    give the condensed table to round-off (measured 3e-16); a count beyond the step's bound is
    refused with the largest admissible one (the coarse disc's 12th mode is 30.2 kHz, its 13th
    33.5 kHz: 12 at 5e-6 s)."""
    from rvsim.fe.disc import disc_body, disc_geometry, disc_tables
    from rvsim.fe.modes import MAX_OMEGA_DT, disc_modal_arrays, supported_modes

    r = with_values(RV40E, COARSE)
    tables = disc_tables(r)
    m = tables.shape[1]
    residual, participation, omega = disc_modal_arrays(r, tables, 6, 5e-6)
    modal = modal_array(participation, omega)
    body, supported, _ = disc_body(disc_geometry(r))
    hz = supported_modes(body, r.materials.cycloid_disc.density, supported, 6)[0]
    assert hz[0] == pytest.approx(10.1e3, rel=0.01)
    for disc in range(2):
        assert np.allclose(modal[disc, m + OMEGA2], (2 * math.pi * hz) ** 2, rtol=1e-9)
        shapes = modal[disc, :m]
        static = residual[disc] + (shapes / modal[disc, m + OMEGA2]) @ shapes.T
        assert np.max(np.abs(static - tables[disc])) <= 1e-12 * np.max(tables[disc])
        assert not np.any(modal[disc, m + ETA:])          # at rest
    assert np.array_equal(modal[1, :m], np.roll(modal[0, :m], 20 * 2, axis=0))
    # zero modes: the condensed tables themselves
    same, empty, none = disc_modal_arrays(r, tables, 0, 5e-6)
    assert same is tables and modal_array(empty, none).shape == (2, m + HEADER, 0)
    with pytest.raises(ParameterError) as refused:
        disc_modal_arrays(r, tables, 13, 5e-6)
    assert refused.value.field == "flexibility.fe_modes"
    assert refused.value.reason.endswith("at most 12 at this step")
    assert 2 * math.pi * 30.2e3 * 5e-6 < MAX_OMEGA_DT < 2 * math.pi * 33.5e3 * 5e-6


@pytest.mark.parametrize("omega_dt", [0.3, 1.0])
def test_free_vibration_of_a_modal_coordinate(omega_dt):
    """The kernel's modal step (advance_modes) rings at the symplectic-Euler frequency
    (2 / dt) asin(omega dt / 2) (measured to 1e-5 from the zero crossings of 40 periods): 0.4 %
    above the mode's at omega dt = 0.3, 4.7 % at the admitted bound 1; with damping zeta the
    amplitude decays as exp(-zeta omega t) (the peaks over 6 periods at zeta 0.05: 1.5 % faster
    at omega dt = 0.3, 5.4 % at 1, as (1 - 2 zeta omega dt)^(t / 2 dt) says)."""
    dt = 5e-6
    omega = omega_dt / dt
    modal = modal_array(np.array([[[1.0], [0.5]]]), np.array([omega]))[0]   # 2 segments, 1 mode
    modal[2 + ETA, 0] = 1.0
    steps = int(40 * 2 * math.pi / omega / dt)
    eta = np.empty(steps)
    for n in range(steps):
        advance_modes(modal, dt, 0.0)
        eta[n] = modal[2 + ETA, 0]
    crossings = np.flatnonzero(np.diff(np.sign(eta)) != 0)
    # linear interpolation of each crossing
    times = crossings + eta[crossings] / (eta[crossings] - eta[crossings + 1])
    period = 2.0 * np.mean(np.diff(times)) * dt
    expected = 2.0 / dt * math.asin(omega_dt / 2.0)
    assert 2 * math.pi / period == pytest.approx(expected, rel=2e-4)
    assert expected / omega - 1.0 == pytest.approx(
        {0.3: 0.00376, 1.0: 0.0472}[omega_dt], abs=2e-4)
    # damped: every step multiplies the phase-space area by 1 - 2 zeta omega dt, so the
    # amplitude decays as (1 - 2 zeta omega dt)^(t / 2 dt), exp(-zeta omega t) as dt -> 0
    zeta = 0.05
    modal[2 + ETA, 0], modal[2 + RATE, 0] = 1.0, 0.0
    eta = np.empty(int(6 * 2 * math.pi / expected / dt))
    for n in range(len(eta)):
        advance_modes(modal, dt, zeta)
        eta[n] = modal[2 + ETA, 0]
    peaks = np.flatnonzero((eta[1:-1] > eta[:-2]) & (eta[1:-1] >= eta[2:])) + 1
    rate = -np.polyfit(peaks * dt, np.log(eta[peaks]), 1)[0]
    # (the sampled peaks jitter by a few % at 6 steps per period)
    assert rate == pytest.approx(-math.log(1 - 2 * zeta * omega * dt) / (2 * dt),
                                 rel={0.3: 0.005, 1.0: 0.03}[omega_dt])
    assert rate == pytest.approx(zeta * omega, rel={0.3: 0.02, 1.0: 0.08}[omega_dt])


def test_modes_at_their_static_deflection_give_the_condensed_contacts():
    """Static limit of the contact side: with each mode at eta = Omega^-2 P^T f (f the forces
    of the condensed solution, spread on the segments as the table is read) the Gauss-Seidel
    sweeps on the residual table (with the self-term correction) return the condensed
    solution's forces (measured to 6e-16; without the correction 15 % off on this table, whose
    modal part is as large as its residual)."""
    rng = np.random.default_rng(3)
    m, n_modes = 8, 3
    shapes = 0.5 * rng.normal(size=(m, n_modes))        # M = P Omega^-2 P^T ~ R
    omega2 = np.array([4e9, 9e9, 2.5e10])
    a = rng.uniform(size=(m, m))
    residual = 1e-11 * (a @ a.T + m * np.eye(m))
    table = residual + (shapes / omega2) @ shapes.T
    modal = modal_array(shapes[None], np.sqrt(omega2))[0]
    c = palmgren_coefficient(0.015, RV40E.materials.cycloid_disc, RV40E.materials.pin)
    foot = np.array([0.5, 2.2, 3.9])               # between segment centres
    delta = np.array([2e-6, 1.5e-6, 1e-6])
    exact = np.zeros(3)
    _, _, converged = coupled_forces(table, delta, foot, np.zeros(3), 3, c, np.zeros(3), exact,
                                     np.zeros((0, 0)))
    assert converged

    def weights(u):
        s = (u / (2 * math.pi)) % 1.0 * m - 0.5
        i0 = math.floor(s)
        return i0 % m, (i0 + 1) % m, s - i0

    for a_pin in range(3):
        add_modal_force(modal, *weights(foot[a_pin]), exact[a_pin])
    modal[m + ETA] = modal[m + FORCE] / omega2
    deflection, extra = np.array([foot_modes(modal, *weights(u)) for u in foot]).T
    # contiguous, as the engine passes it: the engine's compiled lagged_forces is loaded from
    # numba's cache instead of a strided copy compiled for this test
    extra = np.ascontiguousarray(extra)
    own = delta - deflection
    for corrected, tol in ((True, 1e-12), (False, None)):
        force, cii = np.zeros(3), np.zeros(3)
        for _ in range(60):
            if corrected:
                lagged_forces(residual, own, foot, force.copy(), 3, c, np.zeros(3), force, cii, extra)
            else:
                lagged_forces(residual, own, foot, force.copy(), 3, c, np.zeros(3), force, cii)
        if corrected:
            assert np.allclose(force, exact, rtol=tol)
        else:
            assert np.max(np.abs(force / exact - 1)) > 0.05


@pytest.fixture(scope="module")
def runs():
    """The short run with 0, 4 or 12 modes at the default 2 kHz samples (``runs(n)``) or
    sampled at every step (``runs(n, every=True)``), each simulated once for the module."""
    from rvsim.dynamics import simulate

    done = {}

    def run(modes, every=False):
        if (modes, every) not in done:
            r = with_values(RV40E, {**COARSE, **SHORT, "flexibility.fe_modes": modes})
            rate = {"sample_rate": 1.0 / 5e-6} if every else {}
            done[modes, every] = simulate(r, raise_on_failure=False, **rate)
        return done[modes, every]

    return run


def test_modes_converge_to_the_condensed_disc_under_slow_loading(runs):
    """The load rises over 0.1 s, the modes ring at >= 10 kHz: the runs are quasi-static and
    the modal disc must give the condensed one's TE (one code path: 0 modes is the condensed
    run itself, measured bit-for-bit against the kernel before the modes; pinned below).
    Measured on this coarse disc, 0 / 4 / 12 modes: TE mean 0.476364324 / 0.476364449 /
    0.476364441 arcmin (2.6e-7 relative), p-p 0.0454362 / 0.0454370 / 0.0454447 (1.9e-4),
    largest pin force 331.29 / 331.42 / 331.41 N (3.7e-4; of the 2 kHz samples; at every step,
    since 2026-11-26: 333.15 / 333.18 / 333.14 N, 1.1e-4), energy residuals -2.4e-5 / -2.5e-5
    / -2.5e-5 of the input work (the modal energies included)."""
    runs = {n: runs(n) for n in (0, 4, 12)}
    base = runs[0].metrics
    assert runs[0].status == "ok"
    for n in (4, 12):
        res = runs[n]
        assert res.status == "ok"
        assert abs(res.energy["relative_residual"]) < 5e-5
        m = res.metrics
        assert m["te_mean_arcmin"] == pytest.approx(base["te_mean_arcmin"], rel=2e-6)
        assert m["te_pp_arcmin"] == pytest.approx(base["te_pp_arcmin"], rel=1e-3)
        assert m["max_pin_force_n"] == pytest.approx(base["max_pin_force_n"], rel=1e-3)
    assert base["te_mean_arcmin"] == pytest.approx(0.476364, rel=2e-5)


def test_too_many_modes_is_one_line(cli):
    result = cli("simulate", "--json", "--set", "A=1", "--set", "flexibility.model=fe",
                 "--set", "flexibility.fe_element_size=4", "--set",
                 "flexibility.fe_segments_per_tooth=2", "--set", "flexibility.fe_crank=false",
                 "--set", "flexibility.fe_carrier=false", "--set", "flexibility.fe_modes=13",
                 *(arg for key, value in SHORT.items() for arg in ("--set", f"{key}={value}")))
    assert result.code == 2
    assert result.err.count("\n") == 1
    assert "flexibility.fe_modes" in result.err and "at most 12" in result.err
    assert result.out == ""


def test_the_quasi_static_engine_does_not_read_the_modes(cli):
    """Static: the modes' statics is the condensed table, so ltca is the same with any n."""
    import json

    args = ("ltca", "--positions", "81", "--json", "--set", "A=1", "--set",
            "flexibility.model=fe", "--set", "flexibility.fe_element_size=4", "--set",
            "flexibility.fe_segments_per_tooth=2", "--set", "flexibility.fe_crank=false",
            "--set", "flexibility.fe_carrier=false")
    plain = json.loads(cli(*args).out)
    modal = json.loads(cli(*args, "--set", "flexibility.fe_modes=4").out)
    drop = ("wall_s",)
    assert {k: v for k, v in plain.items() if k not in drop} == \
        {k: v for k, v in modal.items() if k not in drop}


@pytest.mark.parametrize("modes", [0, 4])
def test_largest_pin_force_is_every_steps_with_coupled_pins(runs, modes):
    """The coupled solve's pin forces (and the modal disc's) feed the window's largest pin force
    at every step: sampled at every step the histories give the same number to the bit, and
    the default 2 kHz samples do not exceed it (the default runs are the test above's)."""
    every, default = runs(modes, every=True), runs(modes)
    assert every.status == default.status == "ok"
    peak = every.metrics["max_pin_force_n"]
    assert peak == every.pin_forces[every.time >= 0.2 - 1e-12].max()
    assert default.metrics["max_pin_force_n"] == peak
    assert default.pin_forces[default.time >= 0.2 - 1e-12].max() <= peak
    assert np.array_equal(every.channel("pin_f_max"), every.pin_forces.max(axis=(1, 2)))
