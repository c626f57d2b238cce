"""Which model evaluates a study's runs: the dynamic simulation or the quasi-static engine.

A study file chooses with ``engine = "dynamic"`` (default) or ``engine = "quasi-static"``;
with the quasi-static engine ``hysteresis = true`` adds the torque-reversal test to each run.
:func:`evaluate_quasi_static` returns the same outcome shape as
:func:`rvsim.doe.runner.evaluate` (status, metrics, wall_s, error; never raises), with the
LTCA summary (``te_mean_arcmin``, ``te_pp_arcmin``, ``max_pin_force_n``, ...) and, asked for,
the catalogue quantities (``torsional_rigidity_nm_per_arcmin``, ``lost_motion_arcmin``,
``backlash_arcmin``, ``hysteresis_loss_arcmin``, ``rated_torque_nm``) as responses.
"""

from __future__ import annotations

import traceback
from typing import Callable

from .._cache_guard import RunClock
from ..errors import InputFileError, SimulationError

__all__ = ["ENGINES", "DEFAULT_ENGINE", "evaluate_quasi_static", "evaluate_dynamic",
           "engine_options", "compact_history", "EVALUATORS", "register_evaluator",
           "metric_columns"]

DEFAULT_ENGINE = "dynamic"
ENGINES = ("dynamic", "quasi-static")

#: the numeric columns each engine adds to a study's rows (``rvsim study --response`` names
#: one of them; tests/integration/test_response_option.py checks them against real runs).
#: The dynamic engine's guard and implicit-scheme counters appear with their scheme only.
_METRICS = {
    "dynamic": ("te_mean_arcmin", "te_pp_arcmin", "te_rms_arcmin", "te_std_arcmin",
                "te_max_arcmin", "speed_ratio", "energy_residual", "max_pin_force_n",
                "ate_arcmin", "te_window_revolutions", "sim_time_s", "steps", "wall_s",
                "guard_substep_checks", "guard_substep_checks_steady", "guard_peak_omega_dt",
                "implicit_factorisations", "implicit_alerts", "implicit_fallbacks"),
    "quasi-static": ("te_mean_arcmin", "te_pp_arcmin", "ate_arcmin", "te_window_revolutions",
                     "max_pin_force_n", "pins_in_contact_min", "pins_in_contact_max",
                     "max_contact_stress_mpa", "torsional_stiffness_nm_per_arcmin",
                     "torque_nm", "positions", "wall_s"),
    "hysteresis": ("rated_torque_nm", "torsional_rigidity_nm_per_arcmin",
                   "lost_motion_arcmin", "backlash_arcmin", "hysteresis_loss_arcmin",
                   "points"),
}


def metric_columns(engine: str, hysteresis: bool = False) -> tuple[str, ...]:
    """The metric columns a study on ``engine`` (with the torque-reversal test when
    ``hysteresis``) gives its rows."""
    return _METRICS[engine] + (_METRICS["hysteresis"] if hysteresis else ())


def engine_options(data: dict, path) -> tuple[str, bool]:
    """(engine, hysteresis) from a study file's top-level keys, checked."""
    engine = data.get("engine", DEFAULT_ENGINE)
    if engine not in ENGINES:
        raise InputFileError(f"{path}: engine must be one of {', '.join(ENGINES)} "
                             f"(got {engine!r})")
    hysteresis = data.get("hysteresis", False)
    if not isinstance(hysteresis, bool):
        raise InputFileError(f"{path}: hysteresis must be true or false")
    if hysteresis and engine != "quasi-static":
        raise InputFileError(f"{path}: hysteresis = true needs engine = \"quasi-static\"")
    return engine, hysteresis


def _without(summary: dict, *names: str) -> dict:
    return {k: v for k, v in summary.items() if k not in names}


