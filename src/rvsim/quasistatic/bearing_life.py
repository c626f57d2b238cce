"""Rating life of the crank bearings under an output torque at an output speed: :func:`life`.

The quasi-static engine (:func:`~rvsim.quasistatic.transmission.ltca`) gives the radial load
of every crank bearing at equally spaced input positions over one output revolution; ISO 281
(:mod:`rvsim.physics.rating_life`) turns each bearing's geometry into its dynamic load rating
C and its load cycle into a mean equivalent load P; the relative speed of its raceways follows
from the kinematics.  docs/model.md section 19.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from .._display import Headline, number
from ..errors import ParameterError
from ..parameters import Reducer, check_reducer

__all__ = ["life", "LifeResult", "BearingLife", "crank_speed", "check_life_inputs",
           "dynamic_ratings", "main_bearing_rows", "DEFAULT_POSITIONS",
           "check_static_capacity"]

#: input positions over the output revolution whose loads are averaged (ltca's default)
DEFAULT_POSITIONS = 360
_RPM = 2.0 * math.pi / 60.0


@dataclasses.dataclass
class BearingLife:
    """Rating life of one bearing (SI; ``status`` "ok", "bushing": a plain bushing there, no
    rating life, or "needs_external_load": the model puts no load on it)."""

    name: str
    kind: str
    dynamic_rating: float          # C [N]
    equivalent_load: float         # P [N], mean equivalent load over the cycle
    peak_load: float               # [N] largest radial load over the cycle
    speed: float                   # [rad/s] relative speed of the raceways
    exponent: float                # p of L10 = (C / P)^p
    l10: float                     # [revolutions]
    l10_hours: float               # [h]
    status: str = "ok"
    weibull_slope: float = 9.0 / 8.0   # e of the life scatter (roller 9/8, ball 10/9)

    def as_dict(self) -> dict:
        return {"name": self.name, "kind": self.kind, "status": self.status,
                "dynamic_rating_n": self.dynamic_rating,
                "equivalent_load_n": self.equivalent_load, "peak_load_n": self.peak_load,
                "speed_rpm": self.speed / _RPM, "life_exponent": self.exponent,
                "l10_million_revolutions": self.l10 / 1e6, "l10_hours": self.l10_hours}


@dataclasses.dataclass(repr=False)
class LifeResult(Headline):
    """Rating life of the reducer's bearings at one output torque and output speed (SI).
    Shown as its headline figures (:meth:`headline`)."""

    name: str
    torque: float                  # [N*m]
    output_speed: float            # [rad/s]
    crank_speed: float             # [rad/s] crank relative to the carrier
    bearings: list                 # [BearingLife]
    catalogue_life: float          # [s] K (N0 / N) (T0 / T)^(10/3) of rating.*
    status: str
    positions: int
    wall_s: float

    @property
    def rated_bearings(self) -> list:
        return [b for b in self.bearings if b.status == "ok" and math.isfinite(b.l10_hours)]

    @property
    def life_hours(self) -> float:
        """The reducer's rating life: its shortest bearing life [h], the main bearings included
        when they are loaded (nan: none rated)."""
        rated = self.rated_bearings
        return min(b.l10_hours for b in rated) if rated else math.nan

    @property
    def crank_life_hours(self) -> float:
        """The shortest life of the crank bearings [h], what the catalogue rule rates (it
        leaves out the external loads on the main bearings)."""
        crank = [b.l10_hours for b in self.rated_bearings if not b.name.startswith("main")]
        return min(crank) if crank else math.nan

    @property
    def system_life_hours(self) -> float:
        """L10 of all rated bearings together [h]: 90 % of reducers keep every one of them
        (each with its Weibull slope; :func:`~rvsim.physics.rating_life.system_life`)."""
        from ..physics.rating_life import system_life

        rated = self.rated_bearings
        return system_life([b.l10_hours for b in rated],
                           [b.weibull_slope for b in rated]) if rated else math.nan

    @property
    def limiting(self) -> str:
        rated = self.rated_bearings
        return min(rated, key=lambda b: b.l10_hours).name if rated else ""

    def headline(self) -> tuple[str, list[tuple[str, str]]]:
        """Status, operating point and the lives in hours (the repr)."""
        m = self.summary()
        return (f"Rating life of {m['reducer']} at {number(m['torque_nm'], 'N*m')}, "
                f"{number(m['output_speed_rpm'], 'rpm')} output: {m['status']}",
                [("life (shortest bearing)", f"{number(m['life_hours'], 'h')} "
                                             f"({m['limiting_bearing'] or 'none rated'})"),
                 ("system life (all bearings)", number(m["system_life_hours"], "h")),
                 ("crank bearings", number(m["crank_life_hours"], "h")),
                 ("catalogue rule", number(m["catalogue_life_hours"], "h"))])

    def summary(self) -> dict:
        """The JSON keys: the life in hours, the limiting bearing, the crank bearings' life
        and the catalogue rule's at the same point (and their ratio), one entry per bearing."""
        catalogue_h = self.catalogue_life / 3600.0
        return {"reducer": self.name, "torque_nm": self.torque,
                "output_speed_rpm": self.output_speed / _RPM,
                "crank_speed_rpm": self.crank_speed / _RPM,
                "life_hours": self.life_hours, "limiting_bearing": self.limiting,
                "system_life_hours": self.system_life_hours,
                "catalogue_life_hours": catalogue_h,
                "crank_life_hours": self.crank_life_hours,
                "life_ratio_to_catalogue": self.crank_life_hours / catalogue_h,
                "bearings": [b.as_dict() for b in self.bearings],
                "positions": self.positions, "wall_s": self.wall_s, "status": self.status}


