"""The built-in single-stage cycloid drive ``cycloid-drive`` (docs/parameters.md, "cycloid-drive").

A plain cycloidal drive of a robot joint: the input shaft is the eccentric shaft on the housing
axis, two discs at 180 deg, output through eight pins (rollers) in holes of the discs, ring pins
fixed in the housing.  The dimensions are the proportions of the textbook design rules (pin
count, curtate ratio K1 = a zp / r_p = 0.75, output-hole bridge widths); docs/parameters.md
says which values are assumed and why no published set is reproduced exactly.
"""

from __future__ import annotations

import dataclasses
from ._types import SINGLE_STAGE, Crankshaft, CycloidStage, Layout, Operating, Rating, Reducer

__all__ = ["CYCLOID_DRIVE", "CYCLOID_DRIVE_CITATION"]

_MM = 1e-3

CYCLOID_DRIVE_CITATION = (
    "single-stage cycloid drive, proportions after the textbook design rules (docs/parameters.md)")

CYCLOID_DRIVE = Reducer(
    name="cycloid-drive",
    citation=CYCLOID_DRIVE_CITATION,
    cycloid=CycloidStage(
        eccentricity=1.5 * _MM, disc_teeth=29, pin_count=30, disc_width=10.0 * _MM,
        pin_radius=4.0 * _MM, pin_circle_radius=60.0 * _MM, disc_bore_radius=18.0 * _MM,
        pillar_hole_count=0, pillar_hole_radius=0.0, carrier_radius=62.0 * _MM,
        carrier_thickness=15.0 * _MM),
    crank=Crankshaft(
        eccentric_radius=15.0 * _MM, journal_radius=10.0 * _MM, arm_bushing_thickness=3.0 * _MM,
        support_bushing_width=10.0 * _MM, lower_support_z=0.0, disc1_z=12.0 * _MM,
        disc2_z=24.0 * _MM, upper_support_z=36.0 * _MM, gear_z=36.0 * _MM),
    operating=Operating(load_torque=150.0, fluctuation_amplitude=20.0, load_inertia=0.05),
    # start/stop and momentary: the RV-40E class's ratios to rated (1029 / 412 = 2.5, 2058 / 412
    # = 5), assumed for want of a catalogue of this drive (docs/parameters.md)
    rating=Rating(rated_torque=200.0, start_stop_torque=500.0, momentary_torque=1000.0),
    layout=Layout(stages=SINGLE_STAGE, disc_count=2, output_pin_count=8,
                  output_pin_radius=5.0 * _MM, output_pin_circle_radius=36.0 * _MM,
                  output_pin_clearance=0.0, input_bearing_clearance=0.0),
)

assert dataclasses.is_dataclass(CYCLOID_DRIVE) and CYCLOID_DRIVE.ratio == -29.0
