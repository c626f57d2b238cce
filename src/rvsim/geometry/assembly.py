"""Interference check of the assembled reducer, before any simulation.

The dynamic model starts every run from the assembled pose (:func:`rvsim.dynamics.model.
build_model`, ``q0``): carrier and input at zero, each crank centred in its support bores with
its eccentric for disc k at angle k*pi, each disc in its nominal (kinematic) pose for crank
angle 0 with the crank's eccentricity a - G, at rest.  In that pose:

* **pins**: every pin's gap to both discs is computed exactly (:func:`~rvsim.geometry.cycloid.
  pin_gaps`).  Errors that close clearance (G, rotation modification, disc runout, pin position
  errors) make some gaps negative unless the clearance-opening errors and modifications (F, H, I,
  J) exceed them; G alone makes the disc overlap the pin opposite its eccentric by G.  F, H,
  I and J may be negative (they then close clearance); a negative equidistant modification
  with a larger positive radial-moving one can nearly cancel on the working flank and still
  assemble: the exact gaps decide.
* **bushings**: the eccentric and journal centres coincide with their bore centres, so the
  radial approach is minus the clearance (K + M, O + L, O + N), never an overlap for the
  non-negative clearances validation allows, unless per-part errors (each eccentric's size and
  phase, the crank holes in each disc, the bores in the carrier:
  :class:`~rvsim.parameters.PartErrors`) move them apart and make them overlap.
* **rolling bearings** (``bearings.arm_needles`` / ``support_rollers``): the needles must fit
  the radial space between the eccentric and the disc hole (``crank.arm_bushing_thickness``):
  a needle diameter larger than that space plus K + M is an interference; a bearing's own
  preload (negative internal clearance) is intended and not reported (it is the overlap's
  ``preload``).  The tapered support bearings start centred like the bushings.  An
  interference of a rolling bearing is not refused here: it is assembled with elastic
  preload of its rollers, as real reducers are, and refused only where the preload's Hertz
  stress exceeds the static limit (:func:`rvsim.bearings.check_preload`, called where the
  engines build their model; issue 32).
* **per-part errors** of pins (position, size) and discs (pitch, phase, profile form) enter
  the exact pin gaps (:mod:`rvsim.geometry.deviations`).
* **sun-planet meshes**: the cranks start at zero phase with the input at zero, so the mesh
  deflection along the line of action is zero and the approach is minus half the backlash.

An overlap larger than :data:`CONTACT_TOLERANCE` (round-off of the gap evaluation) of any
other pair is an interference: :func:`check_assembly` raises
:class:`~rvsim.errors.ParameterError` naming the parts, the overlap and the parameters that
close clearance.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from ..errors import ParameterError
from ..parameters import Reducer
from .cycloid import nominal_disc_pose, pin_gaps

__all__ = ["CONTACT_TOLERANCE", "ROLLING", "Overlap", "assembly_overlaps", "rigid_overlaps",
           "check_assembly"]

#: an overlap at or below this is contact (round-off of the exact gap), not interference [m]
CONTACT_TOLERANCE = 1e-9
#: the elements whose interference is elastic preload of their rollers (Overlap.element)
ROLLING = ("arm_needles", "support_rollers")

#: parameters whose non-zero value can close clearance at the assembled pose
_CLOSING = ("errors.eccentricity", "errors.rotation_modification", "errors.disc_runout",
            "errors.pin_position_tolerance")
#: parameters that open clearance when positive and close it when negative (F, H, I, J)
_OPENING = ("errors.pin_radius", "errors.pin_circle_radius", "errors.equidistant_modification",
            "errors.radial_modification")


@dataclasses.dataclass(frozen=True)
class Overlap:
    """The approach of one pair of parts at the assembled pose (positive = overlap) [m].

    ``element``: "pin", "arm_bushing", "support_bushing", "mesh", "output_pin" or one of
    :data:`ROLLING`; ``preload`` [m]: a rolling bearing's own radial preload (half its
    negative radial internal clearance), which ``approach`` leaves out (intended, not an
    interference): the most loaded roller's radial approach is ``approach + preload``."""

    parts: str
    approach: float
    element: str = "pin"
    preload: float = 0.0


