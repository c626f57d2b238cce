"""Synthetic bench recordings made by rvsim itself (known parameters): the quasi-static model's
curves sampled the way a bench samples them, with encoder quantisation, noise and arbitrary
encoder zeros.  They verify the import and the analyses (tests/verification/test_testrig.py)
and make the example in docs/examples/.

Columns and signs are those of :data:`rvsim.testrig.recording.DEFAULT_COLUMNS`: angles in deg;
torques positive in the sense of the input's rotation (output torque = the torque the output
delivers to the brake).
"""

from __future__ import annotations

import math

import numpy as np

from ..analysis import catalogue
from ..parameters import Reducer

__all__ = ["te_recording", "reversal_recording", "quantise"]

_DEG = 180.0 / math.pi
_ARCSEC = math.pi / 648000.0


def quantise(angle, counts_per_revolution: float | None):
    """An angle [rad] as an incremental encoder reports it (whole counts), or unchanged."""
    if not counts_per_revolution:
        return angle
    step = 2.0 * math.pi / counts_per_revolution
    return np.floor(np.asarray(angle) / step) * step


def _te_of(reducer: Reducer, torque: float, points: int):
    """Periodic TE of the model against the nominal output angle (a periodic cubic spline
    through the quasi-static solution at ``points`` positions)."""
    from scipy.interpolate import CubicSpline

    from ..quasistatic import ltca

    run = ltca(reducer, torque=torque, positions=points)
    phi = np.r_[run.input_angle / run.ratio, 2.0 * math.pi]
    return CubicSpline(phi, np.r_[run.te, run.te[0]], bc_type="periodic"), run


def te_recording(reducer: Reducer, *, torque: float | None = None, revolutions: float = 1.2,
                 backward: bool = False, samples_per_revolution: int = 20_000,
                 input_speed_rpm: float = 15.0, efficiency: float = 0.85,
                 counts_in: float | None = 2 ** 20, counts_out: float | None = 2 ** 23,
                 noise_arcsec: float = 0.1, zero_in: float = 1.234, zero_out: float = -0.567,
                 start: float = 0.3, model_points: int = 4096, seed: int = 0):
    """A constant-speed TE recording (pandas DataFrame, default columns): ``revolutions``
    output revolutions forward, then (``backward``) as many back; the model is the
    quasi-static TE under ``torque`` (resisting the motion); returns (frame, model runs by
    direction)."""
    import pandas as pd

    torque = reducer.operating.load_torque if torque is None else float(torque)
    ratio = reducer.ratio
    rng = np.random.default_rng(seed)
    n = int(round(revolutions * samples_per_revolution))
    step = 2.0 * math.pi / samples_per_revolution
    runs, parts = {}, []
    for sign in ((1, -1) if backward else (1,)):
        spline, runs[sign] = _te_of(reducer, sign * torque, model_points)
        begin = start if sign > 0 else start + n * step
        phi = begin + sign * step * np.arange(n)
        parts.append((phi, spline(np.mod(phi, 2.0 * math.pi)), sign))
    phi = np.concatenate([p for p, _, _ in parts])
    te = np.concatenate([t for _, t, _ in parts])
    sense = np.concatenate([np.full(p.size, s) for p, _, s in parts])
    omega_out = input_speed_rpm * 2.0 * math.pi / 60.0 / ratio
    time = np.arange(phi.size) * step / omega_out
    theta_in = quantise(ratio * phi + zero_in, counts_in)
    theta_out = quantise(phi - te + zero_out + rng.normal(0.0, noise_arcsec * _ARCSEC,
                                                          phi.size), counts_out)
    out_torque = sense * torque
    frame = pd.DataFrame({
        "time_s": time, "input_angle_deg": theta_in * _DEG, "output_angle_deg": theta_out * _DEG,
        "input_torque_nm": out_torque / (ratio * efficiency), "output_torque_nm": out_torque,
        "oil_temperature_c": np.full(phi.size, 40.0)})
    return frame, runs


def _side_angle(branch, sign: float, torque: np.ndarray) -> np.ndarray:
    """Angle of one model branch at ``torque`` values on its ``sign`` side of zero: linear
    between its samples, its first segment extended towards zero (as catalogue.angle_at)."""
    t, a = catalogue.branch_side(*branch, sign)
    x = sign * t
    value = np.interp(sign * torque, x, a)
    near = sign * torque < x[0]
    slope = (a[1] - a[0]) / (x[1] - x[0])
    value[near] = a[0] + slope * (sign * torque[near] - x[0])
    return value


def reversal_recording(reducer: Reducer, *, rated_torque: float | None = None,
                       samples: int = 20_000, duration_s: float = 60.0,
                       torque_noise_nm: float = 0.2, counts_out: float | None = 2 ** 23,
                       noise_arcsec: float = 0.1, zero_in: float = 0.42,
                       zero_out: float = 2.5, seed: int = 1):
    """A torque-reversal recording (input locked): torque 0 -> -rated -> 0 -> +rated -> 0 ->
    -rated linear in time, the output angle of the quasi-static model's loop; returns
    (frame, model result)."""
    import pandas as pd

    from ..quasistatic import hysteresis

    model = hysteresis(reducer, rated_torque=rated_torque)
    rated = model.rated_torque
    rng = np.random.default_rng(seed)
    ends = np.array([0.0, -rated, 0.0, rated, 0.0, -rated])
    s = np.linspace(0.0, 5.0, samples)
    torque = np.interp(s, np.arange(6.0), ends)
    rising = np.r_[np.diff(torque) > 0, False]
    rising[-1] = rising[-2]
    t, a, b, _ = catalogue.loop_arrays(model)
    up, down = catalogue.loop_branches(t, a, b)
    angle = np.empty(samples)
    for branch, mask in ((up, rising), (down, ~rising)):
        for sign in (1.0, -1.0):
            pick = mask & ((torque > 0) if sign > 0 else (torque <= 0))
            angle[pick] = _side_angle(branch, sign, torque[pick])
    frame = pd.DataFrame({
        "time_s": s / 5.0 * duration_s,
        "input_angle_deg": np.full(samples, zero_in * _DEG),
        "output_angle_deg": quantise(angle + zero_out + rng.normal(
            0.0, noise_arcsec * _ARCSEC, samples), counts_out) * _DEG,
        "output_torque_nm": torque + rng.normal(0.0, torque_noise_nm, samples)})
    return frame, model
