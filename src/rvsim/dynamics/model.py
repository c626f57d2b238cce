"""Assemble the kernel's constant vector and arrays from a :class:`~rvsim.parameters.Reducer`.

Mass properties come from simple solids of the part sizes and Table 5 densities; compliances
from :mod:`rvsim.physics.compliance`.  Every assumption is listed in docs/model.md.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from ..geometry.cycloid import profile_offset
from ..geometry._pose import bore_centre_py, disc_centre_py
from ..geometry.deviations import bore_offsets, eccentric_errors, hole_offsets, pin_table
from ..geometry.involute import gear_geometry
from ..parameters.fe_sizes import check_element_sizes
from ..bearings import check_preload
from ..friction import fill_constants as fill_friction_constants
from ..errors import ParameterError
from ..parameters import Reducer
from ..physics import _layout as L
from ..physics._bearings import bushing_shift
from ._implicit_bearings import REFRESH_STEPS as IMPLICIT_REFRESH_STEPS
from ._implicit_bearings import THETA as IMPLICIT_THETA
from ..physics.compliance import palmgren_coefficient, pin_compliance, ring_compliance, tooth_compliance

__all__ = ["KernelModel", "build_model", "MassProperties", "mass_properties"]

#: stability guard of the crank nodes (dynamics._stiff_nodes, docs/model.md section 9): the
#: largest omega dt of a crank's node modes before the step is divided into sub-steps (below
#: the undamped limit 2 of the scheme with the margin measured in docs/benchmarks.md: 1.8 let
#: paper run 2 diverge at 1e-5 s with the earlier mass-scaling guard), and the steps between
#: two checks
OMEGA_DT_LIMIT = 1.6
REFRESH_STEPS = 8
#: the guard runs for steps above this [s] only: at and below it the node modes stay at
#: omega dt <= 1.3 (0.58-1.07 measured at 5e-6 s), and its checks cost about 3 % of the run
GUARD_FROM_STEP = 6e-6
#: integration schemes (docs/model.md section 9): the semi-implicit Euler step with the guard
#: above, or the same step with the bearings taken linearly implicitly (dynamics.
#: _implicit_bearings), each with its default step [s]
EXPLICIT = "explicit"
IMPLICIT_BEARINGS = "implicit-bearings"
SCHEMES = {EXPLICIT: 5e-6, IMPLICIT_BEARINGS: 2e-5}


@dataclasses.dataclass(frozen=True)
class MassProperties:
    """Masses [kg] and inertias [kg m^2] of the moving parts."""

    disc_mass: float
    disc_inertia: float
    crank_mass: float
    crank_inertia: float
    crank_node_mass: np.ndarray  # 2x2 mass matrix of the (lower, upper) support nodes
    carrier_inertia: float


def _cylinder(radius: float, length: float, density: float) -> float:
    return math.pi * radius ** 2 * length * density


def mass_properties(r: Reducer) -> MassProperties:
    """Mass properties from the part sizes (simple solids; docs/model.md)."""
    if r.layout.single_stage:
        return _single_stage_masses(r)
    c, k, g = r.cycloid, r.crank, r.gears
    gear = gear_geometry(r)
    rho_disc = r.materials.cycloid_disc.density
    outer = c.pin_circle_radius - c.pin_radius
    hole = k.eccentric_radius + k.arm_bushing_thickness
    m_full = _cylinder(outer, c.disc_width, rho_disc)
    m_bore = _cylinder(c.disc_bore_radius, c.disc_width, rho_disc)
    m_hole = _cylinder(hole, c.disc_width, rho_disc)
    m_pillar = _cylinder(c.pillar_hole_radius, c.disc_width, rho_disc)
    n_holes = g.planet_count
    disc_mass = m_full - m_bore - n_holes * m_hole - c.pillar_hole_count * m_pillar
    a_w = gear.centre_distance
    disc_inertia = (0.5 * m_full * outer ** 2 - 0.5 * m_bore * c.disc_bore_radius ** 2
                    - n_holes * m_hole * (0.5 * hole ** 2 + a_w ** 2)
                    - c.pillar_hole_count * m_pillar * (0.5 * c.pillar_hole_radius ** 2
                                                        + a_w ** 2))

    # shaft: journal radius from the lower bushing's outer face to the gear, and the eccentrics
    nodes, crank_mass, crank_inertia = _crank_nodes(
        r, k.lower_support_z - 0.5 * k.support_bushing_width, k.gear_z, 2)
    span = k.upper_support_z - k.lower_support_z
    weights = lambda z: np.array([(k.upper_support_z - z) / span,  # noqa: E731
                                  (z - k.lower_support_z) / span])
    tilt = np.array([[1.0, -1.0], [-1.0, 1.0]]) / span ** 2
    # planet gear: annulus from the journal to the pitch radius
    rho_gear = r.materials.planet_gear.density
    r_out = 0.5 * g.module * g.planet_teeth
    m_gear = _cylinder(r_out, g.face_width, rho_gear) - _cylinder(k.journal_radius,
                                                                  g.face_width, rho_gear)
    w = weights(k.gear_z)
    nodes += m_gear * np.outer(w, w)
    nodes += m_gear * (3.0 * (r_out ** 2 + k.journal_radius ** 2) + g.face_width ** 2) / 12.0 \
        * tilt
    crank_inertia += 0.5 * m_gear * (r_out ** 2 + k.journal_radius ** 2)
    crank_mass += m_gear

    m_carrier = _cylinder(c.carrier_radius, c.carrier_thickness, r.materials.carrier.density)
    carrier_inertia = 0.5 * m_carrier * c.carrier_radius ** 2
    return MassProperties(disc_mass, disc_inertia, crank_mass, crank_inertia, nodes,
                          carrier_inertia)


def _crank_nodes(r: Reducer, z0: float, z1: float, discs: int):
    """Node mass matrix, mass and polar inertia of a shaft of journal radius from z0 to z1
    with ``discs`` eccentrics at the disc stations (slices lumped on the two support nodes)."""
    c, k = r.cycloid, r.crank
    rho = r.materials.crankshaft.density
    span = k.upper_support_z - k.lower_support_z
    weights = lambda z: np.array([(k.upper_support_z - z) / span,  # noqa: E731
                                  (z - k.lower_support_z) / span])
    nodes = np.zeros((2, 2))
    slices = np.linspace(z0, z1, 41)
    mass = 0.0
    for za, zb in zip(slices[:-1], slices[1:]):
        m = _cylinder(k.journal_radius, zb - za, rho)
        w = weights(0.5 * (za + zb))
        nodes += m * np.outer(w, w)
        mass += m
    inertia = 0.5 * mass * k.journal_radius ** 2
    tilt = np.array([[1.0, -1.0], [-1.0, 1.0]]) / span ** 2
    for z in (k.disc1_z, k.disc2_z)[:discs]:
        m = _cylinder(k.eccentric_radius, c.disc_width, rho) - _cylinder(
            k.journal_radius, c.disc_width, rho)
        w = weights(z)
        nodes += m * np.outer(w, w)
        nodes += m * (3.0 * k.eccentric_radius ** 2 + c.disc_width ** 2) / 12.0 * tilt
        inertia += m * (0.5 * k.eccentric_radius ** 2 + c.eccentricity ** 2)
        mass += m
    return nodes, mass, inertia


def _single_stage_masses(r: Reducer) -> MassProperties:
    """Single-stage drive: disc with a central eccentric bore and output-pin holes; the
    eccentric shaft between its bearings; the output flange (docs/model.md section 13)."""
    c, k, lay = r.cycloid, r.crank, r.layout
    rho = r.materials.cycloid_disc.density
    outer = c.pin_circle_radius - c.pin_radius
    bore = k.eccentric_radius + k.arm_bushing_thickness
    hole = lay.output_pin_radius + c.eccentricity + lay.output_pin_clearance
    m_full = _cylinder(outer, c.disc_width, rho)
    m_bore = _cylinder(bore, c.disc_width, rho)
    m_hole = _cylinder(hole, c.disc_width, rho)
    n = lay.output_pin_count
    disc_mass = m_full - m_bore - n * m_hole
    disc_inertia = (0.5 * m_full * outer ** 2 - 0.5 * m_bore * bore ** 2
                    - n * m_hole * (0.5 * hole ** 2 + lay.output_pin_circle_radius ** 2))
    z0 = k.lower_support_z - 0.5 * k.support_bushing_width
    z1 = k.upper_support_z + 0.5 * k.support_bushing_width
    nodes, crank_mass, crank_inertia = _crank_nodes(r, z0, z1, lay.disc_count)
    if lay.ring_output:
        return MassProperties(disc_mass, disc_inertia, crank_mass, crank_inertia, nodes,
                              ring_inertia(r))
    m_flange = _cylinder(c.carrier_radius, c.carrier_thickness, r.materials.carrier.density)
    return MassProperties(disc_mass, disc_inertia, crank_mass, crank_inertia, nodes,
                          0.5 * m_flange * c.carrier_radius ** 2)


def ring_inertia(r: Reducer) -> float:
    """Single-stage drive with the pin ring as output: polar inertia of the turning housing, a
    ring from the pin circle radius out to the pin circle radius plus one pin diameter (its
    wall; assumed, docs/model.md section 13) over the discs' width, plus the pins (solid
    cylinders on the pin circle) [kg m^2]."""
    c, lay, m = r.cycloid, r.layout, r.materials
    length = lay.disc_count * c.disc_width
    inner, outer = c.pin_circle_radius, c.pin_circle_radius + 2.0 * c.pin_radius
    m_ring = _cylinder(outer, length, m.carrier.density) - _cylinder(inner, length,
                                                                    m.carrier.density)
    m_pin = _cylinder(c.pin_radius, length, m.pin.density)
    return (0.5 * m_ring * (inner ** 2 + outer ** 2)
            + c.pin_count * m_pin * (0.5 * c.pin_radius ** 2 + c.pin_circle_radius ** 2))


def input_stiffness(r: Reducer) -> float:
    """Single-stage drive: torsional stiffness of the eccentric shaft between the input
    coupling and the discs, G J / L with the journal's polar moment over the bearing span
    (assumed; docs/model.md section 13) [N*m/rad]."""
    k, mat = r.crank, r.materials.crankshaft
    shear = mat.elastic_modulus / (2.0 * (1.0 + mat.poisson_ratio))
    return shear * 0.5 * math.pi * k.journal_radius ** 4 / (k.upper_support_z - k.lower_support_z)


@dataclasses.dataclass(frozen=True)
class KernelModel:
    """Everything the compiled kernel needs, as arrays."""

    P: np.ndarray
    pins: np.ndarray
    holes: np.ndarray
    crank_angles: np.ndarray
    mesh_phase: np.ndarray
    q0: np.ndarray
    masses: MassProperties
    #: the discs' finite-element compliance tables (2, m, m); (2, 0, 0) with closed-form bodies
    fe: np.ndarray = dataclasses.field(default_factory=lambda: np.zeros((2, 0, 0)))


def _station_weights(r: Reducer, z: float) -> tuple[float, float]:
    k = r.crank
    span = k.upper_support_z - k.lower_support_z
    return (k.upper_support_z - z) / span, (z - k.lower_support_z) / span


def fill_turns(P: np.ndarray) -> None:
    """The constant turns of the kernel's angles (P[FRAME_TURN0 ..], P[ECC_TURN0 ..]), so that
    a force evaluation takes one cosine and sine per angle (docs/model.md section 9), from
    P[ZC], P[PROFILE_ROT] and P[ECC_PHASE0 ..]."""
    from ..physics._frames import eccentric_angle, profile_turn
    for disc in range(2):
        turn = profile_turn(P, disc)
        P[L.FRAME_TURN0 + 2 * disc:L.FRAME_TURN0 + 2 * disc + 2] = math.cos(turn), math.sin(turn)
    at_rest = np.zeros(L.N_DOF)
    for j in range(2):       # disc 1's eccentric less disc 0's
        turn = eccentric_angle(P, at_rest, j, 1) - eccentric_angle(P, at_rest, j, 0)
        P[L.ECC_TURN0 + 2 * j:L.ECC_TURN0 + 2 * j + 2] = math.cos(turn), math.sin(turn)


def build_model(r: Reducer, time_step: float, scheme: str = EXPLICIT) -> KernelModel:
    """Constant vector, pin and hole positions and the initial (assembled) state, for the
    integration ``scheme`` (one of :data:`SCHEMES`)."""
    c, k, e, cl, m = r.cycloid, r.crank, r.errors, r.clearances, r.materials
    gear = None if r.layout.single_stage else gear_geometry(r)
    masses = mass_properties(r)
    P = np.zeros(L.N_PARAMS)
    P[L.DT] = time_step
    op = r.operating
    P[L.INPUT_SPEED] = op.input_speed
    P[L.RAMP_TIME] = op.speed_ramp_time
    P[L.LOAD] = op.load_torque
    P[L.LOAD_T0] = op.load_start
    P[L.LOAD_T1] = op.load_ramp_end
    P[L.FLUCT_AMP] = op.fluctuation_amplitude if op.load_fluctuation else 0.0
    P[L.FLUCT_FREQ] = op.fluctuation_frequency
    P[L.STEADY_START] = op.steady_start

    if not r.layout.single_stage:  # the single-stage drive has no involute stage
        P[L.RB1] = gear.sun_base_radius
        P[L.RB2] = gear.planet_base_radius
        P[L.CENTRE_DIST] = gear.centre_distance
        P[L.SIN_AW] = math.sin(gear.operating_pressure_angle)
        P[L.BACKLASH] = r.gears.backlash
        P[L.BASE_PITCH] = gear.base_pitch
        P[L.CONTACT_RATIO] = gear.contact_ratio
        P[L.K_MESH] = gear.single_pair_stiffness
        P[L.MESH_MASS] = masses.crank_inertia / gear.planet_base_radius ** 2

    P[L.RG] = c.pin_circle_radius - e.radial_modification
    P[L.A_GEN] = c.eccentricity
    P[L.ZP] = c.pin_count
    P[L.ZC] = c.disc_teeth
    P[L.PROFILE_OFFSET] = c.pin_radius + e.equidistant_modification
    P[L.PIN_RADIUS] = c.pin_radius - e.pin_radius
    P[L.ECC] = c.eccentricity - e.eccentricity
    P[L.PROFILE_ROT] = e.rotation_modification

    P[L.PIN_C] = palmgren_coefficient(c.disc_width, m.cycloid_disc, m.pin)
    # the pin load that carries the rated torque at the largest lever arm
    # (the pin ring as output carries zp / zc times the torque that the disc would carry)
    disc_torque = r.rating.rated_torque * (c.disc_teeth / c.pin_count
                                           if r.layout.single_stage and r.layout.ring_output
                                           else 1.0)
    pin_load = disc_torque / (2.0 * c.eccentricity * c.disc_teeth)
    root_radius = c.pin_circle_radius - c.pin_radius - c.eccentricity
    body = 0.0
    check_element_sizes(r)          # before the first mesh (validate has, unless bypassed)
    check_preload(r)    # a rolling bearing's interference: elastic preload within ISO 76
    fe_disc = r.flexibility.cycloid_disc and r.flexibility.model == "fe"
    if r.flexibility.cycloid_disc and not fe_disc:
        body += tooth_compliance(2.0 * c.eccentricity, 2.0 * math.pi * root_radius / c.disc_teeth,
                                 c.disc_width, m.cycloid_disc)
    fe_pin = r.flexibility.pin and r.flexibility.model == "fe"
    if r.flexibility.pin and not fe_pin:
        body += pin_compliance(c.pin_radius, c.disc_width, pin_load, m.pin)
    P[L.PIN_CB] = body
    if fe_pin:      # the finite-element pin in its groove, read at each contact's angle
        _fe_pin_table(r, P)
    _bearing_constants(r, P)
    P[L.FE_DISC] = 1.0 if fe_disc else 0.0
    holes = fe_disc and r.flexibility.fe_disc_holes and not r.layout.single_stage
    P[L.FE_HOLES] = 1.0 if holes else 0.0
    # the dynamic engine's disc modes (rvsim.dynamics.simulate builds them; docs/model.md 17)
    P[L.FE_MODES] = r.flexibility.fe_modes if fe_disc else 0
    if fe_crank_used(r):
        P[L.FE_CRANK_XX1:L.FE_CRANK_XX1 + 10] = _fe_crank_constants(r)
    _fe_plate_constants(r, P)      # finite-element carrier and flange (docs/model.md sec. 17)
    P[L.ZETA] = r.contact.damping_ratio
    P[L.V_FRIC] = r.contact.friction_velocity
    fill_friction_constants(r, P)       # P[MU] and the friction block (docs/model.md sec. 15)

    # the driven load turns with the carrier (rigid coupling; docs/model.md section 7)
    P[L.J_CARRIER] = masses.carrier_inertia + op.load_inertia
    P[L.M_DISC] = masses.disc_mass
    P[L.J_DISC] = masses.disc_inertia
    P[L.J_CRANK] = masses.crank_inertia
    inv = np.linalg.inv(masses.crank_node_mass)
    P[L.MINV_LL], P[L.MINV_LU], P[L.MINV_UU] = inv[0, 0], inv[0, 1], inv[1, 1]
    P[L.M_NODE] = 0.5 * (masses.crank_node_mass[0, 0] + masses.crank_node_mass[1, 1])
    P[L.W_D1_L], P[L.W_D1_U] = _station_weights(r, k.disc1_z)
    P[L.W_D2_L], P[L.W_D2_U] = _station_weights(r, k.disc2_z)
    P[L.W_G_L], P[L.W_G_U] = _station_weights(r, k.gear_z)
    P[L.PEN_LIMIT] = 0.2e-3
    # stability guard of the crank nodes (dynamics._stiff_nodes; docs/model.md section 9);
    # off with a coupled finite-element body (disc, crank, plates): its stiffness assembly
    # would switch their solves from the dynamic sweep to the converged quasi-static one
    coupled_fe = P[L.FE_DISC] == 1.0 or P[L.FE_CRANK_XX1] > 0.0 or P[L.FE_PLATE_XX1] > 0.0
    if not (isinstance(scheme, str) and scheme in SCHEMES):
        raise ValueError(f"unknown integration scheme {scheme!r} (one of {', '.join(SCHEMES)})")
    implicit = scheme == IMPLICIT_BEARINGS
    P[L.NODE_OMEGA_DT] = (OMEGA_DT_LIMIT if time_step > GUARD_FROM_STEP and not coupled_fe
                          and not implicit else 0.0)
    P[L.NODE_REFRESH] = REFRESH_STEPS
    # the bearings linearly implicit (dynamics._implicit_bearings): no guard, it needs none
    P[L.IMPLICIT_THETA] = IMPLICIT_THETA if implicit else 0.0
    P[L.IMPLICIT_REFRESH] = IMPLICIT_REFRESH_STEPS

    pins = pin_table(r)       # pin centres, and per-pin / per-tooth errors when there are any
    size, phase = eccentric_errors(r)
    P[L.ECC_ERR0:L.ECC_ERR0 + 4] = size
    P[L.ECC_PHASE0:L.ECC_PHASE0 + 4] = phase
    fill_turns(P)
    bores = bore_offsets(r)
    P[L.BORE_DR0:L.BORE_DR0 + 2] = bores[:, 0]
    P[L.BORE_DT0:L.BORE_DT0 + 2] = bores[:, 1]
    P[L.RUNOUT_X0], P[L.RUNOUT_Y0] = profile_offset(r, 0)
    P[L.RUNOUT_X1], P[L.RUNOUT_Y1] = profile_offset(r, 1)
    P[L.STAGES] = r.layout.stages
    P[L.CRANK_COUNT] = 2
    P[L.DISC_COUNT] = 2
    if r.layout.single_stage:
        _single_stage_constants(r, P)
    # ln(a2 / a1) of each conforming bushing, once per run (_bearings.conforming_force)
    for shift, a1, a2 in ((L.ARM_SHIFT, L.ARM_A1, L.ARM_A2),
                          (L.SUP_SHIFT_L, L.SUP_A1, L.SUP_A2_L),
                          (L.SUP_SHIFT_U, L.SUP_A1, L.SUP_A2_U)):
        P[shift] = bushing_shift(P[a1], P[a2])
    crank_angles = np.array([0.0, math.pi])
    if r.layout.single_stage:
        holes = np.zeros((2, 2))  # the eccentric shaft on the axis (the second row unused)
    else:
        holes = gear.centre_distance * np.column_stack([np.cos(crank_angles),
                                                        np.sin(crank_angles)])
    mesh_phase = (r.gears.sun_teeth * crank_angles / (2.0 * math.pi)) % 1.0
    q0 = np.zeros(L.N_DOF)
    # the crank starts on its carrier bores' centre (the single-stage drive's one eccentric
    # shaft on the axis: the second crank's coordinates unused, left at zero)
    for j in range(1 if r.layout.single_stage else 2):
        b = L.CRANK0 + L.CRANK_STRIDE * j
        x, y = bore_centre_py(P[L.CENTRE_DIST] + bores[j, 0], bores[j, 1],
                              math.cos(crank_angles[j]), math.sin(crank_angles[j]))
        q0[b:b + 4] = [x, y, x, y]
    if r.parts.disc_holes:
        holes = np.hstack([holes, hole_offsets(r)])
    for kd in range(2):
        d = L.DISC0 + L.DISC_STRIDE * kd
        q0[d], q0[d + 1] = disc_centre_py(P[L.ECC], 0.0, kd)
    tables = _fe_tables(r, P, holes) if fe_disc else np.zeros((2, 0, 0))
    P, tables = _scaled_stiffness(r, P, tables)
    return KernelModel(P, pins, holes, crank_angles, mesh_phase, q0, masses, tables)


def _scaled_stiffness(r: Reducer, P: np.ndarray, tables: np.ndarray):
    """P and the FE disc tables with the ``stiffness.*`` scalings of ``r`` (the compliance
    budget's stiffening, :func:`rvsim.physics.stiffening.stiffen`); unchanged, not copied,
    when every factor is 1.  A factor other than 1 for a group the model lacks is a
    ParameterError."""
    from ..physics.stiffening import elements_in, stiffen

    factors = {f.name: getattr(r.stiffness, f.name) for f in dataclasses.fields(r.stiffness)
               if getattr(r.stiffness, f.name) != 1.0}
    if not factors:
        return P, tables
    present = elements_in(P)
    for name in factors:
        if name not in present:
            raise ParameterError(f"stiffness.{name}", f"this model has no such element (it "
                                 f"has {', '.join(present)}): leave it at 1")
    if "fe_disc" in factors and P[L.FE_MODES] > 0:
        # the dynamic engine's disc modes come from the unscaled mesh (rvsim.fe.modes)
        raise ParameterError("stiffness.fe_disc", "cannot be scaled with flexibility.fe_modes "
                             "> 0 (the disc's modes are not scaled): leave it at 1 or set "
                             "fe_modes = 0")
    return stiffen(P, tables, factors)


def _fe_tables(r: Reducer, P: np.ndarray, holes: np.ndarray) -> np.ndarray:
    """The finite-element disc tables (rvsim.fe: meshed and condensed once per geometry); with
    the crank holes as load points (P[FE_HOLES], rvsim.fe.disc_holes) each disc's table has the
    holes' stretch column c_sp last and P gets c_ss and the holes' axis (physics._fe_holes)."""
    if P[L.FE_HOLES] == 0.0:
        from ..fe.disc import disc_tables

        return disc_tables(r)
    from ..fe.disc_holes import disc_hole_tables

    tables, css = disc_hole_tables(r)
    P[L.FE_HOLE_CSS0], P[L.FE_HOLE_CSS1] = css
    axis = holes[1, :2] - holes[0, :2]
    P[L.FE_HOLE_EX], P[L.FE_HOLE_EY] = axis / np.hypot(*axis)
    return tables


def _fe_pin_table(r: Reducer, P: np.ndarray) -> None:
    """The pin-in-groove table c_pin(psi) into P (rvsim.fe.pin; docs/model.md section 6)."""
    from ..fe.pin import pin_table

    table = pin_table(r)
    P[L.PIN_FE_STEP] = float(table.psi[1] - table.psi[0])
    P[L.PIN_FE0:L.PIN_FE0 + L.PIN_FE_N] = table.compliance


def _fe_plate_constants(r: Reducer, P: np.ndarray) -> None:
    """The carrier and flange plates' bore table into P (``flexibility.model = fe`` with
    ``flexibility.fe_carrier``, RV reducer; physics._fe_carrier uses it): the parameter set
    does not distinguish the two plates, so one table serves both (docs/decisions.md)."""
    from ..errors import ParameterError
    from ..fe.carrier import carrier_table
    from ..physics._fe_crank import pack_table

    f = r.flexibility
    if f.model != "fe" or not f.fe_carrier or r.layout.single_stage:
        return
    if r.bearings.support_rollers:
        raise ParameterError("flexibility.fe_carrier", "the finite-element carrier takes the "
                             "support bushings only so far, not bearings.support_rollers "
                             "(set flexibility.fe_carrier = false)")
    P[L.FE_PLATE_XX1:L.FE_PLATE_XX1 + 10] = pack_table(carrier_table(r).compliance)


def fe_crank_used(r: Reducer) -> bool:
    """Whether the crankshafts are finite-element bodies (flexibility.fe_crank with model = fe,
    an RV reducer)."""
    return (r.flexibility.model == "fe" and r.flexibility.fe_crank
            and not r.layout.single_stage)


def _fe_crank_constants(r: Reducer) -> np.ndarray:
    """The crank's in-plane table (forces x, y of both eccentrics; rvsim.fe.crank, cached per
    geometry) as the 10 constants of P."""
    from ..errors import ParameterError
    from ..fe.crank import crank_table
    from ..physics._fe_crank import pack_table

    if r.bearings.arm_needles:
        raise ParameterError("flexibility.fe_crank", "the finite-element crank takes the "
                             "paper's arm bushings only (set bearings.arm_needles = false or "
                             "flexibility.fe_crank = false)")
    table = crank_table(r, r.flexibility.fe_crank_element_size).compliance
    forces = [0, 1, 4, 5]                  # force x, y of eccentric 1, then of eccentric 2
    return pack_table(table[np.ix_(forces, forces)])


def _bearing_constants(r: Reducer, P: np.ndarray) -> None:
    """Constants of the arm and support elements: the paper's bushings (conforming contacts,
    docs/model.md "Bearings") or rolling bearings (per-roller Palmgren contacts)."""
    from ..bearings import (arm_play, conforming_constants, roller_pitch_diameter, roller_set,
                            support_play)

    c, k, cl, m, b = r.cycloid, r.crank, r.clearances, r.materials, r.bearings
    factor = r.contact.bushing_stiffness_factor
    floor = b.bushing_min_radial_difference
    P[L.ARM_CLEAR] = arm_play(r)
    P[L.SUP_CLEAR_L] = support_play(r, upper=False)
    P[L.SUP_CLEAR_U] = support_play(r, upper=True)
    if b.arm_needles:
        P[L.ARM_KIND] = 1.0
        needles = roller_set(r, "arm_needles")
        P[L.ARM_ROLLERS] = needles.count
        P[L.ARM_C] = needles.coefficient
        inner = needles.inner_radius
        P[L.ARM_CAGE_IN] = inner / roller_pitch_diameter(inner, needles.diameter)
    else:
        P[L.ARM_J1], P[L.ARM_A1] = conforming_constants(
            c.disc_width, m.crankshaft, m.bushing, max(cl.crank_arm_bushing, floor), factor)
        P[L.ARM_J2], P[L.ARM_A2] = conforming_constants(
            c.disc_width, m.bushing, m.cycloid_disc, max(cl.disc_arm_bushing, floor), factor)
        P[L.ARM_CB] = (ring_compliance(k.arm_bushing_thickness,
                                       k.eccentric_radius + 0.5 * k.arm_bushing_thickness,
                                       c.disc_width, m.bushing)
                       if r.flexibility.arm_bushing else 0.0)
    if b.support_rollers:
        P[L.SUP_KIND] = 1.0
        rollers = roller_set(r, "support_rollers")
        P[L.SUP_ROLLERS] = rollers.count
        P[L.SUP_C] = rollers.coefficient
        inner = rollers.inner_radius
        P[L.SUP_CAGE_IN] = inner / roller_pitch_diameter(inner, rollers.diameter)
        P[L.SUP_COS_ALPHA] = rollers.cos_alpha
    else:
        width = k.support_bushing_width
        P[L.SUP_J1], P[L.SUP_A1] = conforming_constants(
            width, m.crankshaft, m.bushing, max(cl.crank_support_bushing, floor), factor)
        P[L.SUP_J2], P[L.SUP_A2_L] = conforming_constants(
            width, m.bushing, m.carrier, max(cl.support_flange, floor), factor)
        _, P[L.SUP_A2_U] = conforming_constants(
            width, m.bushing, m.carrier, max(cl.support_carrier, floor), factor)


def _single_stage_constants(r: Reducer, P: np.ndarray) -> None:
    """Constants of the single-stage drive (docs/model.md section 13): one eccentric shaft on
    the axis, input on it (the input turns so that the output turns forwards: ratio < 0 with
    the output pins as output, > 0 with the pin ring), input bearings with their clearance,
    output pins in the discs' holes (on the output flange, or fixed to the frame)."""
    from ..geometry.layout import output_hole_clearance

    c, lay, m = r.cycloid, r.layout, r.materials
    P[L.INPUT_SPEED] = math.copysign(r.operating.input_speed, r.ratio)
    P[L.RING_OUTPUT] = 1.0 if lay.ring_output else 0.0
    P[L.CRANK_COUNT] = 1
    P[L.DISC_COUNT] = lay.disc_count
    P[L.CENTRE_DIST] = 0.0
    play = lay.input_bearing_clearance
    if r.bearings.support_rollers:
        play += 0.5 * r.bearings.support_clearance
    else:  # the input bearings' clearance is the second conforming interface's
        from ..bearings import conforming_constants

        _, P[L.SUP_A2_L] = conforming_constants(
            r.crank.support_bushing_width, m.bushing, m.carrier,
            max(lay.input_bearing_clearance, r.bearings.bushing_min_radial_difference),
            r.contact.bushing_stiffness_factor)
        P[L.SUP_A2_U] = P[L.SUP_A2_L]
    P[L.SUP_CLEAR_L] = P[L.SUP_CLEAR_U] = play
    P[L.K_INPUT] = input_stiffness(r)
    P[L.OUT_COUNT] = lay.output_pin_count
    P[L.OUT_RADIUS] = lay.output_pin_circle_radius
    P[L.OUT_CLEAR] = output_hole_clearance(r)
    # an output pin (roller) on the hole wall is a line contact like a ring pin on the profile
    # (same law, material pair and length), not a bushing: the bushing factor leaves it alone
    P[L.OUT_C] = palmgren_coefficient(c.disc_width, m.cycloid_disc, m.pin)
    P[L.OUT_CB] = 0.0
