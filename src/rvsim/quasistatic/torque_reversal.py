"""The torque-reversal (hysteresis) test, quasi-static: :func:`hysteresis`.

Input locked at 0; the output torque is swept 0 -> -rated -> 0 -> +rated -> 0 -> -rated
(shared/design/catalogue_tests.md) and the whole reducer solved for static equilibrium at each
torque, each point continued from the previous one (docs/model.md, "Quasi-static analysis").
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from .._display import Headline, draw, figure, number, without_status
from ..errors import ParameterError, SimulationError
from ..parameters import Reducer, check_reducer
from ..units import ARCMIN
from .transmission import _finite, solve_path

__all__ = ["hysteresis", "HysteresisResult", "sweep_torques", "TEST_OUTPUT_SPEED"]

#: output speed of the test [rad/s] that sets the bearings' speed-dependent friction (a bench
#: turns the output this slowly or slower: Palmgren's viscous torque is at its low-speed value)
TEST_OUTPUT_SPEED = 0.01


@dataclasses.dataclass(repr=False)
class HysteresisResult(Headline):
    """Output angle against output torque, input locked (SI; contract of issue 9).  Shown as
    its catalogue quantities (:meth:`headline`); ``plot()`` draws the loop."""

    torque: np.ndarray             # (m,) [N*m] applied to the output (turns it positive)
    angle: np.ndarray              # (m,) [rad] output angle
    branch: np.ndarray             # (m,) +1 torque increasing (loading), -1 decreasing
    rated_torque: float            # [N*m]
    status: str
    wall_s: float
    converged: np.ndarray          # (m,) bool
    torsional_stiffness: np.ndarray  # (m,) [N*m/rad] local dT/dtheta_out

    def summary(self) -> dict:
        """The issue's JSON keys: catalogue quantities from rvsim.analysis.catalogue."""
        from ..analysis import catalogue                     # CATALOGUE's module (merge)

        ok = self.converged
        t, a, b = self.torque[ok], self.angle[ok], self.branch[ok]

        def quantity(compute):
            # a test stopped early (raise_on_failure=False) may not reach the torques a
            # quantity needs: NaN beside its status, never an exception from a summary
            try:
                return float(compute())
            except catalogue.CurveError:
                if self.status == "ok":
                    raise
                return math.nan

        rated = self.rated_torque
        return {
            "rated_torque_nm": rated,
            "torsional_rigidity_nm_per_arcmin": quantity(
                lambda: catalogue.torsional_rigidity(t, a, rated) * ARCMIN),
            "lost_motion_arcmin": quantity(
                lambda: catalogue.lost_motion(t, a, b, rated) / ARCMIN),
            "backlash_arcmin": quantity(lambda: catalogue.backlash(t, a, b) / ARCMIN),
            "hysteresis_loss_arcmin": quantity(
                lambda: catalogue.hysteresis_loss(t, a, b) / ARCMIN),
            "points": int(len(self.torque)),
            "wall_s": self.wall_s,
            "status": self.status,
        }

    def headline(self) -> tuple[str, list[tuple]]:
        """Status, rated torque and the report's opening rows, the catalogue quantities
        against the class (:func:`rvsim.analysis.headline.hysteresis_rows`): the repr."""
        from ..analysis.headline import hysteresis_rows

        m = self.summary()
        return (f"Torque reversal to +-{number(m['rated_torque_nm'], 'N*m')}: {m['status']}, "
                f"{m['points']} points ({number(m['wall_s'], 's', 3)} wall)",
                without_status(hysteresis_rows(m)))

    def plot(self, ax=None):
        """Output angle [arcmin] against output torque [N*m], the catalogue quantities marked
        (:func:`rvsim.plots.hysteresis_plot`); returns the first panel's Axes.  A failed test
        has no loop: SimulationError naming its status (was the curve reader's "no increasing
        branch")."""
        if self.status != "ok":
            raise SimulationError(self.status, f"no loop to draw: the torque-reversal test "
                                  f"ended {self.status} ({int(self.converged.sum())} of "
                                  f"{self.converged.size} points solved)")
        return draw(figure("rvsim.plots", "hysteresis_plot"), ax, self, self.rated_torque,
                    panels=True)

    def to_frame(self):
        """One row per point, SI with the unit in each column name (angle also in arcmin)."""
        import pandas as pd

        return pd.DataFrame({"torque_nm": self.torque, "angle_rad": self.angle,
                             "angle_arcmin": self.angle / ARCMIN, "branch": self.branch,
                             "torsional_stiffness_nm_per_rad": self.torsional_stiffness,
                             "converged": self.converged})


def sweep_torques(rated: float, points_per_branch: int) -> tuple[np.ndarray, np.ndarray]:
    """Torques 0 -> -rated -> 0 -> +rated -> 0 -> -rated, ``points_per_branch`` steps per
    quarter, and the branch of each point (+1 increasing, -1 decreasing; the first point
    belongs to the first, decreasing, quarter)."""
    ends = [0.0, -rated, 0.0, rated, 0.0, -rated]
    torque, branch = [np.array([0.0])], [np.array([-1])]
    for a, b in zip(ends[:-1], ends[1:]):
        torque.append(np.linspace(a, b, points_per_branch + 1)[1:])
        branch.append(np.full(points_per_branch, 1 if b > a else -1))
    return np.concatenate(torque), np.concatenate(branch)


