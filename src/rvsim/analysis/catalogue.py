"""The quantities precision reducers are specified and accepted by, computed from curves.

Pure functions, SI in and SI out (N*m, rad), independent of where the curve comes from: the
quasi-static engine (:mod:`rvsim.quasistatic`) or a test bench.  Definitions follow
GB/T 35089-2018 (bench tests of robot precision reducers) and the catalogues that use its
wording; docs/catalogue_tests.md states each one, the interval used and the discretisation.

Torque-reversal (hysteresis) curve: ``torque``, ``angle`` (output rotation, input locked) and
``branch`` (+1 where the torque increases, -1 where it decreases), in sweep order.  The test
sequence is 0 -> -rated -> 0 -> +rated -> 0 -> -rated; the *loop* is the last increasing run
(-rated -> +rated) and the last decreasing run (+rated -> -rated); the first run from the
unloaded state is not part of it.

Near zero torque a curve with clearance jumps (the output crosses its free play at 0 N*m), so a
branch is never interpolated across zero: each side of zero is read from its own samples, and
the value *at* zero from a side is the linear extrapolation of that side's two samples nearest
zero (exact when a sample lies at 0 N*m, as the quasi-static engine provides).  A sample at
exactly 0 N*m belongs to the side the sweep reached it from.
"""

from __future__ import annotations

import math

import numpy as np

from ..errors import RvsimError

__all__ = ["CurveError", "loop_branches", "sweep_branches", "branch_side", "angle_at",
           "torsional_rigidity", "lost_motion", "backlash", "hysteresis_loss",
           "transmission_error_pp", "angular_transmission_error", "order_spectrum", "reducer_orders", "loop_arrays",
           "LOST_MOTION_FRACTION", "turning_points", "binned_sweep"]

#: lost motion is read at +- this fraction of rated torque (GB/T 35089-2018, catalogues)
LOST_MOTION_FRACTION = 0.03


class CurveError(RvsimError, ValueError):
    """A curve cannot give the requested quantity (too few points, wrong range, not finite)."""

    def __init__(self, field: str, reason: str):
        self.field = field
        self.reason = reason
        super().__init__(f"curve '{field}': {reason}")


# --- checks -------------------------------------------------------------------------------

def _vector(name: str, values, n: int | None = None) -> np.ndarray:
    array = np.asarray(values, dtype=float)
    if array.ndim != 1:
        raise CurveError(name, f"must be one-dimensional (got shape {array.shape})")
    if n is not None and array.shape[0] != n:
        raise CurveError(name, f"has {array.shape[0]} values, the torque has {n}")
    if not np.all(np.isfinite(array)):
        raise CurveError(name, "contains NaN or infinite values")
    return array


def _rated(rated: float) -> float:
    if isinstance(rated, bool) or not (isinstance(rated, (int, float, np.number))
                                       and math.isfinite(rated) and rated > 0):
        raise CurveError("rated", f"rated torque must be a positive finite number (got {rated!r})")
    return float(rated)


def loop_branches(torque, angle, branch) -> tuple[tuple[np.ndarray, np.ndarray],
                                                 tuple[np.ndarray, np.ndarray]]:
    """The loop's increasing and decreasing branches, each (torque, angle) in sweep order:
    the last run of increasing and the last run of decreasing torque, each starting at the
    reversal point that precedes it."""
    torque = _vector("torque", torque)
    angle = _vector("angle", angle, torque.size)
    branch = _vector("branch", branch, torque.size)
    if not np.all(np.isin(branch, (1.0, -1.0))):
        raise CurveError("branch", "must be +1 (torque increasing) or -1 (decreasing)")
    out = []
    for sign, name in ((1.0, "increasing"), (-1.0, "decreasing")):
        idx = np.flatnonzero(branch == sign)
        if idx.size == 0:
            raise CurveError("branch", f"the curve has no {name} branch")
        # the last contiguous run of this branch
        breaks = np.flatnonzero(np.diff(idx) != 1)
        run = idx[breaks[-1] + 1:] if breaks.size else idx
        # the reversal point that ends the previous run starts this one as well
        if run[0] > 0 and sign * (torque[run[0]] - torque[run[0] - 1]) > 0:
            run = np.r_[run[0] - 1, run]
        t = torque[run]
        if run.size > 1 and not np.all(sign * np.diff(t) > 0):
            raise CurveError("torque", f"the {name} branch is not strictly {name}")
        out.append((t, angle[run]))
    return out[0], out[1]


