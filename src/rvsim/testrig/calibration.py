"""Least-squares calibration of uncertain parameters to bench curves (:func:`calibrate`).

Residuals [arcsec], all measured minus model, each group with its own mean removed (an
encoder zero makes the mean arbitrary):

* every TE direction of every operating point: the measured revolution-synchronous average
  at the model's nodes (``positions`` per output revolution; the model is the quasi-static
  TE at the point's torque, :func:`rvsim.testrig.model.model_te`);
* every torque-reversal loop: the angle of each branch at 24 torques on each side of zero
  (2 % to 98 % of the test torque), read by :func:`rvsim.analysis.catalogue.angle_at`;
* every sample of a loop curve (``loops``, :func:`rvsim.testrig.curves.read_loop`): its
  angle against the model's, the torque-reversal test run along the curve's own torque
  history (:func:`rvsim.quasistatic.hysteresis` with ``torques``: the path friction follows).

Efficiency points (``efficiency``, :func:`rvsim.testrig.curves.read_efficiency`) are fitted
on their own, residuals in percentage points and no mean removed: measured minus
:func:`rvsim.quasistatic.efficiency_points` at each point's speed, torque and lubricant
temperature (angles and efficiencies have different units and noise: one fit weights
one kind).

scipy.optimize.least_squares (trust-region reflective, bounds from the parameters' lower
limits) on the parameters in user units divided by a scale; covariance s^2 (J^T J)^-1 with
s^2 = the residual sum of squares / (m - p); 95 % intervals with Student's t.  A singular or
nearly singular J^T J means the data cannot tell the parameters apart: said by name.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from .._display import Headline, number
from ..analysis import catalogue
from ..errors import ParameterError, RvsimError, SimulationError
from ..parameters import SPECS, get_value, resolve_name, with_values
from ..units import TO_SI
from . import analysis as A
from .bench import check_model_ratio
from .model import model_loop, model_te

__all__ = ["calibrate", "Calibration", "CalibrationError", "residuals", "CORRELATION_LIMIT",
           "NOT_FITTED", "fitted_names", "PERCENT"]

#: efficiency residuals in percentage points
PERCENT = 0.01

#: |correlation| above which two fitted parameters are reported as hardly separable
CORRELATION_LIMIT = 0.95
#: |correlation| from which they count as not separable at all (a singular J^T J shows up so
#: through the finite-difference Jacobian's round-off)
SAME_LIMIT = 0.999
#: condition index of the Jacobian with unit-length columns above which the fitted parameters
#: are collinear as a set (Belsley, Kuh & Welsch 1980, Regression Diagnostics: indices above 30
#: indicate moderate to strong dependencies): not identifiable
CONDITION_LIMIT = 30.0
#: singular values of the scaled Jacobian below this fraction of the largest: not identifiable
RANK_TOLERANCE = 1e-6
_LEVELS = np.linspace(0.02, 0.98, 24)
#: a parameter whose 95 % interval covers this fraction of what it can be (both bounds
#: finite, e.g. a Poisson ratio 0-0.5) is not fixed by the data: they rule out less than the
#: bounds already do
RANGE_COVERED = 0.5
#: a Jacobian column (per change of the parameter by its scale) below this fraction of the
#: largest: the curves do not depend on it beside the others (docs/decisions.md, issue 30)
NIL_SENSITIVITY = 1e-3
#: sections that describe the test or the run, not the reducer on the bench: refused by --fit
NOT_FITTED = {"rating": "the rated torque sets the extent of the model's torque-reversal "
                        "test, it is not a property of the reducer",
              "operating": "the recordings give the operating points and the model is "
                           "quasi-static: the dynamic run's settings do not enter it"}
#: step of the finite-difference Jacobian in scaled units (1e-3 of a parameter's scale)
JACOBIAN_STEP = 1e-3
#: one-sided level of the runs test below which the residuals count as systematic: the fitted
#: model does not reproduce the data (status lack_of_fit; docs/decisions.md, issue 30, fifth
#: session)
LACK_OF_FIT_LEVEL = 1e-3
#: scale of a parameter that starts at zero, by unit
_TYPICAL = {"mm": 0.01, "um": 10.0, "arcmin": 1.0, "deg": 0.1}


class CalibrationError(RvsimError):
    """The data or the chosen parameters cannot be fitted (message says why)."""


@dataclasses.dataclass(repr=False)
class Calibration(Headline):
    """Result of :func:`calibrate` (values in the parameters' user units).  Shown as each
    fitted value with its 95 % interval and the residual before and after (:meth:`headline`)."""

    names: list
    units: list
    start: np.ndarray
    estimate: np.ndarray
    std_error: np.ndarray
    ci_low: np.ndarray
    ci_high: np.ndarray
    correlation: np.ndarray
    notes: list
    rms_start_arcsec: float          # RMS of the residuals at the start, in ``unit``
    rms_arcsec: float                # and at the estimate (the names of the angle fits)
    residuals: int
    evaluations: int
    status: str
    reducer: object = None
    unit: str = "arcsec"             # of the residuals: "arcsec", or "%" (efficiency points)

    def headline(self) -> tuple[str, list[tuple]]:
        """Status, the fit's residual and each parameter's estimate (the repr)."""
        rows = [("RMS residual", f"{number(self.rms_arcsec, self.unit, 4)} (at the start "
                                 f"{number(self.rms_start_arcsec, self.unit, 4)})")]
        for name, unit, start, estimate, low, high in zip(self.names, self.units, self.start,
                                                          self.estimate, self.ci_low,
                                                          self.ci_high):
            interval = (f"95 %: {number(float(low))} to {number(float(high))}"
                        if math.isfinite(low) and math.isfinite(high) else "not identifiable")
            rows.append((name, f"{number(float(estimate), unit)} ({interval}; start "
                               f"{number(float(start))})"))
        return (f"Calibration: {self.status}, {self.residuals} residuals, {self.evaluations} "
                "model evaluations", rows + [("note", n) for n in self.notes])

    def to_dict(self) -> dict:
        def num(v):
            return None if not math.isfinite(v) else float(v)

        return {
            "parameters": {n: {"unit": u, "start": num(s), "estimate": num(e),
                               "std_error": num(se), "ci95": [num(lo), num(hi)]}
                           for n, u, s, e, se, lo, hi in zip(
                               self.names, self.units, self.start, self.estimate,
                               self.std_error, self.ci_low, self.ci_high)},
            "correlation": {"names": self.names,
                            "matrix": [[num(v) for v in row] for row in self.correlation]},
            "notes": self.notes,
            # the RMS of the residuals, in their unit (the two keys of issue 30 keep their
            # arcsec name; an efficiency fit gives percentage points)
            **({"rms_start_arcsec": self.rms_start_arcsec, "rms_arcsec": self.rms_arcsec}
               if self.unit == "arcsec" else {"rms_start_percent": self.rms_start_arcsec,
                                              "rms_percent": self.rms_arcsec}),
            "residual_unit": self.unit,
            "residuals": self.residuals, "evaluations": self.evaluations,
            "status": self.status,
        }


def _targets(points, reducer, positions: int, loops=(), efficiency=None):
    """What the residuals compare: [("te", torque, direction, measured values at the model's
    nodes)], [("loop", reach, None, measured angles at the torque levels)], [("curve", None,
    None, LoopCurve)] and [("efficiency", None, None, EfficiencyPoints)]."""
    step = 2.0 * math.pi / positions
    nodes = np.arange(positions) * step
    targets = [("curve", None, None, loop) for loop in loops]
    if efficiency is not None:
        if points or loops:
            raise ParameterError("--efficiency", "is fitted on its own, not with angle "
                                 "recordings or loops (different units and noise): fit the "
                                 "friction to it, then the angles with --params fitted.toml")
        targets.append(("efficiency", None, None, efficiency))
    for point in points:
        check_model_ratio(point, reducer)
        torque = float(point.point.get("torque_nm", 0.0))
        for f in point.files:
            for d in f.directions or []:
                values = np.interp(nodes, d.curve_angle, d.curve, period=2.0 * math.pi)
                targets.append(("te", torque, d.direction, values))
            if f.loop is not None:
                (tu, _), (td, _) = catalogue.loop_branches(*f.loop)
                reach = min(reducer.rating.rated_torque,
                            float(min(tu.max(), td.max(), -tu.min(), -td.min())))
                # the same torques for the measured and the model loop
                targets.append(("loop", reach, None, _loop_angles(f.loop, reach)))
    if not targets:
        raise CalibrationError("the recordings hold no TE curve and no torque-reversal loop "
                               "to fit")
    return targets


def _measured_values(targets) -> int:
    """How many values the targets measure independently (a group whose mean is removed
    gives one fewer): what must exceed the number of fitted parameters."""
    count = 0
    for kind, _, _, measured in targets:
        if kind == "efficiency":
            count += measured.efficiency.size
        else:
            count += (measured.torque.size if kind == "curve" else measured.size) - 1
    return count


def _curve_residuals(loop, reducer) -> np.ndarray:
    """Measured minus model angle [rad] of a loop curve, the model along its torques."""
    from ..quasistatic import hysteresis

    return loop.angle - hysteresis(reducer, torques=loop.torque).angle


def _efficiency_residuals(points, reducer) -> np.ndarray:
    """Measured minus model efficiency [-] at each point, the model at the point's
    lubricant temperature where the file gives one."""
    from ..quasistatic.efficiency import efficiency_points

    model = np.empty(points.efficiency.size)
    groups = ([(None, np.arange(model.size))] if points.temperature is None else
              [(t, np.flatnonzero(points.temperature == t))
               for t in np.unique(points.temperature)])
    for temperature, rows in groups:
        at = reducer if temperature is None else with_values(
            reducer, {"operating.temperature": float(temperature)})
        model[rows] = efficiency_points(at, points.speed_rpm[rows], points.torque[rows])
    return points.efficiency - model


def _loop_angles(loop, reach: float) -> np.ndarray:
    """Angles of both branches at +-_LEVELS * ``reach`` [N*m], each side read from its own
    samples."""
    (tu, au), (td, ad) = catalogue.loop_branches(*loop)
    out = [catalogue.angle_at(bt, ba, sign, sign * level * reach, "calibration")
           for bt, ba in ((tu, au), (td, ad)) for sign in (1.0, -1.0) for level in _LEVELS]
    return np.asarray(out)


def residuals(targets, reducer, positions: int) -> np.ndarray:
    """Measured minus model of every target: angles [arcsec], each group with its mean
    removed; efficiency points [percentage points] as they are."""
    parts = []
    for kind, torque, direction, measured in targets:
        if kind == "efficiency":
            parts.append(_efficiency_residuals(measured, reducer) / PERCENT)
            continue
        if kind == "te":
            diff = measured - model_te(reducer, torque, direction, positions)[0].curve
        elif kind == "curve":
            diff = _curve_residuals(measured, reducer)
        else:
            diff = measured - _loop_angles(model_loop(reducer, reducer.rating.rated_torque),
                                           torque)
        parts.append((diff - diff.mean()) / A.ARCSEC)
    return np.concatenate(parts)


def _scale(spec, start: float) -> float:
    if spec.name.endswith("_phase"):
        # a direction: one radian whatever its start (|start| would make the step depend on
        # where the zero of the angle happens to be)
        return 1.0 / TO_SI[spec.unit]
    return abs(start) if start != 0 else _TYPICAL.get(spec.unit, 1.0)


def fitted_names(fit: list[str]) -> list[str]:
    """The dotted names of ``fit`` (names or factor letters), checked: named once each,
    continuous, properties of the reducer (not NOT_FITTED's test settings)."""
    names = [resolve_name(n) for n in fit]
    if not names:
        raise ParameterError("--fit", "name at least one parameter")
    if len(set(names)) != len(names):
        raise ParameterError("--fit", "a parameter is named twice")
    for spec in (SPECS[n] for n in names):
        section = spec.name.split(".")[0]
        if section in NOT_FITTED:
            raise ParameterError(spec.name, f"cannot be fitted ({NOT_FITTED[section]}); fit "
                                 "the reducer's continuous properties: errors.*, "
                                 "clearances.*, contact.*, materials.*, geometry, bearings")
        if spec.kind != "float":
            what = {"int": "a whole number", "bool": "a yes/no switch",
                    "choice": "a choice"}.get(spec.kind, f"of kind {spec.kind}")
            raise ParameterError(spec.name, f"cannot be fitted ({what}; only continuous "
                                 "quantities can be)")
        if section == "flexibility":
            # its numbers are the FE mesh's element sizes: a fit moved the disc's to 1.606 mm,
            # status ok, 95 % interval 0 .. 113 409 mm, the RMS unchanged
            raise ParameterError(spec.name, "cannot be fitted (an element size of the "
                                 "finite-element mesh: the model's resolution, not a property "
                                 "of the reducer)")
    return names


def _check_scalable(reducer, names: list[str]) -> None:
    """Refuse a ``stiffness.*`` scaling the model cannot take (a group it lacks, the FE disc
    with modes): the model built with the factor moved says why (it was status model_fails
    after the fit's first step, exit 1)."""
    from ..dynamics.model import build_model

    for name in (n for n in names if n.startswith("stiffness.")):
        moved = with_values(reducer, {name: 2.0 * float(get_value(reducer, name))})
        try:
            build_model(moved, 1e-5)       # as the quasi-static engine builds it
        except ParameterError as exc:
            raise ParameterError(name, f"cannot be fitted: {exc.reason}") from None


def calibrate(points, reducer, fit: list[str], *, positions: int = 1024,
              max_evaluations: int = 200, loops=(), efficiency=None) -> Calibration:
    """Fit the parameters ``fit`` (dotted names or factor letters, as ``--set`` takes) of
    ``reducer`` to the analysed recordings ``points`` (:func:`rvsim.testrig.analyse_path`),
    the loop curves ``loops`` and, on their own, the ``efficiency`` points
    (:mod:`rvsim.testrig.curves`)."""
    from ..analysis.sampling import check_positions

    _check_inputs(points, reducer, loops, efficiency, max_evaluations)
    check_positions(reducer, positions, "positions")     # the pin order unaliased
    names = fitted_names([fit] if isinstance(fit, str) else fit)
    _check_scalable(reducer, names)
    from scipy import optimize, stats

    specs = [SPECS[n] for n in names]
    start = np.array([float(get_value(reducer, n)) for n in names])
    scale = np.array([_scale(s, v) for s, v in zip(specs, start)])
    lower = np.array([-np.inf if s.minimum is None else s.minimum / TO_SI[s.unit]
                      for s in specs]) / scale
    upper = np.array([np.inf if s.maximum is None else s.maximum / TO_SI[s.unit]
                      for s in specs]) / scale
    targets = _targets(points, reducer, positions, loops, efficiency)
    measured = _measured_values(targets)
    if measured <= len(names):
        field = ("--efficiency" if efficiency is not None else "--loop" if loops and not points
                 else "recordings")
        # efficiency points have no mean removed (the note was wrong there)
        removed = "" if efficiency is not None else " (after removing each curve's mean)"
        raise ParameterError(field, f"{measured} measured values{removed} cannot fit "
                             f"{len(names)} parameters: record more points or fit fewer "
                             "parameters")
    unit = "%" if efficiency is not None else "arcsec"
    evaluations = [0]
    failed = [None]

    def model_at(x):
        return with_values(reducer, dict(zip(names, x * scale)))

    def evaluate(x):
        """(residuals, None) or (None, why the model failed)."""
        evaluations[0] += 1
        try:
            return residuals(targets, model_at(x), positions), None
        except (SimulationError, ParameterError) as exc:
            failed[0] = str(exc)
            return None, str(exc)

    last: dict = {}

    def fun(x):
        r, _ = evaluate(x)
        r = np.full(size, penalty) if r is None else r
        last.update(x=x.copy(), r=r)
        return r

    blocked: dict = {}

    def jacobian(x):
        """Forward differences with a fixed step of JACOBIAN_STEP in scaled units (backward at
        an upper bound or where the model fails forward).  scipy's own 2-point step is
        relative to |x|, which vanishes for a parameter starting at zero."""
        r0 = last["r"] if "x" in last and np.array_equal(last["x"], x) else fun(x)
        J = np.zeros((size, x.size))
        blocked.clear()
        for j in range(x.size):
            steps = (JACOBIAN_STEP, -JACOBIAN_STEP)
            if x[j] + JACOBIAN_STEP > upper[j]:
                steps = steps[::-1]
            why = "no room between the bounds"
            for h in steps:
                if not lower[j] <= x[j] + h <= upper[j]:
                    continue
                trial = x.copy()
                trial[j] += h
                r, why = evaluate(trial)
                if r is not None:
                    J[:, j] = (r - r0) / h
                    break
            else:
                blocked[j] = why
        return J

    try:
        r0 = residuals(targets, reducer, positions)
    except SimulationError as exc:
        raise CalibrationError(f"the model fails at the starting parameters: {exc}") from None
    size = r0.size
    penalty = 10.0 * max(float(np.sqrt(np.mean(r0 ** 2))), 1.0)
    x0 = np.clip(start / scale, lower, upper)
    result = optimize.least_squares(fun, x0, jac=jacobian, bounds=(lower, upper),
                                    x_scale=1.0, max_nfev=max_evaluations)
    m, p = result.fun.size, len(names)
    if m <= p:
        raise CalibrationError(f"{m} residuals cannot fit {p} parameters")
    s2 = 2.0 * result.cost / (m - p)
    J = jacobian(result.x)                 # at the estimate, with the columns it cannot get
    _, sv, vt = np.linalg.svd(J, full_matrices=False)
    keep = sv > RANK_TOLERANCE * sv[0] if sv.size and sv[0] > 0 else np.zeros(p, bool)
    inv = (vt[keep].T / sv[keep] ** 2) @ vt[keep]
    cov = s2 * inv * np.outer(scale, scale)
    std = np.sqrt(np.clip(np.diag(cov), 0.0, None))
    notes = [n for point in points for f in point.files for n in f.notes]   # the recordings'
    notes += [f"{', '.join(f.path.name for f in point.files)}: no torque in the recording, its "
              "name or the manifest: the model ran at 0 N*m" for point in points
              if "torque_nm" not in point.point and any(f.directions for f in point.files)]
    for j, why in blocked.items():
        std[j] = np.inf
        notes.append(f"the model fails on both sides of the estimate of {names[j]} ({why}): "
                     "no interval")
    for row in vt[~keep]:                    # directions the data do not see at all
        involved = [names[i] for i in np.flatnonzero(np.abs(row) > 0.1)
                    if i not in blocked]
        if not involved:
            continue
        std[[names.index(n) for n in involved]] = np.inf
        if len(involved) > 1:
            notes.append(f"the data cannot tell {' and '.join(involved)} apart (they change "
                         "the curves the same way): fix all but one of them")
        else:
            notes.append(f"the data do not depend on {involved[0]}: it cannot be fitted")
    with np.errstate(invalid="ignore", divide="ignore"):
        corr = cov / np.outer(std, std)
    corr[~np.isfinite(corr)] = np.nan
    np.fill_diagonal(corr, 1.0)
    unfixed = {j for j in range(p) if not np.isfinite(std[j]) and j not in blocked}
    for i in range(p):
        for j in range(i + 1, p):
            if not np.isfinite(corr[i, j]):
                continue
            if abs(corr[i, j]) >= SAME_LIMIT:
                unfixed.update((i, j))
                notes.append(f"the data cannot tell {names[i]} and {names[j]} apart "
                             f"(correlation {corr[i, j]:+.4f}): fix one of them")
            elif abs(corr[i, j]) > CORRELATION_LIMIT:
                notes.append(f"{names[i]} and {names[j]} are correlated {corr[i, j]:+.3f}: the "
                             "data hardly tell them apart (wide, linked intervals)")
    if not unfixed:
        unfixed.update(_collinear(J, names, blocked, notes))
    if failed[0] and failed[0] not in blocked.values():
        notes.append(f"the model failed at some trial values (penalised): {failed[0]}")
    estimate = result.x * scale
    half = stats.t.ppf(0.975, m - p) * std
    # a linearised interval can reach beyond what the parameter can be (a clearance below
    # zero): cut at the parameter's bounds, and said
    finite = np.isfinite(half)             # no interval stays no interval
    low = np.where(finite, np.maximum(estimate - half, lower * scale), np.nan)
    high = np.where(finite, np.minimum(estimate + half, upper * scale), np.nan)
    more, unfixed = _not_fixed(J, scale, low, high, lower, upper, names, specs, unfixed,
                               blocked)
    for j in np.flatnonzero(finite & ((low > estimate - half)
                                      | (high < estimate + half))):
        if j in unfixed:                   # said by _not_fixed
            continue
        cut = [f"{b:g}" for b, moved in ((low[j], low[j] > estimate[j] - half[j]),
                                         (high[j], high[j] < estimate[j] + half[j])) if moved]
        notes.append(f"the 95 % interval of {names[j]} is cut at its bound "
                     f"{' and '.join(cut)} {specs[j].unit}: the data hardly fix it")
    notes += more
    for j in unfixed:                      # an interval of a parameter not fixed is no interval
        low[j] = high[j] = np.nan
    fitted = model_at(result.x)
    on_bound = _on_bound(result.active_mask, estimate, names, specs, unfixed, blocked, notes)
    systematic = _systematic(result.fun, _data_rms(targets), notes)
    # a parameter the data do not fix is not fitted, whatever the optimiser says
    status = ("model_fails" if blocked else "not_identifiable" if unfixed
              else "at_bound" if on_bound else "not_converged" if not result.success
              else "lack_of_fit" if systematic else "ok")
    return Calibration(names, [s.unit for s in specs], start, estimate, std, low,
                       high, corr, notes,
                       float(np.sqrt(np.mean(r0 ** 2))),
                       float(np.sqrt(np.mean(result.fun ** 2))), m, evaluations[0], status,
                       fitted, unit)


def _check_inputs(points, reducer, loops, efficiency, max_evaluations) -> None:
    """The Python call's argument types, each refused naming it (a path given as a loop was an
    AttributeError from inside the fit; the command line reads and checks the files)."""
    from ..errors import check_type
    from ..parameters import check_reducer
    from .bench import PointResult
    from .curves import EfficiencyPoints, LoopCurve

    check_reducer(reducer)
    for field, values, kind, what in (
            ("points", points, PointResult, "analysed recordings (rvsim.analyse_path)"),
            ("loops", loops, LoopCurve, "loop curves (rvsim.testrig.curves.read_loop(path))")):
        check_type(values, (list, tuple), field, f"a list of {what}")
        for value in values:
            check_type(value, kind, field, f"a list of {what}")
    if efficiency is not None:
        check_type(efficiency, EfficiencyPoints, "efficiency", "efficiency points "
                   "(rvsim.testrig.curves.read_efficiency(path)) or None")
    if isinstance(max_evaluations, bool) or not isinstance(max_evaluations, int) \
            or max_evaluations < 1:
        raise ParameterError("max_evaluations", f"must be a whole number >= 1 (got "
                             f"{max_evaluations!r})")


def _on_bound(active, estimate, names, specs, unfixed, blocked, notes) -> bool:
    """Whether the fit stopped on a parameter's bound that the data push against (scipy's
    ``active_mask``: the constraint is active, so the least-squares optimum lies outside the
    parameter's range).  Such an estimate is the bound, not a fit: a pin friction of 5e-17
    fitted to efficiency points of another set, a stiffness of 3.7e-5 to a loop recorded in
    kN*m (hostile5).  Each is said in a note."""
    hit = [j for j in np.flatnonzero(active) if j not in unfixed and j not in blocked]
    for j in hit:
        side = "lower" if active[j] < 0 else "upper"
        notes.append(f"{names[j]} stopped on its {side} bound ({estimate[j]:.6g} "
                     f"{specs[j].unit}): the data push it beyond its range, so the value is the "
                     "bound, not a fit (check the recording's units and columns and the "
                     "parameter set it is fitted from)")
    return bool(hit)


def _data_rms(targets) -> float:
    """RMS of the measured values as the residuals see them (angles [arcsec] with each group's
    mean removed, efficiencies [percentage points])."""
    parts = []
    for kind, _, _, measured in targets:
        if kind == "efficiency":
            parts.append(measured.efficiency / PERCENT)
            continue
        values = measured.angle if kind == "curve" else measured
        parts.append((values - values.mean()) / A.ARCSEC)
    values = np.concatenate(parts)
    return float(np.sqrt(np.mean(values ** 2)))


def _systematic(r, data_rms: float, notes) -> bool:
    """Whether the residuals ``r`` (each curve in the order it was measured) are systematic:
    too few runs of one sign for noise (Wald-Wolfowitz runs test about zero, one-sided, below
    :data:`LACK_OF_FIT_LEVEL`; statsmodels' ``runstest_1samp``).  The intervals hold only for
    residuals that are noise; a loop recorded in kN*m fitted by a pin stiffness of 3.7e-5 left
    9 runs where noise gives 51 (z = -8.5).  Residuals whose RMS is below the model's numerical
    resolution (ten times the quasi-static solver's relative tolerance, times ``data_rms``: a
    noise-free curve of the model itself) are not judged.  Said in a note."""
    from scipy import stats
    from statsmodels.sandbox.stats.runs import runstest_1samp

    from ..quasistatic.transmission import TOLERANCE

    r = np.asarray(r, dtype=float)
    rms = float(np.sqrt(np.mean(r ** 2))) if r.size else 0.0
    if r.size < 2 or not np.all(np.isfinite(r)) or rms <= 10.0 * TOLERANCE * data_rms:
        return False
    z, _ = runstest_1samp(r, cutoff=0.0, correction=True)
    p = float(stats.norm.cdf(z))            # too few runs: the one side that means a misfit
    if not p < LACK_OF_FIT_LEVEL:
        return False
    runs = 1 + int(np.count_nonzero(np.diff(r >= 0.0)))
    notes.append(f"the fitted model does not reproduce the data: its residuals are systematic "
                 f"({runs} runs of one sign in {r.size} residuals, runs test z = {z:.1f}, "
                 f"p = {p:.1e} < {LACK_OF_FIT_LEVEL:g}; noise changes sign at random; RMS left "
                 f"{rms / data_rms:.1%} of the data's): check the recording's units and "
                 "columns, free the parameters the misfit needs, or raise --positions (below "
                 "about 256 the model's own discretisation leaves a systematic residual)")
    return True


def _collinear(J, names, blocked, notes) -> set[int]:
    """Indices of fitted parameters that only a combination of fixes (none of them pairwise
    inseparable): the condition index of the Jacobian with its columns scaled to unit length
    (scaled, uncentred: Belsley, Kuh & Welsch 1980) above :data:`CONDITION_LIMIT`; the
    parameters of its weakest direction.  Two bushings in series fitted with the pins from one
    loop reached 184 with every pairwise correlation below 0.999 and intervals that excluded
    the true values; the fits of the guide and the tests that are fixed stay below 18."""
    columns = [j for j in range(J.shape[1]) if j not in blocked]
    norms = np.linalg.norm(J[:, columns], axis=0)
    if len(columns) < 2 or not np.all(norms > 0):
        return set()
    _, sv, vt = np.linalg.svd(J[:, columns] / norms, full_matrices=False)
    index = sv[0] / sv[-1] if sv[-1] > 0 else np.inf
    if index <= CONDITION_LIMIT:
        return set()
    weak = vt[-1] ** 2
    involved = [columns[i] for i in np.flatnonzero(weak > 0.05)]
    notes.append(f"the data fix a combination of {', '.join(names[i] for i in involved)}, not "
                 f"each (condition index {index:.0f} of the scaled Jacobian, above "
                 f"{CONDITION_LIMIT:g}: Belsley, Kuh & Welsch 1980): fix all but one of them, "
                 "or add a test that separates them")
    return set(involved)


def _not_fixed(J, scale, low, high, lower, upper, names, specs, unfixed, blocked):
    """(notes, indices) of the fitted parameters the data do not fix, beside ``unfixed``
    (no interval, or not separable from another): a Jacobian column nil beside the others',
    or a 95 % interval (``low`` .. ``high``, user units) over RANGE_COVERED of a parameter's
    finite range (``lower`` .. ``upper``, scaled)."""
    unfixed, notes = set(unfixed), []
    size = np.linalg.norm(J, axis=0)       # the curves' change per change by one scale
    top = int(np.argmax(size))
    for j, spec in enumerate(specs):
        if j in unfixed or j in blocked:
            continue
        if size.size > 1 and size[j] < NIL_SENSITIVITY * size[top]:
            unfixed.add(j)
            notes.append(f"the curves hardly depend on {names[j]} ({size[j] / size[top]:.1e}"
                         f" of their change with {names[top]}, each changed by its scale): "
                         "it cannot be fitted")
            continue
        span = (upper[j] - lower[j]) * scale[j]
        if math.isfinite(span) and high[j] - low[j] >= RANGE_COVERED * span:
            unfixed.add(j)
            notes.append(f"the 95 % interval of {names[j]} ({low[j]:g} .. {high[j]:g}"
                         f"{_unit(spec)}) covers {(high[j] - low[j]) / span:.0%} of what it can "
                         f"be ({lower[j] * scale[j]:g} .. {upper[j] * scale[j]:g}): the data "
                         "do not fix it")
    return notes, unfixed


def _unit(spec) -> str:
    return "" if spec.unit == "-" else f" {spec.unit}"