def _pin_overlaps(reducer: Reducer) -> list[Overlap]:
    result = []
    for disc in range(2):
        gaps = pin_gaps(reducer, 0.0, disc=disc)
        for pin in range(gaps.shape[0]):
            angle = 360.0 * pin / gaps.shape[0]
            result.append(Overlap(f"disc {disc + 1} overlaps pin {pin} (at {angle:g} deg)",
                                  -float(gaps[pin])))
    return result


def _bushing_overlaps(reducer: Reducer) -> list[Overlap]:
    from ._pose import bore_centre_py, disc_centre_py
    from .layout import (arm_bushing_play, crank_holes, crank_radius, disc_count,
                         support_bushing_play)

    single = reducer.layout.single_stage
    arm_clearance = arm_bushing_play(reducer)
    eccentric = reducer.cycloid.eccentricity - reducer.errors.eccentricity
    result = []
    from .deviations import bore_offsets, eccentric_errors, hole_offsets
    from .layout import crank_angles

    size, turn = eccentric_errors(reducer)            # per-part errors (zero without them)
    holes_off, bores = hole_offsets(reducer), bore_offsets(reducer)
    for crank, hole in enumerate(crank_holes(reducer)):
        turned = crank_angles(reducer)[crank]
        # the crank's axis on its carrier bores' centre (the dynamic model's starting pose)
        axis = np.array(bore_centre_py(crank_radius(reducer) + bores[crank, 0], bores[crank, 1],
                                       math.cos(turned), math.sin(turned)))
        for disc in range(disc_count(reducer)):
            # eccentric of crank ``crank`` for disc ``disc`` (crank centred in its carrier
            # bores, phase 0) ...
            k = 2 * crank + disc
            pin = axis + np.array(disc_centre_py(eccentric + size[k], turn[k], disc))
            # ... and the disc's crank hole, carried by the disc's assembled pose
            x, y, angle = nominal_disc_pose(reducer, 0.0, disc)
            cos_t, sin_t = math.cos(angle), math.sin(angle)
            hx, hy = hole + holes_off[crank, 2 * disc:2 * disc + 2]
            bore = np.array([x + cos_t * hx - sin_t * hy, y + sin_t * hx + cos_t * hy])
            offset = float(np.linalg.norm(pin - bore))
            if reducer.bearings.arm_needles:
                # needles between eccentric and hole: they must fit the radial space, which
                # the bearing's radial internal clearance widens by half of it (its radial
                # play, as rvsim.bearings.arm_play; a preload, negative needle_clearance, is
                # intended, not an overlap); needles smaller than the space add no room, as in
                # arm_play (the engines' gap): the preload judged is the engines' (review)
                excess = max(reducer.bearings.needle_diameter
                             - reducer.crank.arm_bushing_thickness, 0.0)
                needle = reducer.bearings.needle_clearance
                room = arm_clearance + 0.5 * max(needle, 0.0)
                result.append(Overlap(f"crank {crank + 1} needle rollers do not fit between "
                                      f"the eccentric and the hole of disc {disc + 1}",
                                      offset + excess - room, "arm_needles",
                                      0.5 * max(-needle, 0.0)))
                continue
            result.append(Overlap(f"crank {crank + 1} eccentric overlaps the arm bushing of "
                                  f"disc {disc + 1}", offset - arm_clearance, "arm_bushing"))
        # the crank's support journals start on their bore centres
        supports = ((("input shaft", reducer.layout.input_bearing_clearance),) if single else
                    (("lower (flange)", support_bushing_play(reducer, False)),
                     ("upper (carrier)", support_bushing_play(reducer, True))))
        rollers = reducer.bearings.support_rollers and not single
        own = reducer.bearings.support_clearance if rollers else 0.0
        for name, clearance in supports:
            kind = "bearing" if rollers else "bushing"
            result.append(Overlap(f"crank {crank + 1} overlaps its {name} support {kind}",
                                  0.0 - clearance - 0.5 * max(own, 0.0),
                                  "support_rollers" if rollers else "support_bushing",
                                  0.5 * max(-own, 0.0)))
    return result