def sweep_branches(torque) -> np.ndarray:
    """The branch of every sample from the sweep itself: +1 where the torque rose to it, -1
    where it fell to it (the first sample takes the direction of the first step)."""
    torque = _vector("torque", torque)
    if torque.size < 2:
        raise CurveError("torque", f"too few points ({torque.size}, at least 2 needed)")
    step = np.sign(np.diff(torque))
    if np.any(step == 0):
        raise CurveError("torque", "repeats a value in consecutive samples (no sweep "
                         "direction); give 'branch'")
    return np.r_[step[0], step]


def branch_side(torque: np.ndarray, angle: np.ndarray, sign: float):
    """(torque, angle) samples of one branch on the ``sign`` side of zero torque, ordered
    away from zero; a sample at 0 N*m belongs to the side the sweep reached it from."""
    signs = np.sign(torque)
    # a sample at exactly 0 N*m belongs to the side the sweep reached it from
    owner = signs.copy()
    last = 0.0
    for i, s in enumerate(signs):
        if s != 0:
            last = s
        else:
            owner[i] = last
    if owner.size and owner[0] == 0:           # zeros before any nonzero sample: next side
        first = signs[np.flatnonzero(signs)[0]] if np.any(signs) else 0.0
        owner[owner == 0] = first
    keep = owner == sign
    t, a = torque[keep], angle[keep]
    order = np.argsort(sign * t, kind="stable")
    return t[order], a[order]


def angle_at(torque: np.ndarray, angle: np.ndarray, sign: float, value: float,
             what: str = "curve") -> float:
    """Angle of one branch (``torque``, ``angle`` in sweep order) at torque ``value``, read
    from the branch's samples on the ``sign`` side of zero only (``value`` has that sign or
    is 0); between zero and the first sample the first segment is extended."""
    t, a = branch_side(torque, angle, sign)
    direction = "positive" if sign > 0 else "negative"
    if t.size < 2:
        raise CurveError("torque", f"too few points on the {direction} side of the curve "
                         f"({t.size}, at least 2 needed) for the {what}")
    x, y = sign * t, a                          # x increases away from zero
    target = sign * value
    if target > x[-1] * (1 + 1e-12):
        raise CurveError("torque", f"never reaches {value:g} N*m on the {direction} side "
                         f"(largest {t[-1]:g} N*m), needed for the {what}")
    if target >= x[0]:
        return float(np.interp(target, x, y))
    # between zero and the first sample: extend that side's first segment
    slope = (y[1] - y[0]) / (x[1] - x[0])
    return float(y[0] + slope * (target - x[0]))


def _crosses_zero(t: np.ndarray, name: str) -> None:
    if not (t.min() <= 0.0 <= t.max()):
        raise CurveError("torque", f"the {name} branch does not cross 0 N*m "
                         f"(range {t.min():g} .. {t.max():g} N*m)")


def loop_arrays(hysteresis):
    """(torque, angle, branch, local stiffness or None) of a torque-reversal result object
    (attributes ``torque``, ``angle``, ``branch``, optional ``converged`` and
    ``torsional_stiffness``), its converged points only."""
    n = len(hysteresis.torque)
    ok = np.asarray(getattr(hysteresis, "converged", np.ones(n, dtype=bool)), dtype=bool)
    stiffness = getattr(hysteresis, "torsional_stiffness", None)
    arrays = [np.asarray(v, dtype=float)[ok] for v in (hysteresis.torque, hysteresis.angle,
                                                        hysteresis.branch)]
    if stiffness is not None:
        stiffness = np.asarray(stiffness, dtype=float)[ok]
        if not np.all(np.isfinite(stiffness)):
            stiffness = None
    return (*arrays, stiffness)


