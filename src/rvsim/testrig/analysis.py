"""The standard analyses of a bench recording (and of a model run, through the same functions).

* Transmission error: TE = theta_in / i - theta_out, cut into the complete output revolutions
  of each direction of the input (:func:`te_directions`), each revolution resampled onto
  equally spaced nodes of the nominal output angle; peak-to-peak per revolution, RMS, and the
  order spectrum of the revolution-synchronous average (:func:`rvsim.analysis.catalogue.
  order_spectrum`); the forward/backward offset (mean TE forward minus backward, one file, one
  encoder zero).
* Torque reversal: the sampled loop reduced by :func:`rvsim.analysis.catalogue.binned_sweep`
  and read by the catalogue's lost motion, backlash, hysteresis loss and rigidity.
* Efficiency: output power / input power per run.

docs/decisions.md ("Test-bench data") says how revolutions are cut, what is removed (the mean,
which an encoder zero makes arbitrary; no trend) and what the offset means numerically.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from ..analysis import catalogue
from ..analysis.catalogue import CurveError

__all__ = ["DirectionTE", "te_directions", "input_runs", "te_curve_directions", "te_summary",
           "reversal_curve", "reversal_summary", "run_efficiency", "leading_orders",
           "DEFAULT_POINTS", "ARCSEC"]

ARCSEC = math.pi / 648000.0
ARCMIN = math.pi / 10800.0
#: nodes per output revolution (orders up to 2047 resolved: the RV-40E's sun-planet mesh is
#: at order 1440)
DEFAULT_POINTS = 4096
#: nodes per output revolution a bench analysis takes (``rvsim testrig --points``)
MIN_POINTS, MAX_POINTS = 64, 65536


def check_points(points, field: str) -> int:
    """``points`` (nodes per output revolution of a bench analysis) if a whole number from
    MIN_POINTS to MAX_POINTS, else a ParameterError naming ``field``."""
    from ..errors import ParameterError

    if isinstance(points, bool) or not isinstance(points, (int, np.integer)) \
            or not MIN_POINTS <= points <= MAX_POINTS:
        raise ParameterError(field, f"must be {MIN_POINTS} to {MAX_POINTS} (got {points!r})")
    return int(points)
#: at least this many samples per node on average: nodes take the mean of their samples;
#: fewer: a cubic spline through the samples, read at the nodes
BIN_MIN_SAMPLES = 4
#: a reversal of the input counts once it has turned back by this fraction of an output
#: revolution (smaller wiggles are encoder noise at standstill)
REVERSAL_FRACTION = 1e-3


@dataclasses.dataclass
class DirectionTE:
    """TE of one direction of rotation (+1 forward: input angle increasing, -1 backward)."""

    direction: int
    revolutions: list            # [(node angle [rad] ascending, TE [rad])] one per revolution
    mean: float                  # [rad] mean TE before removal (depends on the encoder zeros)
    curve_angle: np.ndarray      # (points,) common nodes k * 2 pi / points [rad]
    curve: np.ndarray            # (points,) revolution-synchronous average, mean removed [rad]

    @property
    def pp_per_revolution(self) -> list[float]:
        return [catalogue.transmission_error_pp(te) for _, te in self.revolutions]

    @property
    def rms(self) -> float:
        te = np.concatenate([te for _, te in self.revolutions]) - self.mean
        return float(np.sqrt(np.mean(te ** 2)))

    def spectrum(self):
        """(orders, amplitude [rad]) of the averaged curve."""
        return catalogue.order_spectrum(self.curve_angle, self.curve)


def _segments(position: np.ndarray, threshold: float) -> list[tuple[int, int, int]]:
    """(start, stop, direction) runs of a position that turns back at its turning points."""
    turns = catalogue.turning_points(position, threshold)
    bounds = np.r_[0, turns, position.size - 1]
    runs = []
    for a, b in zip(bounds[:-1], bounds[1:]):
        if b > a:
            runs.append((int(a), int(b) + 1, 1 if position[b] > position[a] else -1))
    return runs


def _revolutions(progress: np.ndarray, te: np.ndarray, points: int):
    """TE at nodes k * step (step = 2 pi / points) of ``progress`` (angle travelled from the
    run's start) over the complete revolutions; (node progress, values) or None."""
    step = 2.0 * math.pi / points
    whole = int(math.floor(progress.max() / (2.0 * math.pi) + 1e-9))
    if whole < 1:
        return None
    n = whole * points
    nodes = np.arange(n) * step
    cell = np.floor(progress / step + 0.5).astype(np.int64)
    keep = (cell >= 0) & (cell < n)
    if np.count_nonzero(keep) >= BIN_MIN_SAMPLES * n:
        count = np.bincount(cell[keep], minlength=n)
        sums = np.bincount(cell[keep], te[keep], minlength=n)
        values = np.empty(n)
        full = count > 0
        values[full] = sums[full] / count[full]
        if not full.all():
            values[~full] = np.interp(nodes[~full], nodes[full], values[full])
    else:
        order = np.argsort(progress, kind="stable")
        x, y = progress[order], te[order]
        if x.size >= 4 and np.all(np.diff(x) > 0):
            # sparse samples (an exported curve, a model run): a cubic spline, which keeps
            # the amplitude of the orders a linear interpolation would damp (1 % at order 40
            # from 720 samples per revolution)
            from scipy.interpolate import CubicSpline

            values = CubicSpline(x, y)(nodes)
        else:
            values = np.interp(nodes, x, y)
    return nodes, values


def _on_common_nodes(first: float, values: np.ndarray) -> np.ndarray:
    """One revolution sampled at ``first`` + j * 2 pi / n, moved to the nodes k * 2 pi / n by
    trigonometric interpolation (exact for a curve without orders above n / 2; a linear one
    would damp order 40 by ~1 % at 512 nodes)."""
    n = values.size
    orders = np.arange(n // 2 + 1)
    return np.fft.irfft(np.fft.rfft(values) * np.exp(-1j * orders * first), n)


def _directions(position: np.ndarray, te: np.ndarray, points: int, runs) -> list[DirectionTE]:
    """Complete revolutions of every run (start, stop, sense of travel of the position,
    direction label), grouped by direction label."""
    step = 2.0 * math.pi / points
    found: dict[int, list] = {}
    for a, b, sign, label in runs:
        x, y = position[a:b], te[a:b]
        cut = _revolutions(sign * (x - x[0]), y, points)
        if cut is None:
            continue
        nodes, values = cut
        angle = x[0] + sign * nodes
        for r in range(len(values) // points):
            part = slice(r * points, (r + 1) * points)
            order = np.argsort(angle[part])
            found.setdefault(label, []).append((angle[part][order], values[part][order]))
    out = []
    common = np.arange(points) * step
    for sign in sorted(found, reverse=True):
        revs = found[sign]
        mean = float(np.mean([np.mean(v) for _, v in revs]))
        curve = np.mean([_on_common_nodes(a[0], v) for a, v in revs], axis=0)
        out.append(DirectionTE(sign, revs, mean, common, curve - curve.mean()))
    return out


def input_runs(input_angle, ratio: float) -> list[tuple[int, int, int]]:
    """(start, stop, direction) of the runs of the input between its reversals."""
    return _segments(np.asarray(input_angle, dtype=float) / ratio,
                     REVERSAL_FRACTION * 2.0 * math.pi)


def te_directions(input_angle, output_angle, ratio: float, points: int = DEFAULT_POINTS,
                  runs=None) -> list[DirectionTE]:
    """TE of a time series of encoder angles [rad], per direction of the input.

    The nominal output angle phi = theta_in / ratio is the position; runs are split where the
    input turns back (by more than :data:`REVERSAL_FRACTION` of an output revolution); each
    run's complete output revolutions are resampled at ``points`` nodes per revolution.  Node
    angles are phi shifted by the run's mean (theta_out - phi), i.e. referred to the output
    encoder's zero.  ``runs``: those of :func:`input_runs`, if already found."""
    theta_in = np.asarray(input_angle, dtype=float)
    theta_out = np.asarray(output_angle, dtype=float)
    phi = theta_in / ratio
    te = phi - theta_out
    runs = input_runs(theta_in, ratio) if runs is None else runs
    position = phi.copy()
    for a, b, _ in runs:
        position[a:b] = phi[a:b] - np.mean(te[a:b])
    return _directions(position, te, points, [(a, b, s, s) for a, b, s in runs])


def te_curve_directions(output_angle, te, direction, points: int = DEFAULT_POINTS
                        ) -> list[DirectionTE]:
    """The same for a ready-made TE curve: output position [rad], TE [rad], direction +-1 per
    sample (runs are the contiguous stretches of one direction)."""
    position = np.asarray(output_angle, dtype=float)
    te = np.asarray(te, dtype=float)
    direction = np.asarray(direction, dtype=float)
    change = np.flatnonzero(np.diff(direction) != 0) + 1
    bounds = np.r_[0, change, position.size]
    positions, values, runs, start = [], [], [], 0
    for a, b in zip(bounds[:-1], bounds[1:]):
        if b - a < 2:
            continue
        p, t = position[a:b], te[a:b]
        # a run's sense of travel is that of its positions (the column says which direction)
        sense = 1 if p[-1] > p[0] else -1
        # one revolution sampled periodically (0, 0.5, ..., 359.5 deg): the curve is closed
        # by its first sample one turn on, which it repeats
        step = float(np.median(np.abs(np.diff(p))))
        if abs(abs(p[-1] - p[0]) + step - 2.0 * math.pi) <= 0.5 * step:
            p, t = np.r_[p, p[0] + sense * 2.0 * math.pi], np.r_[t, t[0]]
        positions.append(p)
        values.append(t)
        runs.append((start, start + p.size, sense, int(direction[a])))
        start += p.size
    if not runs:
        return []
    return _directions(np.concatenate(positions), np.concatenate(values), points, runs)


def leading_orders(orders, amplitude, marks: dict, count: int = 8) -> list[dict]:
    """The ``count`` largest lines above order 0: order, amplitude [arcsec], the names of the
    reducer's orders that fall on it (``marks``: name -> order)."""
    orders = np.asarray(orders)
    amplitude = np.asarray(amplitude)
    idx = np.flatnonzero(orders > 0)
    idx = idx[np.argsort(amplitude[idx])[::-1][:count]]
    names: dict[float, list] = {}
    for name, order in marks.items():
        names.setdefault(round(float(order), 9), []).append(name)
    return [{"order": float(orders[k]), "amplitude_arcsec": float(amplitude[k] / ARCSEC),
             "name": ", ".join(names.get(round(float(orders[k]), 9), []))} for k in idx]


def te_summary(directions: list[DirectionTE], marks: dict) -> dict:
    """The TE quantities of one recording (or model run): largest peak-to-peak of a complete
    revolution, RMS, leading orders of the average of the first direction, per direction
    details and the forward/backward offset."""
    per_direction = {}
    for d in directions:
        orders, amplitude = d.spectrum()
        name = "forward" if d.direction > 0 else "backward"
        per_direction[name] = {
            "revolutions": len(d.revolutions),
            "ate_pp_arcmin": max(d.pp_per_revolution) / ARCMIN,
            "pp_per_revolution_arcmin": [v / ARCMIN for v in d.pp_per_revolution],
            "average_pp_arcmin": catalogue.transmission_error_pp(d.curve) / ARCMIN,
            "te_rms_arcsec": d.rms / ARCSEC,
            "mean_te_arcmin": d.mean / ARCMIN,
            "orders": leading_orders(orders, amplitude, marks),
        }
    first = next(iter(per_direction.values()))
    squares = [d.rms ** 2 * sum(len(v) for _, v in d.revolutions) for d in directions]
    count = sum(sum(len(v) for _, v in d.revolutions) for d in directions)
    summary = {
        "ate_pp_arcmin": max(v["ate_pp_arcmin"] for v in per_direction.values()),
        "te_rms_arcsec": math.sqrt(sum(squares) / count) / ARCSEC,
        "orders": first["orders"],
        "directions": per_direction,
    }
    if "forward" in per_direction and "backward" in per_direction:
        summary["forward_backward_offset_arcmin"] = (per_direction["forward"]["mean_te_arcmin"]
                                                     - per_direction["backward"][
                                                         "mean_te_arcmin"])
    return summary


def reversal_curve(torque, angle, bins_per_side: int = 100):
    """(torque, angle, branch) of a sampled torque-reversal recording (catalogue form)."""
    return catalogue.binned_sweep(torque, angle, bins_per_side)


def reversal_summary(torque, angle, branch, rated: float) -> dict:
    """Catalogue quantities of a torque-reversal curve; the test torque is the rated torque,
    or the loop's reach if it stops short of it (reported)."""
    (tu, _), (td, _) = catalogue.loop_branches(torque, angle, branch)
    reach = float(min(tu.max(), td.max(), -tu.min(), -td.min()))
    if not reach > 0:
        raise CurveError("torque", f"the loop does not load both ways on both branches (it "
                         f"reaches {reach:.3g} N*m where +- a test torque is needed): are the "
                         "rows in time order?")
    test = min(rated, reach)
    out = {"test_torque_nm": test,
           "torsional_rigidity_nm_per_arcmin": catalogue.torsional_rigidity(
               torque, angle, test, branch=branch) * ARCMIN,
           "lost_motion_arcmin": catalogue.lost_motion(torque, angle, branch, rated) / ARCMIN,
           "backlash_arcmin": catalogue.backlash(torque, angle, branch) / ARCMIN,
           "hysteresis_loss_arcmin": catalogue.hysteresis_loss(torque, angle, branch) / ARCMIN}
    if reach < 0.98 * rated:
        out["note"] = (f"the loop reaches +-{reach:.4g} N*m, not the rated {rated:g} N*m: "
                       "rigidity from 50-100 % of the reach")
    return out


def run_efficiency(time, input_angle, output_angle, input_torque, output_torque,
                   input_speed=None, output_speed=None) -> float:
    """Output power / input power of one run: mean torque times mean speed on each side
    (speeds from the speed columns if given, else the angles' slope over the run)."""
    t = np.asarray(time, dtype=float)
    span = t[-1] - t[0]
    if span <= 0:
        raise CurveError("time", "a run needs a positive duration")
    w_in = (np.mean(input_speed) if input_speed is not None
            else (input_angle[-1] - input_angle[0]) / span)
    w_out = (np.mean(output_speed) if output_speed is not None
             else (output_angle[-1] - output_angle[0]) / span)
    p_in = abs(float(np.mean(input_torque)) * w_in)
    p_out = abs(float(np.mean(output_torque)) * w_out)
    if p_in == 0.0:
        raise CurveError("input_torque", "no input power (zero torque or speed)")
    return p_out / p_in
