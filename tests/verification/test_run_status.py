"""No silent numbers (issue 8, item 1): absurd inputs end in a status or a one-line error.

Each case a hostile review found (``rvsim simulate --set M=5`` gave a mean TE of 97 473 arcmin
with status ok) either fails validation naming the parameter, or runs and ends with a non-ok
status that ``simulate`` raises and the CLI prints (exit code 1).  The dynamic cases use the
short schedule (0.2 s; 0.4 s until 2026-11-28: they fail there the same way).
"""

import dataclasses
import json

import numpy as np
import pytest

from rvsim.dynamics import simulate
from rvsim.dynamics.result import Result
from rvsim.dynamics.simulate import (ENERGY_RESIDUAL_LIMIT, SPEED_RATIO_LIMIT,
                                     _check_finished_run)
from rvsim.errors import ParameterError, SimulationError
from rvsim.parameters import RV40E, with_values

SHORT = {"operating.duration": 0.2, "operating.speed_ramp_time": 0.05,
         "operating.load_start": 0.05, "operating.load_ramp_end": 0.1,
         "operating.steady_start": 0.15}


@pytest.mark.parametrize("values, field", [
    ({"M": 5}, "clearances.disc_arm_bushing"),
    ({"K": 1e6}, "clearances.crank_arm_bushing"),
    ({"O": 5}, "clearances.crank_support_bushing"),
    ({"K": 1.0, "M": 1.0, "O": 0.5, "N": 0.6}, "clearances.crank_arm_bushing"),
])
def test_clearance_larger_than_the_tooth_height_is_a_parameter_error(values, field):
    with pytest.raises(ParameterError) as info:
        with_values(RV40E, values)
    assert info.value.field == field and "tooth height" in info.value.reason


@pytest.mark.parametrize("values, statuses", [
    # bushings 10,000x softer than the conforming law: the discs rattle and the output slips
    # behind the input (speed ratio -2.09 against 121) and the balance fails with it (residual
    # -3.5 to -8.2 of the input work); which check speaks first follows the rattle, which
    # round-off decides (2026-11-26: 2 of 4 runs with the step changed by 1e-12 each way)
    ({"contact.bushing_stiffness_factor": 1e-4}, ("speed_ratio_off", "energy_imbalance")),
    # mu = 1 with the regularised friction: far beyond the explicit step's stability
    ({"contact.friction_coefficient": 1.0}, ("energy_imbalance",)),
])
def test_absurd_runs_end_with_a_status(values, statuses):
    reducer = with_values(RV40E, {**SHORT, **values})
    with pytest.raises(SimulationError) as info:
        simulate(reducer)
    assert info.value.status in statuses
    result = simulate(reducer, raise_on_failure=False)
    assert result.status == info.value.status == result.summary()["status"]


@pytest.mark.parametrize("duration, words", [
    (1.0, "longer than the start of the steady window"),
    (1.5, "longer than the start of the steady window"),
    (float("inf"), "finite"),
    (float("nan"), "finite"),
    (1e12, "GB"),
])
def test_unusable_durations_are_parameter_errors(duration, words):
    with pytest.raises(ParameterError) as info:
        simulate(RV40E, duration=duration)
    assert info.value.field == "duration" and words in info.value.reason


@pytest.mark.parametrize("args, code, words", [
    (("--set", "M=5"), 2, "clearances.disc_arm_bushing"),
    (("--set", "K=1e6"), 2, "clearances.crank_arm_bushing"),
    (("--set", "O=5"), 2, "clearances.crank_support_bushing"),
    (("--duration", "1"), 2, "duration"),
    (("--duration", "inf"), 2, "duration"),
    (("--duration", "1e12"), 2, "duration"),
    (("--set", "contact.friction_coefficient=1", *[f"--set={k}={v}" for k, v in SHORT.items()]),
     1, "energy_imbalance"),
])
def test_cli_absurd_cases(cli, args, code, words):
    res = cli("simulate", "--json", *args)
    assert res.code == code and words in res.err and res.err.count("\n") == 1
    if code == 1:
        assert json.loads(res.out)["status"] == words


def _finished(ratio_factor: float, residual: float) -> Result:
    """A synthetic finished run: steady speeds in the ratio 121 * ratio_factor."""
    time = np.linspace(0.0, 1.0, 11)
    channels = np.zeros((11, 17))
    channels[:, 0] = time
    channels[:, 2] = 121.0 * ratio_factor          # omega_in
    channels[:, 4] = 1.0                            # omega_out
    energy = {"input_work": 100.0, "kinetic_start": 1.0, "residual": 100.0 * residual,
              "relative_residual": residual}
    return Result(time, channels, np.zeros((11, 2, 40)), 121.0, 0.5, "ok", 10, 0.0, energy)


@pytest.mark.parametrize("ratio_factor, residual, status", [
    (1.0, 0.0, "ok"),
    (1.0, 0.9 * ENERGY_RESIDUAL_LIMIT, "ok"),
    (1.0, -1.1 * ENERGY_RESIDUAL_LIMIT, "energy_imbalance"),
    (1.0 + 0.9 * SPEED_RATIO_LIMIT, 0.0, "ok"),
    (1.0 - 1.1 * SPEED_RATIO_LIMIT, 0.0, "speed_ratio_off"),
    (-6.99 / 121, 0.0, "speed_ratio_off"),
])
def test_finished_run_checks(ratio_factor, residual, status):
    from rvsim.physics._status import STATUS_TEXT

    code, message = _check_finished_run(_finished(ratio_factor, residual))
    assert STATUS_TEXT[code] == status
    assert (message == "") == (status == "ok")


def _energy(input_work: float, kinetic_start: float, residual: float) -> dict:
    from rvsim.physics import _layout as L
    from rvsim.dynamics.simulate import _energy_balance

    e = np.zeros(L.N_ENERGY)
    e[L.E_INPUT], e[L.E_KIN0], e[L.E_KIN1] = input_work, kinetic_start, kinetic_start
    e[L.E_DISSIPATED] = input_work - residual
    return _energy_balance(e)


def test_no_load_run_is_judged_against_its_kinetic_energy():
    # without load the input work is only the damping loss (~1e-6 J): the residual is
    # compared with the kinetic energy instead
    result = _finished(1.0, 0.0)
    result.energy = _energy(2e-6, 0.16, -1e-6)
    assert _check_finished_run(result)[0] == 0
    result = dataclasses.replace(result, energy=_energy(2e-6, 0.16, -0.01))
    assert _check_finished_run(result)[0] != 0
    # and the summary's energy_residual is the figure judged (found by a hostile review: it
    # was over the input work alone, 0.47 on a no-load run whose status was ok)
    assert result.energy["relative_residual"] == pytest.approx(-0.01 / 0.16, rel=1e-12)
    assert _energy(100.0, 1.0, 0.5)["relative_residual"] == pytest.approx(5e-3, rel=1e-12)


def test_a_no_load_run_reports_the_residual_it_is_judged_by():
    result = simulate(with_values(RV40E, {"operating.duration": 1.6,
                                          "operating.load_torque": 0.0}),
                      scheme="implicit-bearings")
    residual = result.summary()["energy_residual"]
    assert result.status == "ok" and abs(residual) < 5e-5     # measured 2.1e-5
    assert residual == result.energy["residual"] / result.energy["kinetic_start"]