# --- sampled (bench) sweeps ------------------------------------------------------------------

def turning_points(values, threshold: float) -> np.ndarray:
    """Indices where a noisy sweep reverses: a running extreme counts as a turning point once
    the signal has retreated from it by more than ``threshold`` (so noise makes no reversal
    while its peak-to-peak stays below the threshold).  Returns the indices of the extremes,
    in order."""
    x = _vector("values", values)
    if not (math.isfinite(threshold) and threshold > 0):
        raise CurveError("threshold", f"must be positive (got {threshold!r})")
    # the first move beyond the threshold sets the first direction
    up = np.flatnonzero(x - np.minimum.accumulate(x) > threshold)
    down = np.flatnonzero(np.maximum.accumulate(x) - x > threshold)
    if not (up.size or down.size):
        return np.zeros(0, dtype=int)
    direction = 1.0 if (up[0] if up.size else x.size) < (down[0] if down.size else x.size) \
        else -1.0
    turns = []
    start = 0
    while True:
        rest = direction * x[start:]              # looking for a maximum of direction * x
        past = np.flatnonzero(np.maximum.accumulate(rest) - rest > threshold)
        if not past.size:
            break
        start += int(np.argmax(rest[:past[0] + 1]))
        turns.append(start)
        direction = -direction
    return np.asarray(turns, dtype=int)


def binned_sweep(torque, angle, bins_per_side: int = 100, threshold: float | None = None):
    """A sampled torque sweep (a bench's time series: noisy torque, angle) as the curve the
    torque-reversal functions take: each run between turning points (:func:`turning_points`,
    ``threshold`` default 5 % of the largest torque) reduced to the means of its samples in
    torque bins (``bins_per_side`` on each side of zero, 0 N*m an edge so that no bin mixes the
    two sides of a free play; the samples in the two bins next to zero are left out: the
    free play is crossed there and the torque noise cannot tell its sides apart), in sweep
    order.  Returns (torque, angle, branch)."""
    torque = _vector("torque", torque)
    angle = _vector("angle", angle, torque.size)
    top = float(np.max(np.abs(torque)))
    if top == 0.0:
        raise CurveError("torque", "is zero throughout")
    threshold = 0.05 * top if threshold is None else threshold
    turns = turning_points(torque, threshold)
    bounds = np.r_[0, turns, torque.size - 1]
    edges = np.linspace(-top, top, 2 * bins_per_side + 1)
    width = top / bins_per_side
    out_t, out_a, out_b = [], [], []
    for a, b in zip(bounds[:-1], bounds[1:]):
        if b <= a:
            continue
        t, y = torque[a:b + 1], angle[a:b + 1]
        sign = 1.0 if t[-1] > t[0] else -1.0
        # a free play is crossed at zero torque, where the torque noise cannot tell the two
        # sides apart: the samples within one bin of zero are left out (the catalogue's
        # readings extend each side's first segment to zero)
        keep = np.abs(t) >= width
        t, y = t[keep], y[keep]
        if t.size == 0:
            continue
        cell = np.clip(np.searchsorted(edges, t, side="right") - 1, 0, edges.size - 2)
        count = np.bincount(cell, minlength=edges.size - 1)
        used = np.flatnonzero(count)
        mean_t = np.bincount(cell, t, edges.size - 1)[used] / count[used]
        mean_a = np.bincount(cell, y, edges.size - 1)[used] / count[used]
        if sign < 0:
            mean_t, mean_a = mean_t[::-1], mean_a[::-1]
        out_t.append(mean_t)
        out_a.append(mean_a)
        out_b.append(np.full(mean_t.size, sign))
    if not out_t:
        raise CurveError("torque", "has no sweep (no run between turning points)")
    return np.concatenate(out_t), np.concatenate(out_a), np.concatenate(out_b)


# --- torque-reversal quantities -------------------------------------------------------------

