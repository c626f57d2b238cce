"""The one driver of the dynamic model: :func:`simulate`."""

from __future__ import annotations

import time as _time

import numpy as np

from ..errors import ParameterError, SimulationError
from ..parameters import Reducer, validate
from . import _layout as L
from ._kernel import integrate
from .model import build_model
from .result import Result

__all__ = ["simulate", "decompose_te", "DEFAULT_TIME_STEP", "DEFAULT_SAMPLE_RATE"]

#: integration step [s]; docs/model.md and the convergence test justify it
DEFAULT_TIME_STEP = 1e-5
#: rate at which histories are stored [Hz]
DEFAULT_SAMPLE_RATE = 2000.0


def simulate(reducer: Reducer, *, duration: float | None = None,
             time_step: float = DEFAULT_TIME_STEP, sample_rate: float = DEFAULT_SAMPLE_RATE,
             raise_on_failure: bool = True) -> Result:
    """Simulate ``reducer`` from rest over ``duration`` (default: its operating duration).

    Returns a :class:`Result`.  A run that diverges or whose pins penetrate more than 0.2 mm
    raises :class:`~rvsim.errors.SimulationError` (or, with ``raise_on_failure=False``, returns
    the partial result with its ``status``).
    """
    validate(reducer)
    duration = reducer.operating.duration if duration is None else duration
    if not duration > 0:
        raise ParameterError("duration", "must be positive")
    if not 0 < time_step <= 1e-3:
        raise ParameterError("time_step", "must be in (0, 1e-3] s")
    model = build_model(reducer, time_step)
    n_steps = int(round(duration / time_step))
    sample_every = max(1, int(round(1.0 / (sample_rate * time_step))))
    n_samples = n_steps // sample_every + 1
    channels = np.zeros((n_samples, L.N_CHANNELS))
    pin_forces = np.zeros((n_samples, 2, reducer.cycloid.pin_count))
    energy = np.zeros(L.N_ENERGY)
    q = model.q0.copy()
    v = np.zeros(L.N_DOF)
    start = _time.perf_counter()
    status, steps = integrate(model.P, q, v, n_steps, sample_every, model.pins, model.holes,
                              model.crank_angles, model.mesh_phase, channels, pin_forces, energy)
    wall = _time.perf_counter() - start
    rows = steps // sample_every + (1 if status == L.STATUS_OK else 0)
    rows = min(rows, n_samples)
    result = Result(time=channels[:rows, L.CH_TIME].copy(), channels=channels[:rows],
                    pin_forces=pin_forces[:rows], ratio=reducer.ratio,
                    steady_start=reducer.operating.steady_start,
                    status=L.STATUS_TEXT[status], steps=int(steps), wall_s=wall,
                    energy=_energy_balance(energy), reducer_name=reducer.name)
    if status != L.STATUS_OK and raise_on_failure:
        raise SimulationError(result.status, f"simulation stopped at t = {steps * time_step:.4f}"
                              f" s: {result.status.replace('_', ' ')}")
    return result


def _energy_balance(e: np.ndarray) -> dict[str, float]:
    """Energy terms over the steady window [J] and the relative residual of the balance
    W_in = W_out + D + dKE + dPE - W_parametric."""
    terms = {
        "input_work": e[L.E_INPUT], "output_work": e[L.E_OUTPUT],
        "dissipated": e[L.E_DISSIPATED], "parametric_work": e[L.E_PARAMETRIC],
        "kinetic_change": e[L.E_KIN1] - e[L.E_KIN0],
        "potential_change": e[L.E_POT1] - e[L.E_POT0],
    }
    residual = (terms["input_work"] - terms["output_work"] - terms["dissipated"]
                - terms["kinetic_change"] - terms["potential_change"] + terms["parametric_work"])
    terms = {k: float(v) for k, v in terms.items()}
    terms["residual"] = float(residual)
    terms["relative_residual"] = (float(residual / terms["input_work"])
                                  if terms["input_work"] else float("nan"))
    return terms


def decompose_te(reducer: Reducer, **options) -> dict[str, float]:
    """Split the steady mean TE into its elastic part and the part clearances take up.

    The elastic part is the mean TE of the same reducer with every error, modification and
    clearance set to zero (same load, flexibility switches and contact law): the wind-up of
    the loaded parts.  The rest, ``lost_motion``, is what the errors, modifications and
    clearances add once the load has taken them up.  Two simulations; ``options`` go to
    :func:`simulate`.  Errors and clearances interact with stiffness (a modified profile
    shares its load among fewer pins), so the split is a first-order reading, not an identity.
    """
    import dataclasses

    from ..parameters import Clearances, Errors

    total = simulate(reducer, **options).metrics["te_mean_arcmin"]
    perfect = dataclasses.replace(reducer, errors=Errors(), clearances=Clearances())
    elastic = simulate(perfect, **options).metrics["te_mean_arcmin"]
    return {"te_mean_arcmin": total, "te_elastic_arcmin": elastic,
            "te_lost_motion_arcmin": total - elastic}
