"""The one driver of the dynamic model: :func:`simulate`."""

from __future__ import annotations

import math
import numbers

import numpy as np

from .._cache_guard import RunClock
from .._stopping import check_stop
from ..errors import ParameterError, SimulationError
from ..parameters import Reducer, validate
from ..physics import _layout as L
from ..physics._status import (STATUS_ENERGY, STATUS_MESSAGE, STATUS_OK, STATUS_SPEED_RATIO,
                               STATUS_TEXT)
from ._kernel import COUNT_ROW, integrate, new_state
from ..physics._pins import nothing_carried
from ._implicit_bearings import new_work
from .model import EXPLICIT, IMPLICIT_BEARINGS, SCHEMES, build_model
from .result import Result

__all__ = ["simulate", "decompose_te", "DEFAULT_TIME_STEP", "DEFAULT_SAMPLE_RATE",
           "SCHEMES", "default_time_step", "check_scheme", "check_run_options", "MAX_TIME_STEP", "CHUNK_STEPS", "MAX_HISTORY_BYTES", "MAX_STEPS", "ENERGY_RESIDUAL_LIMIT", "SPEED_RATIO_LIMIT"]

#: integration step [s] of the default scheme ("explicit"); docs/model.md and the convergence
#: test justify it (5e-6 s since the conforming bushings of issue 10, about 3x stiffer than the
#: Palmgren ones before).  The scheme "implicit-bearings" has its own (model.SCHEMES, 2e-5 s)
DEFAULT_TIME_STEP = SCHEMES[EXPLICIT]
#: largest accepted step [s]: far above the stability limit (about 1e-5 s), so a larger value
#: can only be a typo
MAX_TIME_STEP = 1e-3
#: rate at which histories are stored [Hz]
DEFAULT_SAMPLE_RATE = 2000.0
#: steps per call of the compiled driver (0.05 s simulated at the default step, about 20 ms of
#: wall time): Ctrl-C and the progress bar act between calls
CHUNK_STEPS = 5000
#: memory the histories of one run may take [bytes]
MAX_HISTORY_BYTES = 2 * 1024 ** 3
#: steps one run may take (duration / time_step): about 30-50 minutes of one core at 1.7-3 us
#: per step (docs/benchmarks.md), and far inside the kernel's 64-bit step counter
MAX_STEPS = 10 ** 9
#: largest |energy residual| / input work over the steady window of a trusted run (healthy runs:
#: at most 1.19e-4 over the paper's 36 runs; docs/model.md section 9)
ENERGY_RESIDUAL_LIMIT = 1e-2
#: largest relative deviation of the steady speed ratio from the design ratio
SPEED_RATIO_LIMIT = 0.05


def default_time_step(scheme: str = EXPLICIT) -> float:
    """The step [s] a run of the integration ``scheme`` takes unless told otherwise
    (ParameterError for an unknown scheme)."""
    check_scheme(scheme)
    return SCHEMES[scheme]


def check_scheme(scheme) -> None:
    """ParameterError unless ``scheme`` names an integration scheme (:data:`SCHEMES`)."""
    if not (isinstance(scheme, str) and scheme in SCHEMES):
        raise ParameterError("scheme", f"must be one of {', '.join(SCHEMES)} (got {scheme!r})")