def torsional_rigidity(torque, angle, rated: float, low: float = 0.5, high: float = 1.0, *,
                       branch=None, direction: str = "both") -> float:
    """Torsional rigidity b/a [N*m/rad]: the secant of the loading curve between ``low`` and
    ``high`` times rated torque (catalogue definition: 50 % to 100 %).

    Positive direction: the increasing branch between +low*rated and +high*rated; negative
    direction: the decreasing branch between -low*rated and -high*rated.  ``direction`` "both"
    (default) averages the two secants; "positive" or "negative" gives one.  Without
    ``branch`` a monotone curve is one loading sweep, any other curve is split into branches
    by its sweep direction (:func:`sweep_branches`).
    """
    rated = _rated(rated)
    if not (0.0 <= low < high):
        raise CurveError("low", f"needs 0 <= low < high (got {low:g}, {high:g})")
    if branch is None:
        steps = np.diff(_vector("torque", torque))
        if steps.size and (np.all(steps > 0) or np.all(steps < 0)):
            up = down = (_vector("torque", torque), _vector("angle", angle, steps.size + 1))
        else:
            branch = sweep_branches(torque)
    if branch is not None:
        up, down = loop_branches(torque, angle, branch)
    what = f"torsional rigidity ({low:.0%} to {high:.0%} of rated)"

    def secant(start: float, end: float) -> float:
        # a curve whose angle stands still over the span (a coarse or stuck encoder) has no
        # rigidity to give: named, not a division by zero
        if not end - start > 0:
            raise CurveError("angle", f"the angle does not increase with the torque between "
                             f"{low:.0%} and {high:.0%} of rated (it changes by "
                             f"{end - start:.3g} rad: a stuck or too coarse angle encoder?)")
        return (high - low) * rated / (end - start)

    secants = []
    if direction in ("both", "positive"):
        secants.append(secant(angle_at(*up, 1.0, low * rated, what),
                              angle_at(*up, 1.0, high * rated, what)))
    if direction in ("both", "negative"):
        secants.append(secant(angle_at(*down, -1.0, -high * rated, what),
                              angle_at(*down, -1.0, -low * rated, what)))
    if not secants:
        raise CurveError("direction", f"must be 'both', 'positive' or 'negative' "
                         f"(got {direction!r})")
    value = float(np.mean(secants))
    if not (math.isfinite(value) and value > 0):
        raise CurveError("angle", "the angle does not increase with the torque between "
                         f"{low:.0%} and {high:.0%} of rated")
    return value


def lost_motion(torque, angle, branch, rated: float,
                fraction: float = LOST_MOTION_FRACTION) -> float:
    """Lost motion [rad]: the angle between the mid-points of the hysteresis width at
    +``fraction`` and -``fraction`` of rated torque (3 %)."""
    rated = _rated(rated)
    if isinstance(fraction, bool) or not (isinstance(fraction, (int, float, np.number))
                                          and 0.0 < fraction < 1.0):
        raise CurveError("fraction", f"must be a fraction of rated torque between 0 and 1 "
                         f"(got {fraction!r})")
    up, down = loop_branches(torque, angle, branch)
    what = f"lost motion (+-{fraction:.0%} of rated)"
    mids = []
    for sign in (1.0, -1.0):
        value = sign * fraction * rated
        mids.append(0.5 * (angle_at(*up, sign, value, what)
                           + angle_at(*down, sign, value, what)))
    return float(mids[0] - mids[1])


def _zero_width(torque, angle, branch, what: str) -> float:
    """The angle between the two branches where they cross 0 N*m, each read at zero from the
    side the sweep reaches it from: the decreasing branch (coming from positive torque) minus
    the increasing branch (coming from negative torque)."""
    up, down = loop_branches(torque, angle, branch)
    _crosses_zero(up[0], "increasing")
    _crosses_zero(down[0], "decreasing")
    return float(angle_at(*down, 1.0, 0.0, what) - angle_at(*up, -1.0, 0.0, what))


def backlash(torque, angle, branch) -> float:
    """Backlash [rad]: the angle between the two branches where they cross 0 N*m.

    On a loop loaded to rated torque this is the hysteresis loss; the catalogue's backlash
    comes from a reversal at small torque, whose loop then contains little friction
    hysteresis.  Without friction both are the free play of the clearances."""
    return _zero_width(torque, angle, branch, "backlash")


