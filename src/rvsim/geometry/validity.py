"""Whether every part of a reducer can exist, before it is assembled or simulated.

Each check refuses a part that cannot be made or cannot take its place (docs/parameters.md,
"Parts that cannot exist"; docs/decisions.md, issue 30): pins that overlap their neighbours,
rolling elements that do not fit around their race, bores and holes of the disc that cut into
each other, a carrier that cannot hold the crank bores, a journal that the arm bearing and
the disc cannot pass, parts on a crank that overlap axially, and gear teeth too narrow to
carry the rated torque once.  The checks run in :func:`rvsim.parameters.validate` (also for
a tolerance study's reducers, whose assembly is checked separately); only the parts the
model has are checked (the single-stage drive has no gears, central disc bore, pillar
holes or main bearings; rolling bearings only when their flags are set).
"""

from __future__ import annotations

import math

from ..errors import ParameterError
from ..parameters import Reducer
from .layout import crank_angles, crank_hole_radius, disc_count, neighbour_distance, \
    pillar_angles, roller_pitch_diameter

__all__ = ["check_parts"]


def _mm(value: float) -> str:
    return f"{value * 1e3:.4g} mm"


def check_parts(reducer: Reducer) -> None:
    """Raise :class:`ParameterError` naming the first part that cannot exist."""
    _check_pins(reducer)
    _check_crank(reducer)
    _check_axial_stations(reducer)
    _check_rolling_elements(reducer)
    if reducer.layout.single_stage:
        _check_output_flange(reducer)
        return
    from .involute import check_gear_strength, gear_geometry

    crank_circle = gear_geometry(reducer).centre_distance
    _check_disc_holes(reducer, crank_circle)
    _check_carrier(reducer, crank_circle)
    check_gear_strength(reducer)


def _check_pins(r: Reducer) -> None:
    """Neighbouring ring pins must leave housing between their grooves."""
    c = r.cycloid
    pitch = neighbour_distance(c.pin_circle_radius, c.pin_count)
    if pitch <= 2.0 * c.pin_radius:
        raise ParameterError("cycloid.pin_radius", f"neighbouring pins overlap: {c.pin_count} "
                             f"pins on the {_mm(c.pin_circle_radius)} pin circle are "
                             f"{_mm(pitch)} apart, not more than the pin diameter "
                             f"{_mm(2.0 * c.pin_radius)}")


def _check_crank(r: Reducer) -> None:
    """The arm bearing (bushing or needles) and the disc are slid over the journal onto the
    eccentric: the journal must fit inside the eccentric and through the disc's crank hole."""
    k = r.crank
    if k.journal_radius > k.eccentric_radius:
        raise ParameterError("crank.journal_radius", f"{_mm(k.journal_radius)} is larger than "
                             f"the eccentric radius {_mm(k.eccentric_radius)}: the crank is a "
                             f"journal with the eccentric around it, over which the arm "
                             f"bearing and the disc are slid")
    hole = crank_hole_radius(r)
    if k.journal_radius + r.cycloid.eccentricity > hole:
        raise ParameterError("crank.journal_radius", f"the disc's crank hole "
                             f"({_mm(hole)} radius) cannot pass over the journal "
                             f"({_mm(k.journal_radius)}) offset by the eccentricity "
                             f"{_mm(r.cycloid.eccentricity)}")


def _check_axial_stations(r: Reducer) -> None:
    """Supports, discs and the planet gear on a crank must not overlap along it; needles no
    longer than the disc hole they run in."""
    c, k, b = r.cycloid, r.crank, r.bearings
    if b.arm_needles and b.needle_length > c.disc_width:
        raise ParameterError("bearings.needle_length", f"{_mm(b.needle_length)} is longer "
                             f"than the disc's crank hole they run in (disc width "
                             f"{_mm(c.disc_width)})")
    support = b.support_roller_length if b.support_rollers else k.support_bushing_width
    parts = [("lower support", "crank.lower_support_z", k.lower_support_z, support),
             ("disc 1", "crank.disc1_z", k.disc1_z, c.disc_width)]
    if disc_count(r) == 2:
        parts.append(("disc 2", "crank.disc2_z", k.disc2_z, c.disc_width))
    parts.append(("upper support", "crank.upper_support_z", k.upper_support_z, support))
    if not r.layout.single_stage:
        parts.append(("planet gear", "crank.gear_z", k.gear_z, r.gears.face_width))
    parts.sort(key=lambda part: part[2])
    for first, second in zip(parts[:-1], parts[1:]):
        if second[2] - first[2] < 0.5 * (first[3] + second[3]):
            field = "crank.gear_z" if "gear" in first[0] else second[1]
            raise ParameterError(field, f"the {first[0]} ({_mm(first[3])} wide at "
                                 f"{_mm(first[2])}) and the {second[0]} ({_mm(second[3])} "
                                 f"wide at {_mm(second[2])}) overlap along the crank")