def _output_pin_overlaps(reducer: Reducer) -> list[Overlap]:
    """Single-stage drive: each output pin in its hole of each disc (flange at angle 0)."""
    from .layout import disc_count, output_hole_clearance, output_pins

    clearance = output_hole_clearance(reducer)
    result = []
    for disc in range(disc_count(reducer)):
        x, y, angle = nominal_disc_pose(reducer, 0.0, disc)
        cos_t, sin_t = math.cos(angle), math.sin(angle)
        for m, pin in enumerate(output_pins(reducer)):
            hole = np.array([x + cos_t * pin[0] - sin_t * pin[1],
                             y + sin_t * pin[0] + cos_t * pin[1]])
            result.append(Overlap(f"output pin {m} overlaps its hole in disc {disc + 1}",
                                  float(np.linalg.norm(pin - hole)) - clearance,
                                  "output_pin"))
    return result


def _mesh_overlaps(reducer: Reducer) -> list[Overlap]:
    # input, carrier and crank phases are zero: the mesh deflection along the line of action
    # is zero, so the approach is minus half the normal backlash (kernel gear_mesh)
    if reducer.layout.single_stage:
        return []
    return [Overlap(f"planet {crank + 1} overlaps the sun", 0.0 - 0.5 * reducer.gears.backlash,
                    "mesh") for crank in range(2)]


def assembly_overlaps(reducer: Reducer) -> list[Overlap]:
    """Approach of every pin, bushing and mesh at the assembled pose (positive = overlap)."""
    return (_pin_overlaps(reducer) + _bushing_overlaps(reducer) + _mesh_overlaps(reducer)
            + _output_pin_overlaps(reducer))


def _closing_parameters(reducer: Reducer) -> str:
    from ..parameters._io import SPECS, get_value

    named = []
    for name in _CLOSING + _OPENING:
        value = get_value(reducer, name)
        if (value < 0.0) if name in _OPENING else (value != 0.0):
            named.append(f"{name} = {value:g} {SPECS[name].unit}")
    if reducer.parts.any:
        named.append("per-part errors (reducer.parts)")
    if not named:
        return ""
    return (f" (clearance closed by {' and '.join(named)}, not opened enough by positive F, H, "
            "I, J)")


def rigid_overlaps(reducer: Reducer) -> list[Overlap]:
    """:func:`assembly_overlaps` but the rolling bearings' (whose interference is elastic
    preload, judged by :func:`rvsim.bearings.check_preload`)."""
    return [o for o in assembly_overlaps(reducer) if o.element not in ROLLING]


def check_assembly(reducer: Reducer) -> None:
    """Raise :class:`ParameterError` if any two parts overlap at the assembled pose, other than
    the rollers of a rolling bearing (elastic preload: :func:`rvsim.bearings.check_preload`)."""
    # round-off ties (disc 2 mirrors disc 1) go to the first part listed
    worst = max(rigid_overlaps(reducer), key=lambda o: round(o.approach, 12))
    if worst.approach > CONTACT_TOLERANCE:
        micrometres = worst.approach * 1e6      # an overlap below 0.05 um is not "0.0 um"
        size = f"{micrometres:.1f}" if micrometres >= 0.1 else f"{micrometres:.2g}"
        raise ParameterError("assembly", f"{worst.parts} by {size} um at "
                             f"the assembled pose{_closing_parameters(reducer)}")