def check_run_options(reducer: Reducer, duration: float | None = None,
                      time_step: float | None = None,
                      sample_rate: float = DEFAULT_SAMPLE_RATE, scheme: str = EXPLICIT) -> None:
    """ParameterError unless :func:`simulate` can run ``reducer`` with these options (scheme,
    step, sampling, a finite duration past the steady window whose histories fit in memory);
    a study checks every run with it before anything is simulated.  ``time_step`` None: the
    scheme's default."""
    for name, value in (("duration", duration), ("time_step", time_step),
                        ("sample_rate", sample_rate)):
        # a number, not a string that float() would read, nor a one-element array
        if value is not None and (isinstance(value, bool) or not isinstance(value,
                                                                            numbers.Real)):
            raise ParameterError(name, f"must be a number (got {value!r})")
    duration = float(reducer.operating.duration if duration is None else duration)
    check_scheme(scheme)            # also where a step is given
    time_step = SCHEMES[scheme] if time_step is None else time_step
    f = reducer.flexibility
    if scheme == IMPLICIT_BEARINGS and f.model == "fe":
        raise ParameterError("scheme", "implicit-bearings takes the closed-form bodies only "
                             "(flexibility.model = closed-form): the bearings' stiffness it "
                             "assembles would switch the finite-element bodies' solves to the "
                             "quasi-static engine's; use the explicit scheme")
    if scheme == IMPLICIT_BEARINGS and reducer.layout.single_stage:
        raise ParameterError("scheme", "implicit-bearings is made for the RV reducer's crank "
                             "bearings; a single-stage drive's step is set by other elements "
                             "(its output pins and input coupling stay explicit: diverged at "
                             "2e-5 s), so use the explicit scheme")
    if (f.fe_modes > 0 and f.fe_disc_holes and f.cycloid_disc and f.model == "fe"
            and not reducer.layout.single_stage):
        raise ParameterError("flexibility.fe_modes", "the disc's modes are built with its crank "
                             "holes held; set flexibility.fe_disc_holes = false to integrate "
                             "them (docs/decisions.md)")
    if not 0 < time_step <= MAX_TIME_STEP:
        raise ParameterError("time_step", f"must be in (0, {MAX_TIME_STEP:g}] s (got "
                             f"{time_step:g})")
    if not (math.isfinite(sample_rate) and sample_rate > 0):
        raise ParameterError("sample_rate", f"must be a positive number of Hz (got "
                             f"{sample_rate:g})")
    if not math.isfinite(duration):
        raise ParameterError("duration", f"must be a finite number of seconds (got {duration:g})")
    steady = reducer.operating.steady_start
    rate = min(sample_rate, 1.0 / time_step)
    if not duration >= steady + 2.0 / rate:
        raise ParameterError("duration", f"must be longer than the start of the steady window "
                             f"(operating.steady_start = {steady:g} s), where the TE metrics "
                             f"are taken, by at least two samples (got {duration:g} s)")
    per_second = rate * (L.N_CHANNELS + 2 * reducer.cycloid.pin_count) * 8
    if duration * per_second > MAX_HISTORY_BYTES:
        need = duration * per_second / 1e9
        size = f"{need:.3g} GB" if math.isfinite(need) else "more memory than any machine has"
        raise ParameterError("duration", f"{duration:g} s of histories at {rate:g} Hz need "
                             f"{size}, more than the {MAX_HISTORY_BYTES / 1e9:.3g} GB limit "
                             f"(at most {MAX_HISTORY_BYTES / per_second:.0f} s at this sample "
                             "rate)")
    # after the histories' limit, which names a duration too long for any step
    if duration / time_step > MAX_STEPS:
        # enough digits that a count just above the limit shows as above it
        raise ParameterError("time_step", f"{duration:.10g} s at {time_step:.10g} s per step "
                             f"is {duration / time_step:.10g} steps, more than the "
                             f"{MAX_STEPS:.0e} a run may take (at least "
                             f"{duration / MAX_STEPS:.10g} s per step for this duration)")