def crank_speed(reducer: Reducer, output_speed: float) -> float:
    """Speed of each crank relative to the carrier [rad/s] at the output (carrier) speed.

    In the carrier's frame the sun turns at w_in - w_out and drives the planet on the crank:
    w_crank = (z1 / z2) (w_in - w_out) = (z1 / z2) (i - 1) w_out = zp w_out, since i = 1 +
    (z2 / z1) zp.  The needles run between the eccentric (turning with the crank) and the disc
    hole (the disc keeps the carrier's orientation: the two cranks are a parallel linkage), the
    support rollers between the journal and the carrier: both at this speed."""
    g = reducer.gears
    return abs(g.sun_teeth / g.planet_teeth * (reducer.ratio - 1.0) * output_speed)


def check_life_inputs(reducer: Reducer, torque: float, output_speed: float,
                      **external: float) -> None:
    """Refuse what has no rating life: a single-stage drive, bushings only, a torque or an
    output speed that is not positive, an output speed above ``rating.allowable_output_speed``,
    an ``external`` main-bearing load (name=value) that is negative or not finite
    (ParameterError)."""
    if reducer.layout.single_stage:
        raise ParameterError("layout.stages", "rating life is modelled for the RV reducer's "
                             "crank bearings (layout.stages = 2) only")
    b = reducer.bearings
    if not (b.arm_needles or b.support_rollers):
        raise ParameterError("bearings.arm_needles", "the paper's bushings have no rating "
                             "life (ISO 281 rates rolling bearings): set bearings.arm_needles "
                             "and bearings.support_rollers, e.g. --params RV-40E-bearings")
    for name, value, unit in (("torque", torque, "N*m"), ("output_speed", output_speed,
                                                           "rad/s")):
        if not math.isfinite(value) or value <= 0.0:
            raise ParameterError(name, f"must be a positive finite number (got {value:g} "
                                 f"{unit})")
    from ..parameters.rating import check_output_speed

    check_output_speed(reducer, output_speed, "output_speed", refuse=True)
    if b.support_rollers:      # before the quasi-static run: ISO 281 needs alpha > 0
        from ..physics.rating_life import tapered_factors

        tapered_factors(b.support_contact_angle, "bearings.support_contact_angle")
    for name, value in external.items():
        if not math.isfinite(value) or value < 0.0:
            raise ParameterError(name, f"must be zero or a positive finite number (got "
                                 f"{value:g})")