def hysteresis(reducer: Reducer, *, rated_torque: float | None = None,
               points_per_branch: int = 50, raise_on_failure: bool = True,
               stiffen=None, torques=None) -> HysteresisResult:
    """Torque-reversal test with the input locked at 0 (rated torque default:
    reducer.rating.rated_torque).  ``torque`` is the torque applied to the output (positive
    turns it in the positive sense; the output load of the dynamic model and of :func:`ltca`
    is its negative, a resisting torque), so the curve rises: angle grows with torque.

    At exactly 0 N*m nothing holds the output: it stays at the contact on the side it comes
    from (the solver leaves an unloaded body where it was), so each branch crosses zero at its
    own side of the clearance.

    ``stiffen`` (element name -> factor, :mod:`rvsim.physics.stiffening`): the test of the
    model with those elements stiffer (the compliance budget, :mod:`rvsim.quasistatic.budget`).

    ``torques`` [N*m]: the torque history of a recording to follow instead of the standard
    sweep (a calibration to a measured loop, :mod:`rvsim.testrig.curves`), each sample's
    branch from the sweep itself (:func:`rvsim.analysis.catalogue.sweep_branches`); its
    largest magnitude is the test's rated torque and ``rated_torque`` and
    ``points_per_branch`` are not used.
    """
    check_reducer(reducer)
    if torques is not None:
        return _follow(reducer, torques, stiffen, raise_on_failure)
    rated = _finite("rated_torque", reducer.rating.rated_torque if rated_torque is None
                    else rated_torque)
    if rated <= 0:
        raise ParameterError("rated_torque", f"must be positive (got {rated:g})")
    from ..parameters.rating import check_torque

    check_torque(reducer, rated, "rated_torque")
    from ..analysis.sampling import MAX_POSITIONS

    most = (MAX_POSITIONS - 1) // 5          # five quarters (sweep_torques) and the start
    if isinstance(points_per_branch, bool) or not isinstance(points_per_branch,
                                                             (int, np.integer)) \
            or not 2 <= points_per_branch <= most:
        # 10**8 asked numpy for 763 MiB, 10**7 in the budget for 6.33 GiB
        raise ParameterError("points_per_branch",
                             f"must be an integer from 2 to {most}, a test of at most "
                             f"{MAX_POSITIONS} points (got {points_per_branch!r})")

    torque, branch = sweep_torques(rated, points_per_branch)
    return _solve(reducer, torque, branch, rated, stiffen, raise_on_failure)


def _follow(reducer: Reducer, torques, stiffen, raise_on_failure: bool) -> HysteresisResult:
    """The test along the torque history ``torques`` (:func:`hysteresis`)."""
    from ..analysis.catalogue import CurveError, sweep_branches
    from ..parameters.rating import check_torque

    try:
        torque = np.asarray(torques, dtype=float).ravel()
    except (TypeError, ValueError):
        raise ParameterError("torques", f"must be numbers [N*m] (got {torques!r:.60})") from None
    if not np.all(np.isfinite(torque)):
        raise ParameterError("torques", "every torque must be a finite number")
    try:
        branch = sweep_branches(torque).astype(int)
    except CurveError as exc:
        raise ParameterError("torques", str(exc)) from None
    rated = float(np.max(np.abs(torque)))
    if rated <= 0:
        raise ParameterError("torques", "the torques are all zero")
    check_torque(reducer, rated, "torques")
    return _solve(reducer, torque, branch, rated, stiffen, raise_on_failure)


def _solve(reducer, torque, branch, rated, stiffen, raise_on_failure) -> HysteresisResult:
    """Equilibrium along ``torque`` (applied to the output, input locked), friction following
    ``branch``."""
    from ..physics import _layout as L

    # the model's output load resists the motion: a load of -T is a torque T applied
    # friction follows the output's motion: turning with the torque's change (the first point
    # belongs to the first, decreasing quarter)
    path = solve_path(reducer, np.zeros(len(torque)), -torque,
                      carrier_rate=TEST_OUTPUT_SPEED * branch, stiffen=stiffen)
    converged = path.status_codes == 0
    angle = path.q[:, L.CARRIER].copy()
    angle[~converged] = np.nan
    result = HysteresisResult(torque=torque, angle=angle, branch=branch, rated_torque=rated,
                              status=path.status, wall_s=path.wall_s, converged=converged,
                              torsional_stiffness=path.torsional_stiffness)
    if path.status != "ok" and raise_on_failure:
        k = int(np.argmax(path.status_codes != 0))
        raise SimulationError(path.status, f"torque-reversal test stopped at {torque[k]:.6g} "
                              f"N*m: {path.status.replace('_', ' ')}")
    return result