def hysteresis_loss(torque, angle, branch, rated: float | None = None) -> float:
    """Hysteresis loss [rad]: the width of the loop at 0 N*m after loading to rated torque and
    unloading: the decreasing branch coming from +rated minus the increasing branch coming
    from -rated (equals the backlash when there is no friction).  With ``rated`` the loop
    must reach +-rated."""
    if rated is not None:
        rated = _rated(rated)
        up, down = loop_branches(torque, angle, branch)
        reach = min(up[0].max(), down[0].max(), -up[0].min(), -down[0].min())
        if reach < rated * (1 - 1e-9):
            raise CurveError("torque", f"the loop reaches only +-{reach:g} N*m, not the rated "
                             f"{rated:g} N*m")
    return _zero_width(torque, angle, branch, "hysteresis loss")


# --- transmission error ---------------------------------------------------------------------

def transmission_error_pp(te) -> float:
    """Peak-to-peak of the TE [rad] (the catalogue's angular transmission error when ``te``
    covers one output revolution in one direction)."""
    te = _vector("te", te)
    if te.size < 2:
        raise CurveError("te", f"too few points ({te.size}, at least 2 needed)")
    return float(np.ptp(te))


def angular_transmission_error(output_angle, te) -> tuple[float, float]:
    """(ATE, output revolutions covered) of a TE curve sampled in one direction of rotation.

    The ATE (GB/T 35089-2018, the catalogues; docs/catalogue_tests.md) is the peak-to-peak of
    ``te`` over one output revolution; over several complete revolutions the largest of their
    peak-to-peaks (as :mod:`rvsim.testrig.analysis` reads a bench recording), NaN when the
    samples cover less than one revolution.  ``output_angle`` [rad] is the output's angle at
    each sample, equally spaced (in time or angle); each sample stands for its spacing, so
    ``n`` samples cover ``n`` spacings: 360 positions ``k * 2 pi / 360`` are one revolution.
    Sample ``k`` belongs to revolution ``floor(|output_angle[k] - output_angle[0]| / 2 pi)``.
    Returns the ATE in the unit of ``te`` and the revolutions covered (0 below two samples).
    """
    angle = _vector("output_angle", output_angle)
    te = _vector("te", te)
    if te.size != angle.size:
        raise CurveError("te", f"has {te.size} values, the output angle has {angle.size}")
    if angle.size < 2:
        return math.nan, 0.0
    travel = np.abs(angle - angle[0]) / (2.0 * math.pi)
    covered = float(travel[-1] * angle.size / (angle.size - 1))
    complete = int(math.floor(covered + 1e-9))       # round-off of n equal spacings
    if complete < 1:
        return math.nan, covered
    revolution = np.floor(travel + 1e-9).astype(int)
    return max(transmission_error_pp(te[revolution == k]) for k in range(complete)), covered


