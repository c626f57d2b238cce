"""One Monte Carlo reducer: assembly check, then the quasi-static LTCA and torque-reversal test.

:func:`evaluate_sample` returns the outcome shape of :func:`rvsim.doe.runner.evaluate`
(status, metrics, wall_s, error; never raises).  A reducer whose parts overlap at the
assembled pose has status ``binds`` (it cannot be built as drawn: the binding share); a
rolling bearing's interference is elastic preload, ``binds`` only above the static stress limit.
"""

from __future__ import annotations

import time
import traceback

from .._cache_guard import RunClock
from ..doe.engines import register_evaluator

__all__ = ["evaluate_sample", "evaluate_run", "assembly_binds", "METRICS", "BINDS"]

BINDS = "binds"
#: torque steps per quarter of the torque-reversal test (the catalogue command's 50 change the
#: lost motion by under 1 %, docs/decisions.md; 20 take 40 % of the time)
HYSTERESIS_POINTS = 20
#: metrics of one reducer: summary key -> (short name used in targets, description)
METRICS = {
    "ate_arcmin": ("ate", "angular transmission error: peak-to-peak TE over one output "
                          "revolution at the study torque [arcmin]"),
    "te_mean_arcmin": ("te_mean", "mean TE over the revolution (the paper's index) [arcmin]"),
    "lost_motion_arcmin": ("lost_motion", "lost motion at +-3 % rated torque [arcmin]"),
    "torsional_rigidity_nm_per_arcmin": ("torsional_rigidity",
                                         "torsional rigidity [N*m/arcmin]"),
}


def evaluate_sample(reducer, positions: int = 360) -> dict:
    """Evaluate one drawn reducer (module docstring)."""
    from ..errors import ParameterError, SimulationError
    from ..quasistatic import hysteresis, ltca

    clock = RunClock()      # the run without numba compiling (a cold cache)
    cpu = time.process_time()
    try:
        binding = assembly_binds(reducer)
        if binding:
            return {"status": BINDS, "metrics": {"binds": 1}, "error": binding,
                    "wall_s": clock.split()[0]}
        run = ltca(reducer, positions=positions).summary()
        loop = hysteresis(reducer, points_per_branch=HYSTERESIS_POINTS).summary()
        metrics = {"binds": 0, "ate_arcmin": run["te_pp_arcmin"],
                   "te_mean_arcmin": run["te_mean_arcmin"],
                   "max_pin_force_n": run["max_pin_force_n"],
                   "lost_motion_arcmin": loop["lost_motion_arcmin"],
                   "backlash_arcmin": loop["backlash_arcmin"],
                   "torsional_rigidity_nm_per_arcmin": loop["torsional_rigidity_nm_per_arcmin"],
                   "cpu_s": time.process_time() - cpu}
        return {"status": "ok", "metrics": metrics, "wall_s": clock.split()[0]}
    except SimulationError as exc:
        return {"status": exc.status, "error": str(exc), "metrics": {},
                "wall_s": clock.split()[0]}
    except ParameterError as exc:      # a drawn value outside what the model accepts
        return {"status": "invalid", "error": str(exc), "metrics": {},
                "wall_s": clock.split()[0]}
    except Exception as exc:  # noqa: BLE001 - a failed sample must not stop the study
        return {"status": "error", "error": f"{type(exc).__name__}: {exc}", "metrics": {},
                "wall_s": clock.split()[0], "detail": traceback.format_exc(limit=3)}


def assembly_binds(reducer) -> str | None:
    """Why a drawn reducer cannot be built (its worst overlap at the assembled pose: "crank 1
    eccentric overlaps ... by 2.20 um"), or None when it assembles.  A rolling bearing's
    interference is assembled with elastic preload and binds only where the preload's Hertz
    stress exceeds the static limit (:func:`rvsim.bearings.preload_refusal`, issue 32).  A
    value the model refuses raises ParameterError first (invalid, even if it binds)."""
    from ..bearings import preload_refusal
    from ..geometry.assembly import CONTACT_TOLERANCE, rigid_overlaps
    from ..parameters import validate

    validate(reducer, assembly=False)
    worst = max(rigid_overlaps(reducer), key=lambda o: o.approach)
    if worst.approach > CONTACT_TOLERANCE:
        return f"{worst.parts} by {worst.approach * 1e6:.2f} um"
    return preload_refusal(reducer)


def evaluate_run(reducer, *, positions: int = 360, **_) -> dict:
    """:func:`evaluate_sample` as an evaluator of the study runner
    (:data:`rvsim.doe.engines.EVALUATORS`, engine "tolerance"; issue 31 step 7): the runner's
    workers are handed this function, not a name doe would have to import."""
    return evaluate_sample(reducer, positions)


register_evaluator("tolerance", evaluate_run)
