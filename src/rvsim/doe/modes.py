"""The reducer's torsional natural frequency at a load: :func:`torsional_mode` (issue 33
item 4; docs/model.md section 21).  In ``doe`` beside the speed-torque grid that marks it,
outside the model fingerprint (:mod:`rvsim._fingerprint`): the grid's rows are keyed by this
file's source and the grid's own, so no other study's stored rows are keyed anew by it.

The dynamic engine drives the input by its motion (Eq. 19): the input side is held, and the
drive train's torsional mode is the output's, the output inertia (carrier and driven load,
``operating.load_inertia``, and the discs, which turn with the output) on the reducer's
torsional stiffness with the input held.  That stiffness is the quasi-static engine's local
``dT/dtheta_out`` (:func:`rvsim.quasistatic.ltca`, the condensed stiffness of the linearised
equilibrium) at the load; it varies over the output revolution with the pins in contact, so
the frequency is given at the revolution's mean stiffness with the band of its least and
largest.  One degree of freedom, f = sqrt(K / J) / (2 pi) (the undamped torsional system,
e.g. Rao, Mechanical Vibrations, chapter 2): the cranks' rotation and the discs' translation
in the mode are left out (docs/model.md section 21: the frequency checked against the dynamic
engine's own ringing).
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from ..parameters import Reducer

__all__ = ["TorsionalMode", "torsional_mode", "natural_frequency", "output_inertia"]

#: positions of the ltca revolution that gives the stiffness (the RV-40E's 39 mesh periods a
#: revolution at 9 positions each)
MODE_POSITIONS = 360


def natural_frequency(stiffness: float, inertia: float) -> float:
    """f = sqrt(K / J) / (2 pi) [Hz] of an inertia ``inertia`` [kg m^2] on a torsional spring
    ``stiffness`` [N m/rad] (NaN for a spring that is not positive)."""
    if not (stiffness > 0.0 and inertia > 0.0):
        return float("nan")
    return math.sqrt(stiffness / inertia) / (2.0 * math.pi)


def output_inertia(reducer: Reducer) -> float:
    """The inertia turning with the output [kg m^2]: the carrier with the driven load
    (``P[J_CARRIER]`` of the dynamic model) and, unless the discs are held (a single-stage
    drive with the pin ring as output), the discs' rotary inertia, as the dynamic model has
    them (:func:`rvsim.dynamics.model.mass_properties`)."""
    from ..dynamics.model import mass_properties
    from ..geometry.layout import disc_count

    masses = mass_properties(reducer)
    inertia = masses.carrier_inertia + reducer.operating.load_inertia   # model.P[J_CARRIER]
    if not (reducer.layout.single_stage and reducer.layout.ring_output):
        inertia += disc_count(reducer) * masses.disc_inertia
    return float(inertia)


@dataclasses.dataclass(frozen=True)
class TorsionalMode:
    """The output's torsional mode at ``torque`` (SI)."""

    torque: float                  # [N m]
    stiffness: float               # [N m/rad] mean over the revolution, input held
    stiffness_min: float
    stiffness_max: float
    inertia: float                 # [kg m^2]
    status: str                    # the ltca's ("ok" or why there is no frequency)

    @property
    def frequency(self) -> float:
        """[Hz] at the mean stiffness."""
        return natural_frequency(self.stiffness, self.inertia)

    @property
    def band(self) -> tuple[float, float]:
        """[Hz] at the least and the largest stiffness of the revolution."""
        return (natural_frequency(self.stiffness_min, self.inertia),
                natural_frequency(self.stiffness_max, self.inertia))

    def summary(self) -> dict:
        from ..units import ARCMIN

        low, high = self.band
        return {"natural_frequency_hz": self.frequency, "natural_frequency_min_hz": low,
                "natural_frequency_max_hz": high,
                "torsional_stiffness_nm_per_arcmin": self.stiffness * ARCMIN,
                "output_inertia_kgm2": self.inertia, "mode_status": self.status}


def torsional_mode(reducer: Reducer, torque: float | None = None) -> TorsionalMode:
    """The output's torsional mode at the output ``torque`` [N m] (default: the reducer's
    ``operating.load_torque``), from one ltca revolution; NaN frequencies (and the ltca's
    status) when a position does not converge."""
    from ..quasistatic.transmission import ltca

    result = ltca(reducer, torque=torque, positions=MODE_POSITIONS, raise_on_failure=False)
    k = result.torsional_stiffness[result.converged]
    ok = result.status == "ok" and k.size > 0 and np.all(np.isfinite(k))
    nan = float("nan")
    return TorsionalMode(torque=float(result.torque),
                         stiffness=float(np.mean(k)) if ok else nan,
                         stiffness_min=float(np.min(k)) if ok else nan,
                         stiffness_max=float(np.max(k)) if ok else nan,
                         inertia=output_inertia(reducer), status=result.status)