def order_spectrum(angle_out, te, *, window: str = "rectangular", with_phase: bool = False):
    """Amplitude spectrum of ``te`` in orders of the output revolution.

    ``angle_out`` [rad] must be equally spaced (nominal output angle, e.g. input angle / i)
    and cover whole output revolutions, endpoint excluded.  Then each integer order k is an
    exact Fourier bin and the default rectangular window has no leakage: a harmonic
    A*cos(k*angle_out + phase) gives amplitude A at order k to round-off.  ``window="hann"``
    (amplitude corrected by the window's coherent gain) is for signals that are not periodic
    over the record.  Returns (orders, amplitude [rad]) and, ``with_phase``, the phase [rad]
    of each order referred to angle_out = 0: te = sum A_k cos(k*angle_out + phase_k).
    """
    te = _vector("te", te)
    angle = _vector("angle_out", angle_out, te.size)
    n = te.size
    if n < 4:
        raise CurveError("te", f"too few points ({n}, at least 4 needed) for a spectrum")
    steps = np.diff(angle)
    step = float(np.mean(steps))
    if step == 0.0 or np.max(np.abs(steps - step)) > 1e-6 * abs(step):
        raise CurveError("angle_out", "must be equally spaced (use the nominal output angle, "
                         "input angle / ratio)")
    revolutions = n * abs(step) / (2.0 * math.pi)
    whole = round(revolutions)
    if whole < 1 or abs(revolutions - whole) > 1e-6 * revolutions:
        raise CurveError("angle_out", f"must cover whole output revolutions, endpoint "
                         f"excluded (covers {revolutions:.6g})")
    if window == "rectangular":
        weights = np.ones(n)
    elif window == "hann":
        weights = np.hanning(n + 1)[:-1]     # periodic Hann
    else:
        raise CurveError("window", f"must be 'rectangular' or 'hann' (got {window!r})")
    spectrum = np.fft.rfft(te * weights) / np.sum(weights)
    amplitude = 2.0 * np.abs(spectrum)
    amplitude[0] *= 0.5
    if n % 2 == 0:
        amplitude[-1] *= 0.5
    orders = np.arange(spectrum.size) / whole
    if not with_phase:
        return orders, amplitude
    sign = 1.0 if step > 0 else -1.0
    phase = sign * np.angle(spectrum) - orders * angle[0]
    phase = np.angle(np.exp(1j * phase))          # wrap to (-pi, pi]
    return orders, amplitude, phase


def reducer_orders(reducer) -> dict[str, float]:
    """Orders of the output revolution at which an RV reducer's TE can have lines.

    With the housing fixed and the carrier the output (one output revolution):
    the disc turns once, so a fixed pin meets ``disc_teeth`` zc teeth and the eccentric turns
    zc times absolutely (pins fixed: disc = -eccentric / zc); the crank turns
    (i - 1) z1 / z2 = zp times relative to the carrier (= zc + 1); the load pattern passes the
    zp pins once per crank turn relative to the carrier; the input shaft turns i times; the
    sun meets (i - 1) z1 planet teeth relative to the carrier.  Multiples 2 zc, 2 zp follow.

    Single-stage drive (output pins): the eccentric shaft is the input and turns |i| = zc
    times per output revolution (in the housing; zp = zc + 1 times relative to the output);
    the output pins pass a given disc position n_w times per eccentric turn relative to
    the output.  With the pin ring as output the eccentric turns i - 1 = zc / (zp - zc) times
    per output revolution relative to the ring.
    """
    g, c = reducer.gears, reducer.cycloid
    if reducer.layout.single_stage and reducer.layout.ring_output:
        # the pin ring is the output: the eccentric turns i - 1 = zc / (zp - zc) times per
        # ring revolution relative to it; the output pins stand still
        return {
            "output": 1.0,
            "disc teeth zc": float(c.disc_teeth),
            "eccentric (rel. output)": float(reducer.ratio - 1.0),
            "pins zp": float(c.pin_count),
            "2 zc": 2.0 * c.disc_teeth,
            "2 zp": 2.0 * c.pin_count,
            "input shaft i": float(reducer.ratio),
        }
    if reducer.layout.single_stage:
        relative = abs(reducer.ratio) + 1.0
        return {
            "output": 1.0,
            "disc teeth zc": float(c.disc_teeth),
            "eccentric (rel. output)": float(relative),
            "pins zp": float(c.pin_count),
            "2 zc": 2.0 * c.disc_teeth,
            "2 zp": 2.0 * c.pin_count,
            "input shaft |i|": float(abs(reducer.ratio)),
            "output pins": float(reducer.layout.output_pin_count),
        }
    ratio = reducer.ratio
    crank = (ratio - 1.0) * g.sun_teeth / g.planet_teeth
    return {
        "output": 1.0,
        "disc teeth zc": float(c.disc_teeth),
        "crank (rel. carrier)": float(crank),
        "pins zp": float(c.pin_count),
        "2 zc": 2.0 * c.disc_teeth,
        "2 zp": 2.0 * c.pin_count,
        "input shaft i": float(ratio),
        "sun-planet mesh": float((ratio - 1.0) * g.sun_teeth),
    }
