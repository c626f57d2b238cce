"""Per-part manufacturing errors: one value per pin, tooth, eccentric or hole (issue 11).

The scalar fields of :class:`~rvsim.parameters.Errors` give each error one value for the whole
reducer; :class:`PartErrors` gives each part its own.  All values are in SI (m, rad) and every
field defaults to empty (= no error).  A tolerance study draws them
(:mod:`rvsim.tolerance`); :mod:`rvsim.geometry.deviations` turns them into the arrays the
kernel and the assembly check use (docs/tolerances.md gives the sign conventions).

Index order: pins 0 .. zp-1 at 2 pi i / zp; teeth 0 .. zc-1 of each disc; cranks 0, 1 (the
single-stage drive has crank 0 only); the eccentric of crank j for disc k at ``2 j + k``.
"""

from __future__ import annotations

import dataclasses

__all__ = ["PartErrors", "HARMONIC_FIELDS"]

#: columns of one profile harmonic: (disc, order, amplitude [m], phase [rad])
HARMONIC_FIELDS = ("disc", "order", "amplitude", "phase")


@dataclasses.dataclass(frozen=True)
class PartErrors:
    """Deviations of individual parts from their nominal size and position (SI).

    ``pin_radial[i]``, ``pin_tangential[i]``: pin i's centre moved outwards / along the pin
    circle (counter-clockwise) [m].  ``pin_radius[i]``: pin i larger by this [m].
    ``disc_pitch[k][m]``: cumulative pitch deviation of tooth m of disc k along the pin circle
    [m] (the tooth turned forwards about the disc centre by that arc).
    ``disc_phase[k]``: disc k's teeth turned about its centre relative to its crank holes [rad].
    ``profile_harmonics``: rows (disc, order, amplitude, phase): the profile of that disc
    stands out along its normal by amplitude * cos(order * u + phase) [m] (u: the profile
    parameter, the polar angle of the generating pin in disc axes).
    ``profile_points[k]``: measured normal deviations of disc k's profile, rows (u [rad],
    deviation [m], positive = excess material), interpolated periodically in u.
    ``eccentricity[2 j + k]``: crank j's eccentric for disc k larger by this [m];
    ``eccentric_phase[2 j + k]``: turned forwards by this [rad].
    ``disc_holes[k][2 j], [2 j + 1]``: crank j's hole in disc k off its nominal centre by (dx, dy)
    in disc axes [m].  ``carrier_holes[2 j], [2 j + 1]``: crank j's bores in the carrier (and
    flange) off their nominal centre radially and tangentially [m].
    """

    pin_radial: tuple = ()
    pin_tangential: tuple = ()
    pin_radius: tuple = ()
    disc_pitch: tuple = ()
    disc_phase: tuple = ()
    profile_harmonics: tuple = ()
    profile_points: tuple = ()
    eccentricity: tuple = ()
    eccentric_phase: tuple = ()
    disc_holes: tuple = ()
    carrier_holes: tuple = ()

    @property
    def any(self) -> bool:
        """Whether any part deviates."""
        return any(getattr(self, f.name) for f in dataclasses.fields(self))

    @property
    def has_profile(self) -> bool:
        """Whether a disc's profile deviates (pitch, phase, form)."""
        return bool(self.disc_pitch or self.disc_phase or self.profile_harmonics
                    or self.profile_points)