def _check_rolling_elements(r: Reducer) -> None:
    """Rollers and balls of a set must not overlap their neighbours on their pitch circle."""
    b, k = r.bearings, r.crank
    sets = []
    if b.arm_needles:
        sets.append(("bearings.needle_count", "needles", b.needle_count, b.needle_diameter,
                     roller_pitch_diameter(k.eccentric_radius, b.needle_diameter)))
    if b.support_rollers:
        sets.append(("bearings.support_roller_count", "support rollers",
                     b.support_roller_count, b.support_roller_diameter,
                     roller_pitch_diameter(k.journal_radius, b.support_roller_diameter)))
    if not r.layout.single_stage:     # the main bearings: the joint model's tilting stiffness
        if b.main_ball_diameter >= b.main_pitch_diameter:
            raise ParameterError("bearings.main_ball_diameter", f"a ball of "
                                 f"{_mm(b.main_ball_diameter)} cannot run on a pitch circle "
                                 f"of {_mm(b.main_pitch_diameter)} diameter (the ball "
                                 f"diameter must be less than the pitch diameter)")
        sets.append(("bearings.main_ball_count", "main-bearing balls", b.main_ball_count,
                     b.main_ball_diameter, b.main_pitch_diameter))
    for field, what, count, diameter, pitch in sets:
        gap = neighbour_distance(0.5 * pitch, count)
        if gap < diameter:
            most = math.floor(math.pi / math.asin(min(diameter / pitch, 1.0)))
            raise ParameterError(field, f"{count} {what} of {_mm(diameter)} do not fit around "
                                 f"their pitch circle of {_mm(pitch)} diameter: neighbours "
                                 f"are {_mm(gap)} apart (at most {most} fit)")


def _check_disc_holes(r: Reducer, crank_circle: float) -> None:
    """RV disc: the central bore, the crank holes and the pillar holes (on the crank circle,
    where the model places them) must leave a ligament between each other; the crank holes'
    distance to the tooth root is checked with the layout (parameters._io)."""
    c = r.cycloid
    hole = crank_hole_radius(r)
    if c.disc_bore_radius + hole >= crank_circle:
        raise ParameterError("cycloid.disc_bore_radius", f"the central bore "
                             f"({_mm(c.disc_bore_radius)}) cuts into the crank holes "
                             f"({_mm(hole)} radius on the {_mm(crank_circle)} crank circle): "
                             f"bore + crank hole radius must stay below the crank circle "
                             f"radius")
    pillar = c.pillar_hole_radius
    if c.pillar_hole_count == 0 or pillar == 0.0:
        return
    root = c.pin_circle_radius - c.pin_radius - c.eccentricity
    if crank_circle + pillar + c.eccentricity >= root:
        raise ParameterError("cycloid.pillar_hole_radius", "the pillar holes cut through the "
                             "disc's tooth root (crank circle + pillar hole radius >= root "
                             "radius)")
    if c.disc_bore_radius + pillar >= crank_circle:
        raise ParameterError("cycloid.pillar_hole_radius", f"the pillar holes "
                             f"({_mm(pillar)}) cut into the central bore "
                             f"({_mm(c.disc_bore_radius)}) on the {_mm(crank_circle)} crank "
                             f"circle")
    for angle in pillar_angles(r):
        for crank in crank_angles(r):
            apart = 2.0 * crank_circle * abs(math.sin(0.5 * (angle - crank)))
            if apart <= hole + pillar:
                raise ParameterError("cycloid.pillar_hole_count", f"a pillar hole "
                                     f"({_mm(pillar)}) overlaps a crank hole ({_mm(hole)}) "
                                     f"where the model places them ({c.pillar_hole_count} "
                                     f"evenly spaced from a quarter turn past the first "
                                     f"crank hole, {_mm(apart)} apart)")
    if c.pillar_hole_count >= 2 and \
            neighbour_distance(crank_circle, c.pillar_hole_count) <= 2.0 * pillar:
        raise ParameterError("cycloid.pillar_hole_count", "neighbouring pillar holes overlap")


def _check_carrier(r: Reducer, crank_circle: float) -> None:
    """The carrier (and the flange) hold the cranks' support bores (journal + bushing wall,
    or the tapered rollers' outer raceway) around its central bore."""
    c, k, b = r.cycloid, r.crank, r.bearings
    bore = k.journal_radius + (b.support_roller_diameter if b.support_rollers
                               else k.arm_bushing_thickness)
    if crank_circle + bore >= c.carrier_radius:
        raise ParameterError("cycloid.carrier_radius", f"{_mm(c.carrier_radius)} cannot hold "
                             f"the crank support bores ({_mm(bore)} radius on the "
                             f"{_mm(crank_circle)} crank circle): crank circle + bore radius "
                             f"must stay below the carrier radius")
    if c.disc_bore_radius + bore >= crank_circle:
        raise ParameterError("cycloid.disc_bore_radius", f"the central bore "
                             f"({_mm(c.disc_bore_radius)}) cuts into the carrier's crank "
                             f"support bores ({_mm(bore)} radius on the {_mm(crank_circle)} "
                             f"crank circle)")


def _check_output_flange(r: Reducer) -> None:
    """Single-stage drive: the output flange (carrier_radius) holds the output pins."""
    lay = r.layout
    reach = lay.output_pin_circle_radius + lay.output_pin_radius
    if reach >= r.cycloid.carrier_radius:
        raise ParameterError("cycloid.carrier_radius", f"the output flange "
                             f"({_mm(r.cycloid.carrier_radius)} radius) cannot hold the output "
                             f"pins (pin circle + pin radius = {_mm(reach)})")
