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

import time
import traceback

from ..errors import InputFileError, SimulationError

__all__ = ["ENGINES", "DEFAULT_ENGINE", "evaluate_quasi_static", "engine_options",
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

    start = time.perf_counter()
    try:
        result = ltca(reducer, positions=positions)
        metrics = _without(result.summary(), "status")
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
                   "wall_s": time.perf_counter() - start}
        if error:
            outcome["error"] = error
        return outcome
    except SimulationError as exc:   # the engine stopped: its status, not "error"
        return {"status": exc.status, "error": str(exc), "metrics": {},
                "wall_s": time.perf_counter() - start}
    except Exception as exc:  # noqa: BLE001 - a failed row must not stop the study
        return {"status": "error", "error": f"{type(exc).__name__}: {exc}", "metrics": {},
                "wall_s": time.perf_counter() - start, "detail": traceback.format_exc(limit=3)}
