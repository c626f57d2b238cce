"""An interference of a rolling bearing is assembled with elastic preload (issue 32 item 2).

A crank hole moved off its place against needle rollers without clearance makes the rollers'
space smaller than the rollers: the reducer is assembled with the rollers preloaded, refused
(status ``binds``) only where the preload's Hertz stress exceeds ``rating.static_contact_stress``
(ISO 76).  Measured 2026-11-28 on `RV-40E-bearings`, crank 1's hole in disc 1 moved 5 um:

* the most loaded needle's force equals Palmgren's law (Harris & Kotzalas, Eq. 7.9) of both
  raceways in series at the 5 um approach, written here independently: within 2e-16 relative
  (tolerance 1e-12); 954.41 N;
* its Hertz pressure on the eccentric (Johnson, Contact Mechanics, section 4.3), the larger
  of its two raceway contacts, written here independently (1e-12); 1476.2 MPa (about
  30 um reach the 4000 MPa limit: 3994 MPa);
* the limit: refused (the stress in the one-line reason, field ``assembly``) with the static
  limit 1 MPa below that stress, kept 1 MPa above it; the engines refuse it where they build
  their model, a tolerance run counts it ``binds``;
* the dynamic engine, started from the assembled pose, settles within 20 ms on the
  quasi-static no-load equilibrium (the needle set's 4673 N at t = 0 to 2145.7 N, 1.8e-5).
"""

import dataclasses
import math

import pytest

from rvsim.bearings import check_preload, preload_refusal, roller_preloads
from rvsim.errors import ParameterError
from rvsim.parameters import BUILT_IN_SETS, PartErrors, with_values
from rvsim.physics.compliance import effective_modulus

BEARINGS = BUILT_IN_SETS["RV-40E-bearings"]
#: Palmgren's line contact of bearing steel: delta [mm] = 3.84e-5 Q^0.9 / l^0.8
PALMGREN_MM = 3.84e-5


def _hole_moved(reducer, dx):
    holes = ((dx, 0.0, 0.0, 0.0), (0.0, 0.0, 0.0, 0.0))      # crank 1's hole in disc 1
    return dataclasses.replace(reducer, parts=PartErrors(disc_holes=holes))


def test_preload_force_of_an_interference_is_the_roller_law_at_that_approach():
    reducer = _hole_moved(BEARINGS, 5e-6)
    (preload,) = roller_preloads(reducer)          # only that bearing is preloaded
    assert preload.parts.startswith("crank 1 needle rollers") and "disc 1" in preload.parts
    assert preload.interference == pytest.approx(5e-6, abs=1e-15)
    b, k, m = reducer.bearings, reducer.crank, reducer.materials
    # Palmgren's constant holds for bearing steel on bearing steel (E 207.5 GPa, nu 0.3)
    steel = 2.075e11 / (2.0 * (1.0 - 0.3 ** 2))
    # Palmgren per raceway, scaled by the pair's E*; the two raceways in series
    per_raceway = [PALMGREN_MM * 1e-3 / (b.needle_length * 1e3) ** 0.8
                   * steel / effective_modulus(m.bushing, other)
                   for other in (m.crankshaft, m.cycloid_disc)]
    force = (preload.interference / sum(per_raceway)) ** (1.0 / 0.9)     # at that approach
    assert preload.force == pytest.approx(force, rel=1e-12)
    assert preload.force == pytest.approx(954.41, abs=0.01)
    # Hertz: p0 = sqrt(Q E* (1/r1 + 1/r2) / (pi L)), the roller on the convex eccentric
    inner = math.sqrt(force * effective_modulus(m.bushing, m.crankshaft)
                      * (2.0 / b.needle_diameter + 1.0 / k.eccentric_radius)
                      / (math.pi * b.needle_length))
    assert preload.stress == pytest.approx(inner, rel=1e-12)
    assert preload.stress == pytest.approx(1476.2e6, abs=0.1e6)


def test_preload_is_refused_only_above_the_static_limit():
    reducer = _hole_moved(BEARINGS, 5e-6)
    stress = roller_preloads(reducer)[0].stress
    below = with_values(reducer, {"rating.static_contact_stress": stress / 1e6 + 1.0})
    above = with_values(reducer, {"rating.static_contact_stress": stress / 1e6 - 1.0})
    assert preload_refusal(below) is None
    check_preload(below)
    with pytest.raises(ParameterError) as info:
        check_preload(above)
    assert info.value.field == "assembly"
    assert "by 5.00 um" in info.value.reason and f"{stress / 1e6:.0f} MPa" in info.value.reason
    # the engines refuse it where they build their model; a tolerance run: binds, same reason
    from rvsim.dynamics.model import build_model
    from rvsim.tolerance.engine import evaluate_sample

    with pytest.raises(ParameterError, match="static limit"):
        build_model(above, 1e-5)
    outcome = evaluate_sample(above, 81)
    assert outcome["status"] == "binds" and outcome["error"] == info.value.reason


def test_without_interference_nothing_is_preloaded():
    assert roller_preloads(BEARINGS) == []
    assert roller_preloads(_hole_moved(BEARINGS, -0.0)) == []


def test_the_engines_preload_needles_larger_than_their_space_as_the_verdict_does():
    """Needles 5 um larger than their radial space: the verdict's approach is the roller
    sets' gap in the engines' model (it was refused before any model was built)."""
    from rvsim.dynamics.model import build_model
    from rvsim.physics import _layout as L

    reducer = with_values(BEARINGS, {"bearings.needle_diameter": 3.005})
    approaches = {p.interference for p in roller_preloads(reducer)}
    assert len(roller_preloads(reducer)) == 4 and len(approaches) == 1
    assert build_model(reducer, 1e-5).P[L.ARM_CLEAR] == pytest.approx(-approaches.pop(),
                                                                     abs=1e-15)


def test_the_dynamic_engine_settles_on_the_quasi_static_preload():
    """Both engines with the preload: the dynamic run starts from the assembled pose (crank 1's
    needles in disc 1 at 4673 N) and settles within 20 ms on the quasi-static equilibrium at
    the same input angle and no load: 2145.7 N within 1.8e-5 (tolerance 1e-4), the three
    other arm forces (797, 161, 111 N) within 0.72 % (tolerance 1 %: the small ones still ring
    at 20 ms).  The explicit scheme, whose balance closes from an early window."""
    import numpy as np

    from rvsim.dynamics import simulate
    from rvsim.physics import _layout as L
    from rvsim.quasistatic import solve_path

    reducer = with_values(_hole_moved(BEARINGS, 5e-6), {"operating.steady_start": 0.01})
    run = simulate(reducer, duration=0.02)
    arms = slice(L.CH_ARM_F00, L.CH_ARM_F11 + 1)
    assert run.channels[0, L.CH_ARM_F00] == pytest.approx(4673.28, abs=0.01)
    last = run.channels[-1]
    static = solve_path(reducer, np.array([last[L.CH_THETA_IN]]), np.array([0.0]))
    assert static.status == "ok" and last[L.CH_TORQUE_LOAD] == 0.0
    assert last[L.CH_ARM_F00] == pytest.approx(static.channels[0, L.CH_ARM_F00], rel=1e-4)
    assert last[arms] == pytest.approx(static.channels[0, arms], rel=1e-2)
    assert static.channels[0, L.CH_ARM_F00] == pytest.approx(2145.6, abs=0.1)
