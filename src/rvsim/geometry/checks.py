"""The checks of a reducer that need its geometry (issue 31 step 4; moved out of
``rvsim.parameters._io`` unchanged, in the same order, with the same messages).

:func:`check_geometry` runs after :func:`rvsim.parameters._io.check_values` (types, ranges,
field consistency): the cycloid profile, the gear stage and crank holes of the RV reducer or
the output-pin holes of the single-stage drive, the play of a disc against the tooth height,
the finite-element mesh sizes, whether every part can exist (:mod:`.validity`) and, unless
left out, the interference check at the assembled pose (:mod:`.assembly`).  The public entry
point stays :func:`rvsim.parameters.validate`, which calls both (docs/architecture.md).
"""

from __future__ import annotations

from ..errors import ParameterError
from ..parameters.fe_sizes import check_element_sizes
from ..parameters import Reducer
from .assembly import check_assembly
from .cycloid import check_profile
from .involute import check_gear_stage, gear_geometry
from .layout import arm_bushing_play, neighbour_distance
from .validity import check_parts

__all__ = ["check_geometry", "MAX_PRELOAD"]


def check_geometry(r: Reducer, assembly: bool = True) -> None:
    """Raise :class:`ParameterError` naming the first field whose geometry is impossible.

    ``r`` has passed the value checks.  ``assembly=False`` leaves out the interference check
    at the assembled pose (a tolerance study counts such reducers as binding)."""
    c, k = r.cycloid, r.crank
    check_profile(r)
    hole = k.eccentric_radius + k.arm_bushing_thickness
    root = c.pin_circle_radius - c.pin_radius - c.eccentricity
    if r.layout.single_stage:
        _check_single_stage(r, hole, root)
    else:
        _check_rv_layout(r, hole, root)
    _check_clearances(r)
    check_element_sizes(r)   # the meshes' sizes: refused here, not after another body's mesh
    check_parts(r)           # every part can exist (pins, bores, rollers, carrier, gears)
    if assembly:
        check_assembly(r)  # every pin, bushing and mesh at the pose the dynamic model starts from


def _check_rv_layout(r: Reducer, hole: float, root: float) -> None:
    c = r.cycloid
    if r.layout.disc_count != 2:
        raise ParameterError("layout.disc_count", "the RV reducer model has 2 discs")
    if r.layout.ring_output:
        raise ParameterError("layout.ring_output", "applies to the single-stage drive only "
                             "(layout.stages = 1); the RV reducer's output is the carrier")
    check_gear_stage(r)
    crank_circle = gear_geometry(r).centre_distance
    if crank_circle + hole + c.eccentricity >= root:
        raise ParameterError("crank.eccentric_radius", "the crank holes cut through the disc's "
                             "tooth root (crank circle + hole radius >= root radius)")


#: largest accepted bearing preload (negative radial internal clearance) [m]: real preloads
#: are a few micrometres
MAX_PRELOAD = 0.02e-3

#: RV-only clearances that the single-stage drive replaces by layout.input_bearing_clearance
_RV_ONLY_CLEARANCES = ("support_flange", "support_carrier", "crank_support_bushing")


def _check_single_stage(r: Reducer, hole: float, root: float) -> None:
    """Geometry of the single-stage drive: central eccentric bore, output-pin holes between
    it and the tooth root, bridges between neighbouring holes (docs/model.md section 13)."""
    c, lay = r.cycloid, r.layout
    if lay.disc_count not in (1, 2):
        raise ParameterError("layout.disc_count", f"must be 1 or 2 (got {lay.disc_count})")
    if r.flexibility.model == "fe" and r.flexibility.cycloid_disc:
        # refused here, as the RV reducer's finite-element sizes are, not at the first run
        # (a study ran its other runs, a tolerance study all of its reducers, first)
        raise ParameterError("flexibility.model", "the finite-element disc is built for the "
                             "RV reducer only so far (use closed-form for the single-stage "
                             "drive)")
    for name in _RV_ONLY_CLEARANCES:
        if getattr(r.clearances, name) != 0.0:
            raise ParameterError(f"clearances.{name}", "does not apply to the single-stage "
                                 "drive (use layout.input_bearing_clearance)")
    out_hole = lay.output_pin_radius + c.eccentricity + lay.output_pin_clearance
    if lay.output_pin_circle_radius + out_hole >= root:
        raise ParameterError("layout.output_pin_circle_radius", "the output-pin holes cut "
                             "through the disc's tooth root (R_w + hole radius >= root radius)")
    if lay.output_pin_circle_radius - out_hole <= hole:
        raise ParameterError("layout.output_pin_circle_radius", "the output-pin holes cut "
                             "into the central eccentric bore (R_w - hole radius <= bore)")
    if neighbour_distance(lay.output_pin_circle_radius, lay.output_pin_count) <= 2.0 * out_hole:
        raise ParameterError("layout.output_pin_count", "neighbouring output-pin holes "
                             "overlap (2 R_w sin(pi / n) <= 2 x hole radius)")


def _check_clearances(r: Reducer) -> None:
    """The bushing clearances between a disc and the housing must stay below the cycloid tooth
    height 2a: with that much play a disc can slip over the pins (docs/parameters.md)."""
    cl = r.clearances
    if r.layout.single_stage:
        play = arm_bushing_play(r) + r.layout.input_bearing_clearance
        if play >= 2.0 * r.cycloid.eccentricity:
            raise ParameterError("layout.input_bearing_clearance", f"the play of a disc, K + M "
                                 f"+ input bearing = {play * 1e3:g} mm, reaches the cycloid "
                                 f"tooth height 2a = {2e3 * r.cycloid.eccentricity:g} mm")
        return
    chain = {"clearances.crank_arm_bushing": cl.crank_arm_bushing,
             "clearances.disc_arm_bushing": cl.disc_arm_bushing,
             "clearances.crank_support_bushing": cl.crank_support_bushing,
             "clearances.support_flange": cl.support_flange,
             "clearances.support_carrier": cl.support_carrier}
    b = r.bearings
    for name in ("needle_clearance", "support_clearance"):
        if getattr(b, name) < -MAX_PRELOAD:
            raise ParameterError(f"bearings.{name}", f"a preload (negative clearance) of "
                                 f"{-getattr(b, name) * 1e3:g} mm is far beyond any bearing "
                                 f"preload (at most {MAX_PRELOAD * 1e3:g} mm accepted)")
    if b.arm_needles:
        chain["bearings.needle_clearance"] = 0.5 * max(b.needle_clearance, 0.0)
    if b.support_rollers:
        chain["bearings.support_clearance"] = 0.5 * max(b.support_clearance, 0.0)
    play = (arm_bushing_play(r) + cl.crank_support_bushing
            + max(cl.support_flange, cl.support_carrier)
            + chain.get("bearings.needle_clearance", 0.0)
            + chain.get("bearings.support_clearance", 0.0))
    tooth = 2.0 * r.cycloid.eccentricity
    if play >= tooth:
        largest = max(chain, key=chain.get)
        raise ParameterError(largest, f"the play of a disc, K + M + O + max(L, N) (+ half the "
                             f"bearings' internal clearances) = "
                             f"{play * 1e3:g} mm, reaches the cycloid tooth height 2a = "
                             f"{tooth * 1e3:g} mm (the disc could slip over the pins)")