def check_static_capacity(reducer: Reducer, radial_load: float, moment: float, thrust: float,
                          names=("radial_load", "moment", "thrust")) -> None:
    """Refuse external loads under which a main bearing row's equivalent load P (the life's
    own, :func:`~rvsim.physics.rating_life.main_bearing_loads`) exceeds the row's basic static
    load rating C_0 (ISO 76): the raceways deform permanently and a fatigue life says nothing
    (``life --moment 1e12`` printed 1e-20 h as ok).  The ParameterError names the largest
    of the three loads as a row force (``names``: radial, moment, thrust fields)."""
    from ..physics import rating_life as iso

    if not (radial_load or moment or thrust):
        return
    b = reducer.bearings
    static = iso.ball_static_rating(b.main_ball_count, b.main_ball_diameter,
                                    b.main_pitch_diameter, b.main_contact_angle,
                                    field="bearings.main_ball_diameter")
    load = max(max(iso.main_bearing_loads(radial_load, sign * moment, thrust, b.main_span,
                                          b.main_contact_angle, "bearings.main_contact_angle"))
               for sign in (1.0, -1.0))
    if load <= static:
        return
    forces = (0.5 * abs(radial_load), abs(moment) / b.main_span, abs(thrust))
    k = max(range(3), key=lambda i: forces[i])
    given = (f"{radial_load:g} N", f"{moment:g} N*m", f"{thrust:g} N")[k]
    raise ParameterError(names[k], f"{given}: a main bearing row's equivalent load {load:.4g} N "
                         f"is above its basic static load rating C0 = {static:.4g} N (ISO 76): "
                         "the raceways would deform permanently, a rating life says nothing")


def main_bearing_rows(reducer: Reducer, rating: float, output_speed: float,
                      radial_load: float, moment: float, thrust: float) -> list:
    """The two main bearing rows under the external loads (each row's C = ``rating``; ISO 281
    with :func:`~rvsim.physics.rating_life.main_bearing_loads`).  The thrust's direction
    relative to the moment's plane is not given: of the two, the one with the shorter life.
    No external load: one row "needs_external_load" without life."""
    from ..physics import rating_life as iso

    b = reducer.bearings
    kind, p = "angular contact ball", iso.BALL_EXPONENT
    if not (radial_load or moment or thrust):
        return [BearingLife("main bearings (each row)", kind, rating, math.nan, math.nan,
                            output_speed, p, math.nan, math.nan, "needs_external_load",
                            iso.BALL_WEIBULL_SLOPE)]
    cases = [iso.main_bearing_loads(radial_load, sign * moment, thrust, b.main_span,
                                    b.main_contact_angle, "bearings.main_contact_angle")
             for sign in (1.0, -1.0)]
    loads = max(cases, key=max)
    rows = []
    for k, load in enumerate(loads):
        l10 = iso.rating_life(rating, load, p)
        rows.append(BearingLife(f"main bearing row {k + 1}", kind, rating, load, load,
                                output_speed, p, l10, iso.life_hours(l10, output_speed), "ok",
                                iso.BALL_WEIBULL_SLOPE))
    return rows


def dynamic_ratings(reducer: Reducer) -> tuple[float, float, float]:
    """ISO 281 basic dynamic radial load ratings C [N] of a needle bearing at an eccentric, a
    tapered support bearing and one row of the main bearings, from ``bearings.*`` (raceways
    of the needles and support rollers: the eccentric or journal, roller pitch diameter
    :func:`~rvsim.bearings.roller_pitch_diameter`)."""
    from ..bearings import roller_pitch_diameter
    from ..physics import rating_life as iso

    b, crank = reducer.bearings, reducer.crank
    needle = iso.roller_dynamic_rating(
        b.needle_count, b.needle_diameter, b.needle_length,
        roller_pitch_diameter(crank.eccentric_radius, b.needle_diameter),
        field="bearings.needle_diameter")
    support = iso.roller_dynamic_rating(
        b.support_roller_count, b.support_roller_diameter, b.support_roller_length,
        roller_pitch_diameter(crank.journal_radius, b.support_roller_diameter),
        b.support_contact_angle, field="bearings.support_roller_diameter")
    main = iso.ball_dynamic_rating(b.main_ball_count, b.main_ball_diameter,
                                   b.main_pitch_diameter, b.main_contact_angle,
                                   field="bearings.main_ball_diameter")
    return needle, support, main


