"""A test-only stand-in for ``rvsim.quasistatic`` (ENGINE's module), following the contract of
issue9_plan.md: ``ltca``, ``hysteresis``, ``LtcaResult``, ``HysteresisResult``.

Its physics is a closed-form toy (a two-slope spring with the reducer's clearance-opening
errors as free play, a TE made of known harmonics); it lets the commands, reports, joint export
and study engine be tested before the real solver is merged.  The ``standin`` fixture puts it
in ``sys.modules["rvsim.quasistatic"]`` for one test.  A torque above 1e5 N*m "fails to
converge" (raising SimulationError unless raise_on_failure=False, as the engine does) so the
failure paths can be tested.
"""

from __future__ import annotations

import dataclasses
import sys
import types

import numpy as np
import pandas as pd
import pytest

from rvsim.analysis import catalogue
from rvsim.errors import SimulationError
from rvsim.units import ARCMIN

RATED = 412.0
STIFFNESS = 35.0 / ARCMIN                     # N*m/rad (35 N*m/arcmin)
FAIL_ABOVE = 1e5


def _free_play(reducer) -> float:
    e = reducer.errors
    opening = e.pin_radius + e.pin_circle_radius + e.equidistant_modification \
        + e.radial_modification
    c = reducer.cycloid
    return 2.0 * max(opening, 0.0) / (c.eccentricity * c.disc_teeth) * 117.0 / 121.0


@dataclasses.dataclass
class LtcaResult:
    input_angle: np.ndarray
    output_angle: np.ndarray
    te: np.ndarray
    torque: float
    ratio: float
    pin_count: int
    disc_teeth: int
    pin_forces: np.ndarray
    contact_stress: np.ndarray
    arm_forces: np.ndarray
    support_forces: np.ndarray
    mesh_forces: np.ndarray
    mesh_stiffness: np.ndarray
    torsional_stiffness: np.ndarray
    status: str
    wall_s: float
    converged: np.ndarray

    @property
    def te_relative(self) -> np.ndarray:
        return self.te - self.te.mean()

    def summary(self) -> dict:
        contact = (self.pin_forces > 0).sum(axis=(1, 2))
        return {"te_mean_arcmin": float(self.te.mean() / ARCMIN),
                "te_pp_arcmin": catalogue.transmission_error_pp(self.te) / ARCMIN,
                "max_pin_force_n": float(self.pin_forces.max()),
                "pins_in_contact_min": int(contact.min()),
                "pins_in_contact_max": int(contact.max()),
                "max_contact_stress_mpa": float(self.contact_stress.max() / 1e6),
                "torsional_stiffness_nm_per_arcmin":
                    float(self.torsional_stiffness.mean() * ARCMIN),
                "positions": int(self.te.size), "wall_s": self.wall_s, "status": self.status}

    def spectrum(self) -> pd.DataFrame:
        orders, amp = catalogue.order_spectrum(self.input_angle / self.ratio, self.te)
        return pd.DataFrame({"order": orders, "amplitude_arcmin": amp / ARCMIN})

    def to_frame(self) -> pd.DataFrame:
        return pd.DataFrame({"input_angle_rad": self.input_angle,
                             "output_angle_rad": self.output_angle, "te_rad": self.te})


@dataclasses.dataclass
class HysteresisResult:
    torque: np.ndarray
    angle: np.ndarray
    branch: np.ndarray
    rated_torque: float
    status: str
    wall_s: float
    converged: np.ndarray
    torsional_stiffness: np.ndarray

    def summary(self) -> dict:
        # as the engine (h-engine f692b5d): converged points, rigidity without 'branch'
        ok = self.converged
        t, a, b, r = self.torque[ok], self.angle[ok], self.branch[ok], self.rated_torque
        return {"rated_torque_nm": r,
                "torsional_rigidity_nm_per_arcmin":
                    catalogue.torsional_rigidity(t, a, r) * ARCMIN,
                "lost_motion_arcmin": catalogue.lost_motion(t, a, b, r) / ARCMIN,
                "backlash_arcmin": catalogue.backlash(t, a, b) / ARCMIN,
                "hysteresis_loss_arcmin": catalogue.hysteresis_loss(t, a, b) / ARCMIN,
                "wall_s": self.wall_s, "status": self.status}

    def to_frame(self) -> pd.DataFrame:
        return pd.DataFrame({"torque_nm": self.torque, "angle_rad": self.angle,
                             "branch": self.branch})