def evaluate_quasi_static(reducer, *, hysteresis: bool = False, positions: int = 360) -> dict:
    """One run on the quasi-static engine; never raises (the outcome carries the status)."""
    from ..quasistatic import hysteresis as torque_reversal
    from ..quasistatic import ltca

    clock = RunClock()      # the run without numba compiling (a cold cache)
    try:
        result = ltca(reducer, positions=positions)
        # the reducer's contact-stress limit and its verdict's text are no run metrics
        metrics = _without(result.summary(), "status", "static_contact_stress_mpa",
                           "contact_stress_verdict")
        status, error = result.status, None
        if status != "ok":
            error = f"ltca {status.replace('_', ' ')}"
        elif hysteresis:
            loop = torque_reversal(reducer)
            status = loop.status
            if status == "ok":
                metrics.update(_without(loop.summary(), "status", "wall_s"))
            else:
                error = f"hysteresis {status.replace('_', ' ')}"
        outcome = {"status": status, "metrics": metrics,
                   "wall_s": clock.split()[0]}
        if error:
            outcome["error"] = error
        return outcome
    except SimulationError as exc:   # the engine stopped: its status, not "error"
        return {"status": exc.status, "error": str(exc), "metrics": {},
                "wall_s": clock.split()[0]}
    except Exception as exc:  # noqa: BLE001 - a failed row must not stop the study
        return {"status": "error", "error": f"{type(exc).__name__}: {exc}", "metrics": {},
                "wall_s": clock.split()[0], "detail": traceback.format_exc(limit=3)}


def evaluate_dynamic(reducer, *, time_step: float, scheme: str = "explicit", **_) -> dict:
    """One run of the dynamic simulation at ``time_step`` with the integration ``scheme``;
    never raises (the outcome carries the status; moved from ``rvsim.doe.runner.evaluate``,
    issue 31 step 7)."""
    from ..dynamics import simulate

    try:
        result = simulate(reducer, time_step=time_step, raise_on_failure=False, scheme=scheme)
        outcome = {"status": result.status, "wall_s": result.wall_s, "metrics": {}}
        if result.status != "ok":
            outcome["error"] = f"simulation {result.status.replace('_', ' ')} at step " \
                               f"{result.steps}"
        try:
            outcome["metrics"] = result.summary()
            outcome["history"] = compact_history(result)
        except Exception:  # noqa: BLE001 - a stopped run may have too few samples
            if result.status == "ok":
                raise
        return outcome
    except Exception as exc:  # noqa: BLE001 - a failed row must not stop the study
        return {"status": "error", "error": f"{type(exc).__name__}: {exc}",
                "metrics": {}, "detail": traceback.format_exc(limit=3)}


def compact_history(result, rate: float = 1000.0) -> bytes:
    """Time, input and output speed and TE at ``rate`` Hz, as compressed .npz bytes."""
    import io

    import numpy as np

    sample = result.time[1] - result.time[0] if len(result.time) > 1 else 1.0 / rate
    step = max(1, int(round(1.0 / (rate * sample))))
    buffer = io.BytesIO()
    np.savez_compressed(buffer, time=result.time[::step], omega_in=result.omega_in[::step],
                        omega_out=result.omega_out[::step], te=result.te[::step],
                        ratio=np.array(result.ratio), steady_start=np.array(result.steady_start))
    return buffer.getvalue()


def _quasi_static(reducer, *, hysteresis: bool = False, positions: int = 360, **_) -> dict:
    return evaluate_quasi_static(reducer, hysteresis=hysteresis, positions=positions)


#: the evaluators of a study's runs by engine name (issue 31 step 7): each is called as
#: ``evaluator(reducer, *, time_step, hysteresis, positions, scheme)`` and returns an outcome
#: ``{status, metrics, error, ...}`` without raising.  doe's own two are here; a package above
#: doe registers its own (:mod:`rvsim.tolerance.engine` registers "tolerance"), so that doe
#: never imports it
EVALUATORS: dict[str, Callable[..., dict]] = {"dynamic": evaluate_dynamic,
                                              "quasi-static": _quasi_static}


def register_evaluator(name: str, evaluator: Callable[..., dict]) -> Callable[..., dict]:
    """Make ``evaluator`` the engine ``name`` of :func:`rvsim.doe.runner.evaluate`."""
    EVALUATORS[name] = evaluator
    return evaluator
