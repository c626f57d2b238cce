"""The model at the measured operating points, analysed by the same functions as the bench.

TE tests: the quasi-static engine (:func:`rvsim.quasistatic.ltca`) over one output revolution
at the point's output torque, resisting the motion (forward: +T along increasing input;
backward: -T, the path read in reverse so that the input turns back); torque-reversal tests:
:func:`rvsim.quasistatic.hysteresis` to the rated torque.  The model runs come back as
:class:`~rvsim.testrig.bench.FileResult` and go through :func:`point_summary` like the
measurements.  Efficiency: :func:`rvsim.quasistatic.efficiency` at the point's input speed and
torque when the parameter set has friction.  Speed and oil temperature do not enter the TE and
the loop (reported).
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from ..analysis import catalogue
from . import analysis as A
from .bench import FileResult, PointResult, check_model_ratio

__all__ = ["simulate_point", "model_te", "model_loop", "model_efficiency", "point_summary",
           "compare_point", "COMPARED_KEYS"]

COMPARED_KEYS = ("ate_pp_arcmin", "te_rms_arcsec", "forward_backward_offset_arcmin",
                 "lost_motion_arcmin", "backlash_arcmin", "hysteresis_loss_arcmin",
                 "torsional_rigidity_nm_per_arcmin", "efficiency")


def model_te(reducer, torque: float, direction: int, points: int) -> list:
    """[DirectionTE] of the model under ``torque`` resisting the motion in ``direction``."""
    from ..quasistatic import ltca

    # points + 1 positions over (points + 1) / points revolutions: the first and the last
    # position are one output revolution apart, so the run holds one complete revolution
    run = ltca(reducer, torque=direction * abs(torque), positions=points + 1,
               revolutions=(points + 1) / points)
    theta_in, theta_out = run.input_angle, run.output_angle
    if direction < 0:
        theta_in, theta_out = theta_in[::-1], theta_out[::-1]
    return A.te_directions(theta_in, theta_out, run.ratio, points)


def model_loop(reducer, rated: float):
    """(torque, angle, branch) of the model's torque-reversal test to ``rated``."""
    from ..quasistatic import hysteresis

    t, a, b, _ = catalogue.loop_arrays(hysteresis(reducer, rated_torque=rated))
    return t, a, b


def model_efficiency(reducer, speed_rpm: float, torque: float) -> float | None:
    """Efficiency of the quasi-static efficiency engine (:func:`rvsim.quasistatic.efficiency`,
    the parameter set's friction) at input ``speed_rpm`` and output ``torque``; None for a
    parameter set without friction (its efficiency would be 1 by construction)."""
    from ..friction import has_friction
    from ..quasistatic import efficiency

    if not has_friction(reducer):
        return None
    result = efficiency(reducer, speeds_rpm=[speed_rpm], torques=[abs(torque)])
    return float(result.efficiency[0, 0])


def simulate_point(point: PointResult, reducer, *, points: int = A.DEFAULT_POINTS
                   ) -> PointResult:
    """The model's runs for every test of a measured point (raises SimulationError; an
    InputFileError when a file's ratio is not the model's)."""
    check_model_ratio(point, reducer)
    torque = float(point.point.get("torque_nm", 0.0))
    speed = point.point.get("speed_rpm")
    files = []
    for measured in point.files:
        if measured.directions:
            directions = []
            for d in measured.directions:
                directions += model_te(reducer, torque, d.direction, points)
            eff = (model_efficiency(reducer, speed, torque)
                   if measured.efficiency is not None and speed and torque else None)
            files.append(FileResult(Path(f"model: ltca at {torque:g} N*m"), measured.test,
                                    {"torque_nm": torque}, directions=directions,
                                    efficiency=eff))
        if measured.loop is not None:
            rated = reducer.rating.rated_torque
            files.append(FileResult(Path(f"model: hysteresis to {rated:g} N*m"),
                                    measured.test, {"torque_nm": rated},
                                    loop=model_loop(reducer, rated)))
    return PointResult(dict(point.point), files)