def _failed(result, raise_on_failure: bool, what: str):
    if result.status != "ok" and raise_on_failure:
        raise SimulationError(result.status, f"{what} stopped: not converged")
    return result


def ltca(reducer, *, torque=None, positions=360, revolutions=1.0,
         raise_on_failure=True) -> LtcaResult:
    torque = reducer.operating.load_torque if torque is None else torque
    ratio, zp, zc = reducer.ratio, reducer.cycloid.pin_count, reducer.cycloid.disc_teeth
    n = int(positions)
    input_angle = np.arange(n) * 2 * np.pi * ratio * revolutions / n
    out = input_angle / ratio
    wind = torque / STIFFNESS + np.sign(torque) * 0.5 * _free_play(reducer)
    te = (wind + 0.05 * ARCMIN * np.cos(zc * out + 0.4) + 0.02 * ARCMIN * np.cos(zp * out)
          + 0.01 * ARCMIN * np.cos(out - 1.0))
    gamma = 2 * np.pi * np.arange(zp) / zp
    phase = zc * out[:, None, None] + np.array([0.0, np.pi])[None, :, None] - gamma
    share = np.clip(np.sin(phase), 0.0, None)
    forces = abs(torque) / (0.0015 * zc) * share / share.sum(axis=2, keepdims=True) / 2
    ok = abs(torque) <= FAIL_ABOVE
    return _failed(LtcaResult(input_angle, out - te, te, float(torque), ratio, zp, zc, forces,
                              8e8 * np.sqrt(forces / (forces.max() + 1e-30)),
                              np.zeros((n, 2, 2)), np.zeros((n, 2, 2)), np.zeros((n, 2)),
                              np.full((n, 2), 1e8), np.full(n, STIFFNESS),
                              "ok" if ok else "not_converged", 0.01, np.full(n, ok)),
                   raise_on_failure, "ltca")


def hysteresis(reducer, *, rated_torque=None, points_per_branch=41,
               raise_on_failure=True) -> HysteresisResult:
    # main's parameter (issue 8: reducer.rating.rated_torque) where present
    default = getattr(getattr(reducer, "rating", None), "rated_torque", RATED)
    rated = default if rated_torque is None else float(rated_torque)
    clear = _free_play(reducer)
    grid = np.linspace(-rated, rated, points_per_branch)

    def angle(t, came_from):
        side = np.where(t > 0, 1.0, np.where(t < 0, -1.0, came_from))
        return t / STIFFNESS + side * clear / 2

    first = np.linspace(0.0, -rated, points_per_branch // 2 + 1)
    torque = np.concatenate([first, grid[1:], grid[::-1][1:]])
    ang = np.concatenate([angle(first, -1.0), angle(grid[1:], -1.0), angle(grid[::-1][1:], 1.0)])
    branch = np.concatenate([-np.ones(first.size), np.ones(grid.size - 1),
                             -np.ones(grid.size - 1)])
    ok = rated <= FAIL_ABOVE
    return _failed(HysteresisResult(torque, ang, branch, rated, "ok" if ok else "not_converged",
                                    0.02, np.full(torque.size, ok),
                                    np.full(torque.size, STIFFNESS)),
                   raise_on_failure, "hysteresis")


def module() -> types.ModuleType:
    mod = types.ModuleType("rvsim.quasistatic")
    mod.ltca, mod.hysteresis = ltca, hysteresis
    mod.LtcaResult, mod.HysteresisResult = LtcaResult, HysteresisResult
    mod.__all__ = ["ltca", "hysteresis", "LtcaResult", "HysteresisResult"]
    return mod


@pytest.fixture
def standin(monkeypatch):
    """``rvsim.quasistatic`` replaced by this stand-in for one test."""
    import rvsim

    mod = module()
    monkeypatch.setitem(sys.modules, "rvsim.quasistatic", mod)
    monkeypatch.setattr(rvsim, "quasistatic", mod, raising=False)
    return mod