def simulate(reducer: Reducer, *, duration: float | None = None,
             time_step: float | None = None, sample_rate: float = DEFAULT_SAMPLE_RATE,
             raise_on_failure: bool = True, progress: bool = False,
             scheme: str = EXPLICIT) -> Result:
    """Simulate ``reducer`` from rest over ``duration`` (default: its operating duration).

    ``scheme``: "explicit" (default; semi-implicit Euler, :data:`DEFAULT_TIME_STEP`) or
    "implicit-bearings" (the bearings' stiffness taken linearly implicitly, so that the step
    is no longer set by the crank nodes on their bearings: 2e-5 s by default, about 40 % of
    the CPU time; closed-form RV reducers only; docs/model.md section 9).  ``time_step`` None: the
    scheme's default.

    Returns a :class:`Result`.  A run that diverges, whose pins penetrate more than 0.2 mm, or
    that ends in a physically absurd state (energy balance off by more than
    :data:`ENERGY_RESIDUAL_LIMIT` of the input work, steady speed ratio more than
    :data:`SPEED_RATIO_LIMIT` away from the design ratio) raises
    :class:`~rvsim.errors.SimulationError` (or, with ``raise_on_failure=False``, returns the
    result with its ``status``).  ``progress=True`` shows a progress bar on stderr.  The
    result's ``wall_s`` is the run's wall time without numba compiling the kernel (a first run
    after an install; :func:`rvsim._cache_guard.compile_seconds` has that time).  The
    compiled loop returns every :data:`CHUNK_STEPS` steps, so Ctrl-C (KeyboardInterrupt)
    stops a run within a fraction of a second.
    """
    validate(reducer)
    from ..parameters.rating import check_torque, peak_load

    check_torque(reducer, *peak_load(reducer))
    duration = float(reducer.operating.duration if duration is None else duration)
    time_step = default_time_step(scheme) if time_step is None else time_step
    check_run_options(reducer, duration, time_step, sample_rate, scheme)   # the scheme too
    model = build_model(reducer, time_step, scheme)
    fe, modal = disc_modes(reducer, model, time_step)
    n_steps = int(round(duration / time_step))
    sample_every = max(1, int(round(1.0 / (sample_rate * time_step))))
    n_samples = n_steps // sample_every + 1
    channels = np.zeros((n_samples, L.N_CHANNELS))
    pin_forces = np.zeros((n_samples, 2, reducer.cycloid.pin_count))
    energy = np.zeros(L.N_ENERGY)
    q = model.q0.copy()
    v = np.zeros(L.N_DOF)
    state = new_state(reducer.cycloid.pin_count, L.N_CHANNELS, int(model.P[L.OUT_COUNT]))
    carried = nothing_carried(reducer.cycloid.pin_count)
    implicit = new_work(model.P)        # the scheme implicit-bearings' (empty: explicit)
    bar = None      # shown after the first chunk: a first run's compile notice stands alone
    clock = RunClock()      # the wall time of the run, without numba compiling the kernel
    step = 0
    try:
        while True:
            stop = min(step + CHUNK_STEPS, n_steps + 1)
            status, step = integrate(model.P, q, v, step, stop, n_steps, sample_every,
                                     model.pins, model.holes, model.crank_angles,
                                     model.mesh_phase, *state, channels, pin_forces, energy,
                                     fe, modal, carried, *implicit)
            if progress and bar is None:
                bar = _progress_bar(duration)
            if bar is not None:
                bar.update(min(step, n_steps) * time_step - bar.n)
            check_stop()        # a Ctrl-C or SIGTERM whose exception was swallowed on its way
            if status != STATUS_OK or step > n_steps:
                break
    finally:
        if bar is not None:
            bar.close()
    wall, _ = clock.split()
    steps = n_steps if status == STATUS_OK else step
    rows = int(state[-1][COUNT_ROW])          # samples the kernel stored
    result = Result(time=channels[:rows, L.CH_TIME].copy(), channels=channels[:rows],
                    pin_forces=pin_forces[:rows], ratio=reducer.ratio,
                    steady_start=reducer.operating.steady_start,
                    status=STATUS_TEXT[status], steps=int(steps), wall_s=wall,
                    energy=_energy_balance(energy), reducer_name=reducer.name,
                    guard=_guard_report(model.P), pin_force_peak=float(energy[L.E_PIN_PEAK]))
    if status != STATUS_OK:
        message = (f"simulation stopped at t = {steps * time_step:.4f} s: "
                   f"{STATUS_MESSAGE[status]}")
    else:
        status, message = _check_finished_run(result)
        result.status = STATUS_TEXT[status]
    if status != STATUS_OK and raise_on_failure:
        raise SimulationError(result.status, message)
    return result