def life(reducer: Reducer, *, torque: float | None = None, output_speed: float | None = None,
         positions: int = DEFAULT_POSITIONS, radial_load: float = 0.0, moment: float = 0.0,
         thrust: float = 0.0) -> LifeResult:
    """L10 rating life of each crank bearing and the reducer's shortest, at the output
    ``torque`` [N*m] (default: ``rating.rated_torque``) and output speed [rad/s] (default:
    ``rating.rated_output_speed``).

    The loads come from :func:`ltca` over one output revolution at ``positions`` equally
    spaced input angles, with the input turning at ``output_speed`` times the ratio (the
    friction of the bearings follows it).  A run that does not converge returns its status
    and no lives (nan).

    The main bearings carry only the external loads on the output flange: ``radial_load``
    [N] midway between them, the tilting ``moment`` [N*m] and the ``thrust`` [N] (all zero:
    no life, status "needs_external_load"); :func:`main_bearing_rows`."""
    import time

    from ..analysis.sampling import check_positions
    from ..parameters import validate
    from ..parameters.rating import check_torque
    from ..physics import rating_life as iso
    from .transmission import ltca

    check_reducer(reducer)
    check_positions(reducer, positions, "positions")    # ltca's own check, before the ratings
    g = reducer.rating
    torque = float(g.rated_torque if torque is None else torque)
    output_speed = float(g.rated_output_speed if output_speed is None else output_speed)
    check_life_inputs(reducer, torque, output_speed, radial_load=radial_load, moment=moment,
                      thrust=thrust)
    validate(reducer)
    check_torque(reducer, torque, "torque")
    c_needle, c_support, c_main = dynamic_ratings(reducer)
    if radial_load or moment or thrust:     # refused before the solve, not after
        iso.angular_contact_factors(reducer.bearings.main_contact_angle,
                                    "bearings.main_contact_angle")
        check_static_capacity(reducer, radial_load, moment, thrust)
    start = time.perf_counter()
    running = dataclasses.replace(reducer, operating=dataclasses.replace(
        reducer.operating, input_speed=output_speed * abs(reducer.ratio)))
    run = ltca(running, torque=torque, positions=positions, raise_on_failure=False)
    speed = crank_speed(reducer, output_speed)
    ok = run.status == "ok"
    b = reducer.bearings
    rows = []

    def add(name, kind, rating, loads, exponent, status="ok"):
        if status != "ok" or not ok:       # a bushing, or the loads of a failed solve
            rows.append(BearingLife(name, kind, rating, math.nan, math.nan, speed, exponent,
                                    math.nan, math.nan, status if status != "ok"
                                    else run.status))
            return
        p = iso.mean_load(loads, exponent)
        l10 = iso.rating_life(rating, p, exponent)
        rows.append(BearingLife(name, kind, rating, p, float(np.max(loads)), speed, exponent,
                                l10, iso.life_hours(l10, speed)))

    for j in range(2):
        for d in range(2):
            add(f"arm needles crank {j + 1} disc {d + 1}", "needle roller", c_needle,
                run.arm_forces[:, j, d], iso.ROLLER_EXPONENT,
                "ok" if b.arm_needles else "bushing")
        lower, upper = run.support_forces[:, j, 0], run.support_forces[:, j, 1]
        p_lower, p_upper = iso.tapered_pair_loads(lower, upper, b.support_contact_angle,
                                                   "bearings.support_contact_angle")
        for where, p in (("lower", p_lower), ("upper", p_upper)):
            add(f"support rollers crank {j + 1} {where}", "tapered roller", c_support, p,
                iso.ROLLER_EXPONENT, "ok" if b.support_rollers else "bushing")
    rows += main_bearing_rows(reducer, c_main, output_speed, radial_load, moment, thrust)
    catalogue = iso.catalogue_life(g.rated_life, g.rated_output_speed, output_speed,
                                   g.rated_torque, torque)
    return LifeResult(reducer.name, torque, output_speed, speed, rows, catalogue, run.status,
                      positions, time.perf_counter() - start)