def point_summary(point: PointResult, reducer) -> dict:
    """One JSON object of an operating point: the TE quantities (largest peak-to-peak of a
    complete revolution, RMS, leading orders), the catalogue quantities of a torque-reversal
    recording, efficiency; keys of what the recordings do not have are left out, except the
    three TE keys (null)."""
    marks = catalogue.reducer_orders(reducer)
    out: dict = {"point": point.point, "files": [f.path.name for f in point.files],
                 "tests": sorted({f.test for f in point.files})}
    te = [A.te_summary(f.directions, marks) for f in point.files if f.directions]
    if te:
        out["ate_pp_arcmin"] = max(s["ate_pp_arcmin"] for s in te)
        out["te_rms_arcsec"] = float(np.sqrt(np.mean([s["te_rms_arcsec"] ** 2 for s in te])))
        lead = point.leading_direction()
        out["orders"] = A.leading_orders(*lead.spectrum(), marks)
        directions: dict = {}
        for f, s in zip([f for f in point.files if f.directions], te):
            for name, values in s["directions"].items():
                directions[name if name not in directions else f"{name} ({f.path.name})"] = \
                    values
        out["directions"] = directions
        offsets = [s["forward_backward_offset_arcmin"] for s in te
                   if "forward_backward_offset_arcmin" in s]
        if offsets:
            out["forward_backward_offset_arcmin"] = offsets[0]
        else:
            out.update(_offset_across_files(point))
    else:
        out.update(ate_pp_arcmin=None, te_rms_arcsec=None, orders=[])
    out["ate_arcmin"] = out["ate_pp_arcmin"]     # the name every other JSON uses (issue 33)
    loops = [f.loop for f in point.files if f.loop is not None]
    if loops:
        out.update(A.reversal_summary(*loops[0], reducer.rating.rated_torque))
    efficiency = [f.efficiency for f in point.files if f.efficiency is not None]
    if efficiency:              # a fraction, as since its first version, and in % (the unit
        out["efficiency"] = float(np.mean(efficiency))      # of the console and the report,
        out["efficiency_pct"] = 100.0 * out["efficiency"]   # as rvsim efficiency's JSON)
    ratios = [f.ratio_measured for f in point.files if f.ratio_measured]
    if ratios:
        out["ratio_measured"] = float(np.mean(ratios))
    samples = sum(f.samples for f in point.files)
    if samples:
        out["samples"] = samples
    notes = [n for f in point.files for n in f.notes]
    if notes:
        out["notes"] = notes
    return out


def _offset_across_files(point: PointResult) -> dict:
    """Forward/backward offset of a point whose forward and backward runs are in different
    files: mean TE of the forward files minus that of the backward ones, with a note (it holds
    only if the encoder zeros did not change between the recordings); {} without both."""
    means: dict = {1: [], -1: []}
    names: dict = {1: [], -1: []}
    for f in point.files:
        for d in f.directions or []:
            means[d.direction].append(d.mean)
            names[d.direction].append(f.path.name)
    if not (means[1] and means[-1]):
        return {}
    return {"forward_backward_offset_arcmin": (np.mean(means[1]) - np.mean(means[-1]))
            / A.ARCMIN,
            "forward_backward_offset_note": (
                f"forward ({', '.join(names[1])}) and backward ({', '.join(names[-1])}) are "
                "different files: the offset holds only if the encoder zeros did not change "
                "between the recordings")}


def _curve_difference(measured: PointResult, simulated: PointResult) -> dict:
    """RMS of measured minus simulated averaged TE curve per direction [arcsec] (the model
    interpolated onto the measured nodes, periodic)."""
    out = {}
    model = {d.direction: d for f in simulated.files if f.directions for d in f.directions}
    for f in measured.files:
        for d in f.directions or []:
            m = model.get(d.direction)
            if m is None:
                continue
            sim = np.interp(d.curve_angle, m.curve_angle, m.curve, period=2.0 * math.pi)
            diff = (d.curve - sim) - np.mean(d.curve - sim)
            name = "forward" if d.direction > 0 else "backward"
            out.setdefault(name, float(np.sqrt(np.mean(diff ** 2)) / A.ARCSEC))
    return out


def compare_point(point: PointResult, reducer, *, points: int = A.DEFAULT_POINTS):
    """(measured summary with "simulated" and "difference" entries, simulated PointResult);
    ``points`` per output revolution must resolve the reducer's highest order (the command
    line's ``--points`` check)."""
    from ..analysis.sampling import check_positions
    from ..errors import SimulationError

    check_positions(reducer, points, "points")
    summary = point_summary(point, reducer)
    try:
        simulated = simulate_point(point, reducer, points=points)
    except SimulationError as exc:
        summary["simulated"] = {"status": exc.status, "error": str(exc)}
        return summary, None
    sim = point_summary(simulated, reducer)
    sim.pop("forward_backward_offset_note", None)       # the model has one nominal zero
    sim["status"] = "ok"
    sim["note"] = ("quasi-static model: speed and oil temperature do not enter the TE and the "
                   "loop")
    if summary.get("efficiency") is not None:
        from ..friction import has_friction

        sim["note"] += ("; efficiency from the quasi-static efficiency engine at the point's "
                        "input speed and torque, with the parameter set's friction and oil "
                        "viscosity (the measured oil temperature does not enter)"
                        if has_friction(reducer) else
                        "; the parameter set has no friction: no model efficiency (give "
                        "friction values, e.g. --params RV-40E-bearings)")
    if "torque_nm" not in point.point and any(f.directions for f in point.files):
        sim["note"] += ("; the recording gives no torque (no torque column, none in the file "
                        "name or manifest): the model's TE is at 0 N*m")
    summary["simulated"] = sim
    summary["difference"] = {k: summary[k] - sim[k] for k in COMPARED_KEYS
                             if summary.get(k) is not None and sim.get(k) is not None}
    if "efficiency" in summary["difference"]:       # in percentage points
        summary["difference"]["efficiency_pct"] = 100.0 * summary["difference"]["efficiency"]
    curves = _curve_difference(point, simulated)
    if curves:
        summary["difference"]["te_curve_rms_arcsec"] = curves
    return summary, simulated