def disc_modes(reducer: Reducer, model, time_step: float) -> tuple[np.ndarray, np.ndarray]:
    """The finite-element discs as the dynamic kernel takes them: (tables, modal).  With
    ``flexibility.fe_modes`` = n > 0, the residual tables and the n modes of each disc at rest
    (:func:`rvsim.fe.modes.disc_modal_arrays`, :func:`rvsim.physics._fe_modes.modal_array`);
    with 0, the condensed tables and no modes.  Closed-form bodies: ``model.fe`` (empty) and
    no modes."""
    if model.fe.shape[1] == 0:
        return model.fe, np.zeros((2, 0, 0))
    # (the modes with the crank holes as load points are refused by check_run_options)
    from ..fe.modes import disc_modal_arrays
    from ..physics._fe_modes import modal_array

    tables, participation, omega = disc_modal_arrays(reducer, model.fe,
                                                     int(model.P[L.FE_MODES]), time_step)
    return tables, modal_array(participation, omega)


def _progress_bar(duration: float):
    import sys

    from tqdm import tqdm

    return tqdm(total=duration, unit="s", desc="simulating", file=sys.stderr, leave=False,
                bar_format="{desc}: {percentage:3.0f}%|{bar}| {n:.2f}/{total:.2f} s simulated "
                           "[{elapsed}<{remaining}]")


def _check_finished_run(result: Result) -> tuple[int, str]:
    """Status of a run that finished: energy balance and speed ratio (docs/model.md 9)."""
    residual = result.energy["relative_residual"]
    if math.isnan(residual) and result.energy["residual"] == 0.0:
        residual = 0.0          # nothing moved and nothing was lost: nothing to balance
    if not abs(residual) <= ENERGY_RESIDUAL_LIMIT:
        return STATUS_ENERGY, (
            f"energy balance off by {100 * residual:.3g} % of the input work (or, larger, the "
            "kinetic energy) over the steady window (limit "
            f"{100 * ENERGY_RESIDUAL_LIMIT:g} %): the state is not physical "
            "(parameters outside the model's range, or a time step too large for them)")
    ratio = result.metrics["speed_ratio"]
    deviation = ratio / result.ratio - 1.0
    if not abs(deviation) <= SPEED_RATIO_LIMIT:
        return STATUS_SPEED_RATIO, (
            f"steady speed ratio {ratio:.4g} is {100 * deviation:+.3g} % off the design "
            f"ratio {result.ratio:.4g} (limit {100 * SPEED_RATIO_LIMIT:g} %): the drive does "
            "not transmit the motion")
    return STATUS_OK, ""


def _guard_report(P: np.ndarray) -> dict[str, float]:
    """What the crank nodes' stability guard did in the run just integrated (empty when it was
    off: steps up to model.GUARD_FROM_STEP), or with the scheme implicit-bearings what its
    factorisations were."""
    if P[L.IMPLICIT_THETA] != 0.0:
        return {"implicit_factorisations": int(P[L.IMPLICIT_FACTORS]),
                "implicit_alerts": int(P[L.IMPLICIT_ALERTS]),
                "implicit_fallbacks": int(P[L.IMPLICIT_FALLBACKS])}
    if P[L.NODE_OMEGA_DT] <= 0.0:
        return {}
    return {"guard_substep_checks": int(P[L.NODE_CHECKS]),
            "guard_substep_checks_steady": int(P[L.NODE_CHECKS_STEADY]),
            "guard_peak_omega_dt": float(P[L.NODE_PEAK])}


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
    terms["kinetic_start"] = float(e[L.E_KIN0])
    terms["residual"] = float(residual)
    # relative to the input work; without load, to the kinetic energy (the input work is then
    # only the small damping loss, and the residual over it meaningless: 0.47 at no load).
    # The run's status is judged on this same figure.
    # NaN where there is nothing to relate it to (a run stopped before its steady window)
    scale = max(abs(terms["input_work"]), terms["kinetic_start"])
    terms["relative_residual"] = float(residual / scale) if scale > 0 else float("nan")
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
    layout = dataclasses.replace(reducer.layout, output_pin_clearance=0.0,
                                 input_bearing_clearance=0.0)  # single-stage clearances
    perfect = dataclasses.replace(reducer, errors=Errors(), clearances=Clearances(),
                                  layout=layout)
    elastic = simulate(perfect, **options).metrics["te_mean_arcmin"]
    return {"te_mean_arcmin": total, "te_elastic_arcmin": elastic,
            "te_lost_motion_arcmin": total - elastic}
