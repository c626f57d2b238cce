"""Frozen dataclasses describing an RV reducer, in SI units.

Tooth counts fix array shapes; errors, clearances, loads and switches are inputs that a design of
experiments sweeps.  Change a value with :func:`dataclasses.replace` or
:func:`rvsim.parameters.with_values`.  Each field's docstring-like metadata gives the unit users
see (``rvsim params`` lists them all).
"""

from __future__ import annotations

import dataclasses
import math

from .._display import Headline, number
from ._parts import PartErrors
from ._schema import choice, count, flag, quantity

__all__ = [
    "Material", "Materials", "GearStage", "CycloidStage", "Crankshaft", "Errors", "Clearances",
    "Flexibility", "Operating", "ContactModel", "Rating", "Layout", "Friction", "Bearings", "Reducer",
    "PartErrors", "Stiffness",
]

#: ``layout.stages`` of the RV reducer (involute + cycloid stage) and of the single-stage drive
RV_STAGES = 2
SINGLE_STAGE = 1

_MM = 1e-3
_DEG = math.pi / 180.0
_RPM = 2.0 * math.pi / 60.0


def _material(name: str, e_gpa: float, density: float, poisson: float):
    return dataclasses.field(default_factory=lambda: Material(name, e_gpa * 1e9, density, poisson))


@dataclasses.dataclass(frozen=True)
class Material:
    """An isotropic linear-elastic material."""

    name: str = "steel"
    elastic_modulus: float = quantity(2.07e11, "GPa", "Young's modulus", positive=True)
    density: float = quantity(7850.0, "kg/m^3", "mass density", positive=True)
    poisson_ratio: float = quantity(0.3, "-", "Poisson's ratio", maximum=0.5)


@dataclasses.dataclass(frozen=True)
class Materials:
    """Materials of the parts the model uses (paper Table 5; bushings assumed).

    Table 5 also lists the input shaft, the pin housing and the flange: the model has no use for
    them (the input shaft's motion is prescribed, the housing is rigid and fixed, and the flange
    is bolted to the carrier, one body of the carrier's material), so they are not parameters.
    """

    planet_gear: Material = _material("38CrMoAl", 211.0, 7850.0, 0.277)
    carrier: Material = _material("ZG65Mn", 198.0, 7850.0, 0.230)
    cycloid_disc: Material = _material("20CrMnMo", 207.0, 7870.0, 0.254)
    crankshaft: Material = _material("20CrMnMo", 207.0, 7870.0, 0.254)
    pin: Material = _material("QT500-7", 168.0, 7250.0, 0.240)
    bushing: Material = _material("GCr15", 219.0, 7830.0, 0.300)


@dataclasses.dataclass(frozen=True)
class GearStage:
    """First (involute sun-planet) stage (paper Table 4, stage I)."""

    module: float = quantity(1.25 * _MM, "mm", "normal module", positive=True)
    sun_teeth: int = count(18, "sun gear teeth z1", minimum=6)
    planet_teeth: int = count(54, "planet gear teeth z2 (one planet per crankshaft)", minimum=6)
    planet_count: int = count(2, "planet gears = crankshafts (fixed at 2 in the dynamic model)",
                              minimum=2)
    face_width: float = quantity(7.0 * _MM, "mm", "tooth width", positive=True)
    pressure_angle: float = quantity(20.0 * _DEG, "deg", "standard pressure angle", positive=True,
                                     maximum=35.0 * _DEG)
    sun_profile_shift: float = quantity(0.469, "-", "sun profile shift coefficient x1",
                                        minimum=-1.0, maximum=1.5)
    planet_profile_shift: float = quantity(-0.505, "-", "planet profile shift coefficient x2",
                                           minimum=-1.0, maximum=1.5)
    backlash: float = quantity(0.0, "mm", "normal backlash of each sun-planet mesh "
                               "(paper's ADAMS gear pair: none)")


@dataclasses.dataclass(frozen=True)
class CycloidStage:
    """Second (cycloid-pin) stage (paper Table 4, stage II) and its assumed part sizes."""

    eccentricity: float = quantity(1.5 * _MM, "mm", "crank eccentricity a", positive=True)
    disc_teeth: int = count(39, "cycloid disc teeth zc", minimum=3)
    pin_count: int = count(40, "pins zp (must be zc + 1)", minimum=4)
    disc_width: float = quantity(15.0 * _MM, "mm", "cycloid disc width (contact length)",
                                 positive=True)
    pin_radius: float = quantity(3.0 * _MM, "mm", "pin radius r_rp", positive=True)
    pin_circle_radius: float = quantity(82.0 * _MM, "mm", "pin centre circle radius r_p",
                                        positive=True)
    disc_bore_radius: float = quantity(20.0 * _MM, "mm",
                                       "central bore of the disc (assumed, docs/model.md)",
                                       positive=True)
    pillar_hole_count: int = count(2, "carrier pillar holes through the disc (assumed)",
                                   minimum=0)
    pillar_hole_radius: float = quantity(11.0 * _MM, "mm", "pillar hole radius (assumed)")
    carrier_radius: float = quantity(80.0 * _MM, "mm",
                                     "outer radius of carrier + flange (assumed)", positive=True)
    carrier_thickness: float = quantity(30.0 * _MM, "mm",
                                        "axial thickness of carrier + flange (assumed)",
                                        positive=True)


@dataclasses.dataclass(frozen=True)
class Crankshaft:
    """Crankshaft, its bushings and their axial stations (assumed; docs/model.md).

    Axial positions ``z`` are measured from the lower (flange-side) support.
    """

    eccentric_radius: float = quantity(12.5 * _MM, "mm",
                                       "eccentric journal radius (inside the arm bushing)",
                                       positive=True)
    journal_radius: float = quantity(10.0 * _MM, "mm",
                                     "support journal radius (inside the support bushing)",
                                     positive=True)
    arm_bushing_thickness: float = quantity(3.0 * _MM, "mm", "arm bushing ring wall",
                                            positive=True)
    support_bushing_width: float = quantity(10.0 * _MM, "mm", "support bushing length",
                                            positive=True)
    lower_support_z: float = quantity(0.0, "mm", "axial station of the lower (flange) support",
                                      minimum=None)
    disc1_z: float = quantity(13.0 * _MM, "mm", "axial station of disc 1", minimum=None)
    disc2_z: float = quantity(29.0 * _MM, "mm", "axial station of disc 2", minimum=None)
    upper_support_z: float = quantity(42.0 * _MM, "mm",
                                      "axial station of the upper (carrier) support",
                                      minimum=None)
    gear_z: float = quantity(52.0 * _MM, "mm", "axial station of the planet gear", minimum=None)


@dataclasses.dataclass(frozen=True)
class Errors:
    """Manufacturing errors and profile modifications (paper Table 2 F-J).

    Positive F, H, I and J open clearance at every pin (paper Sec. 3.2); negative values are
    the opposite deviation (bigger pin, smaller pin circle, negative equidistant or
    radial-moving modification), which closes it.  Industry combines signs, e.g. a negative
    equidistant with a larger positive radial-moving modification that nearly cancel on the
    working flank.  G, the rotation modification, runout and pin position errors close
    clearance somewhere.  The assembly interference check (rvsim.geometry.assembly) decides
    whether a combination can be assembled (docs/model.md section 2).
    """

    pin_radius: float = quantity(0.0, "mm", "F: pin radius made smaller by this "
                                  "(negative: larger)", minimum=None)
    eccentricity: float = quantity(0.0, "mm", "G: crank eccentricity made smaller by this")
    pin_circle_radius: float = quantity(0.0, "mm", "H: pin centre circle radius made "
                                        "larger by this (negative: smaller)", minimum=None)
    equidistant_modification: float = quantity(0.0, "mm",
                                               "I: cycloid equidistant modification "
                                               "(profile offset by r_rp + this; negative: "
                                               "fuller teeth)", minimum=None)
    radial_modification: float = quantity(0.0, "mm",
                                          "J: cycloid radial-moving modification "
                                          "(generating circle r_p - this; negative: "
                                          "moved outwards)", minimum=None)
    rotation_modification: float = quantity(0.0, "arcmin",
                                            "cycloid rotation modification (profile turned, "
                                            "beyond the paper)", minimum=None)
    disc_runout: float = quantity(0.0, "mm", "radial runout of the disc profile relative to "
                                  "its crank holes (Table 1 Delta F_t1; profile centre offset "
                                  "by half of it)")
    disc_runout_phase: float = quantity(0.0, "deg", "direction of the disc runout: the profile "
                                        "centre's offset turned by this from the disc's x "
                                        "axis (disc 2 half a turn on)", minimum=None)
    pin_position_tolerance: float = quantity(0.0, "mm", "each pin centre displaced radially "
                                             "and along the circle by uniform random amounts "
                                             "within +-this (Table 1 delta t_Sigma)")
    pin_position_seed: int = count(0, "seed of the random pin position errors", minimum=0)
    pin_hole_clearance: float = quantity(0.0, "mm", "diametral clearance of each pin in its "
                                         "housing hole (Table 1 row 4): a loaded pin moves "
                                         "back by half of it")


@dataclasses.dataclass(frozen=True)
class Clearances:
    """Radial clearances of the bushings that replace the bearings (paper Table 2 K-O)."""

    crank_arm_bushing: float = quantity(0.0, "mm", "K: crankshaft eccentric to arm bushing")
    support_flange: float = quantity(0.0, "mm", "L: lower support bushing to flange")
    disc_arm_bushing: float = quantity(0.0, "mm", "M: cycloid crank hole to arm bushing")
    support_carrier: float = quantity(0.0, "mm", "N: upper support bushing to carrier")
    crank_support_bushing: float = quantity(0.0, "mm", "O: crankshaft to support bushings")


@dataclasses.dataclass(frozen=True)
class Flexibility:
    """Which parts add their own elastic compliance (paper Table 2 A-C)."""

    cycloid_disc: bool = flag(False, "A: cycloid disc flexible")
    pin: bool = flag(False, "B: pins flexible")
    arm_bushing: bool = flag(False, "C: arm bushing flexible")
    model: str = choice("closed-form", ("closed-form", "fe"),
                        "how the flexible parts deform: closed-form series compliances, or "
                        "the disc (A) and the pins in their grooves (B) from finite elements "
                        "(rvsim.fe; cached per geometry)")
    fe_element_size: float = quantity(1.6 * _MM, "mm", "finite-element size along the disc "
                                      "profile and holes (the inside grows to 4x)",
                                      positive=True)
    fe_segments_per_tooth: int = count(8, "contact segments per disc tooth onto which the "
                                       "finite-element disc is condensed", minimum=2,
                                       maximum=64)
    fe_modes: int = count(0, "modes of the finite-element disc (held at its crank holes) "
                          "that the dynamic engine integrates; 0: massless condensed disc "
                          "(the quasi-static engine is static: modes do not change it)",
                          minimum=0, maximum=100)
    fe_disc_holes: bool = flag(False, "with model = fe and A: the disc's two crank holes are "
                               "load points of its finite-element table (the arm bushings "
                               "stretch the web between them) instead of held edges: the "
                               "soft bound of the hole region, as held edges are the stiff "
                               "one (docs/decisions.md)")
    fe_carrier: bool = flag(True, "with model = fe: the carrier and the flange are "
                            "finite-element plates on which the crank support bushings bear "
                            "(RV reducer; no effect with closed-form)")
    fe_crank: bool = flag(True, "with model = fe: the crankshafts are finite-element bodies "
                          "too (their eccentrics deflect under both discs' arm-bushing "
                          "forces; RV reducers with the paper's arm bushings)")
    fe_crank_element_size: float = quantity(3.0 * _MM, "mm", "element size of the "
                                            "finite-element crankshaft (3-D)", positive=True)


@dataclasses.dataclass(frozen=True)
class Operating:
    """Input motion (Eq. 19), output load (Eqs. 20/21) and simulated time (Sec. 3.3)."""

    input_speed: float = quantity(7000.0 * _DEG, "deg/s", "steady input speed", positive=True)
    speed_ramp_time: float = quantity(1.0, "s", "input speed STEP ramp 0 -> steady",
                                      positive=True)
    load_torque: float = quantity(300.0, "N*m", "E: output load torque X")
    load_start: float = quantity(1.0, "s", "load STEP starts")
    load_ramp_end: float = quantity(1.5, "s", "load STEP ends", positive=True)
    load_fluctuation: bool = flag(False, "D: add fluctuation amplitude * sin(2 pi f t)")
    fluctuation_amplitude: float = quantity(41.2, "N*m", "fluctuation amplitude")
    fluctuation_frequency: float = quantity(20.0, "Hz", "fluctuation frequency")
    load_inertia: float = quantity(0.3, "kg*m^2", "moment of inertia of the driven load "
                                   "turning with the carrier (test rig: brake rotor, couplings, "
                                   "torque sensor; docs/model.md)")
    duration: float = quantity(4.0, "s", "simulated time", positive=True)
    steady_start: float = quantity(1.5, "s", "start of the steady window for TE metrics")
    temperature: float = quantity(40.0, "degC", "operating temperature of the lubricant "
                                  "(sets its viscosity through friction.oil_viscosity_100; "
                                  "40: friction.oil_viscosity as given)", minimum=-273.15,
                                  positive=True)


@dataclasses.dataclass(frozen=True)
class ContactModel:
    """Contact law settings shared by all contacts (docs/model.md gives the sources)."""

    damping_ratio: float = quantity(0.05, "-", "viscous damping of each contact as a fraction "
                                    "of critical at its current stiffness", maximum=2.0)
    friction_coefficient: float = quantity(0.0, "-", "Coulomb friction at pin contacts "
                                           "(paper: none)", maximum=1.0)
    bushing_stiffness_factor: float = quantity(1.0, "-", "multiplies the stiffness of every "
                                               "bushing contact (1: the conforming law; "
                                               "large: rigid bearings)", positive=True)
    friction_velocity: float = quantity(1e-3, "mm/s", "sliding speed at which the "
                                        "regularised friction is fully developed", positive=True)


@dataclasses.dataclass(frozen=True)
class Rating:
    """Catalogue ratings of the reducer."""

    rated_torque: float = quantity(412.0, "N*m", "rated output torque (RV-40E: 412 N*m; the "
                                   "paper's 41.2 N*m fluctuation is 10 % of it)", positive=True)
    start_stop_torque: float = quantity(1029.0, "N*m", "allowable output torque at start "
                                        "and stop (acceleration/deceleration; RV-40E class: "
                                        "1029 N*m)", positive=True)
    momentary_torque: float = quantity(2058.0, "N*m", "momentary maximum output torque "
                                       "(emergency stop; RV-40E class: 2058 N*m): larger "
                                       "loads are refused", positive=True)
    rated_output_speed: float = quantity(15.0 * _RPM, "rpm", "rated output "
                                         "speed N0, at which the rated torque gives the rated "
                                         "life (RV-E class: 15 rpm)", positive=True)
    rated_life: float = quantity(6000.0 * 3600.0, "h", "rated service life K at the rated "
                                 "torque and rated output speed (RV-E class: 6000 h)",
                                 positive=True)
    allowable_output_speed: float = quantity(70.0 * _RPM, "rpm", "allowable output speed "
                                             "at 100 % duty (RV-40E class: 70 rpm): faster "
                                             "output speeds are refused by 'life' and "
                                             "warned of elsewhere", positive=True)
    static_contact_stress: float = quantity(4000e6, "MPa", "static limit of the largest "
                                            "Hertz contact stress of hardened bearing steel "
                                            "in line contact (ISO 76: 4000 MPa at roller "
                                            "bearings' C0; 4200 ball, 4600 self-aligning "
                                            "ball): above it permanent deformation is "
                                            "expected (warned, not refused)", positive=True)


@dataclasses.dataclass(frozen=True)
class Layout:
    """Topology of the drive (docs/model.md section 13, docs/decisions.md).

    ``stages`` = 2: the RV reducer (involute stage, two crankshafts; the other fields here are
    ignored).  ``stages`` = 1: the single-stage cycloid drive: the input shaft is the eccentric
    shaft on the housing axis, the output flange carries output pins (rollers) that run in
    holes of the discs; the involute stage (``gears.*``) and the RV's crank axial station
    ``crank.gear_z`` are ignored, and the support clearances L, N, O are replaced by
    ``layout.input_bearing_clearance``.  With ``ring_output`` the output pins are fixed to the
    frame (the discs only wobble) and the pin ring turns as the output.
    """

    stages: int = count(2, "2: RV reducer (involute + cycloid stage); 1: single-stage "
                        "cycloid drive with output pins", minimum=1)
    disc_count: int = count(2, "cycloid discs (single-stage: 1, or 2 at 180 deg; the RV "
                            "model has 2)", minimum=1)
    output_pin_count: int = count(8, "single-stage: output pins (rollers) on the output "
                                  "flange", minimum=3)
    output_pin_radius: float = quantity(5.0 * _MM, "mm", "single-stage: output pin (roller) "
                                        "outer radius r_w", positive=True)
    output_pin_circle_radius: float = quantity(36.0 * _MM, "mm", "single-stage: output pin "
                                               "centre circle radius R_w", positive=True)
    output_pin_clearance: float = quantity(0.0, "mm", "single-stage: radial clearance of "
                                           "each output pin in its disc hole (hole radius = "
                                           "r_w + a + this)")
    input_bearing_clearance: float = quantity(0.0, "mm", "single-stage: radial clearance of "
                                              "the input (eccentric) shaft's two bearings "
                                              "in the housing")
    ring_output: bool = flag(False, "single-stage: the pin ring (housing) is the output and "
                             "the output pins are fixed to the frame, holding the discs "
                             "against rotation (ratio +zp / (zp - zc)); off: output through "
                             "the pins (ratio -zc / (zp - zc))")

    @property
    def single_stage(self) -> bool:
        return self.stages == SINGLE_STAGE


@dataclasses.dataclass(frozen=True)
class Friction:
    """Friction beyond the pin-disc sliding coefficient ``contact.friction_coefficient``
    (docs/model.md section 15 gives every law and its source; all zero: the paper's
    frictionless model).  rvsim.friction.TYPICAL_FRICTION lists values for a greased reducer."""

    pins_turn: bool = flag(False, "pins free to turn in their housing grooves: the pin rolls "
                           "on the disc and slides in its groove (else it slides on the disc)")
    pin_groove_coefficient: float = quantity(0.0, "-", "Coulomb friction of a pin turning in "
                                             "its housing groove (with pins_turn)", maximum=1.0)
    pin_rolling_coefficient: float = quantity(0.0, "-", "rolling resistance of a pin on the "
                                              "disc, as a fraction of the normal force (with "
                                              "pins_turn)", maximum=0.1)
    mesh_coefficient: float = quantity(0.0, "-", "mean Coulomb friction coefficient of the "
                                       "sun-planet tooth flanks", maximum=1.0)
    oil_viscosity: float = quantity(100.0 * (_MM * _MM), "mm^2/s", "kinematic viscosity of "
                                    "the lubricant (grease: its base oil) at 40 degC, the "
                                    "operating temperature's default (without "
                                    "oil_viscosity_100: the viscosity used)", positive=True)
    oil_viscosity_100: float = quantity(0.0, "mm^2/s", "kinematic viscosity of the lubricant "
                                        "at 100 degC: with oil_viscosity, the viscosity-"
                                        "temperature law (ASTM D341) that gives the viscosity "
                                        "at operating.temperature (0: no law)")
    oil_cloud_point: float = quantity(-20.0, "degC", "lowest temperature of the viscosity-"
                                      "temperature law (ASTM D341: from the lubricant's cloud "
                                      "point up)", minimum=-273.15, positive=True)
    oil_max_temperature: float = quantity(150.0, "degC", "highest temperature of the "
                                          "lubricant (mineral base oils degrade from 110-150 "
                                          "degC): a hotter operating.temperature is refused",
                                          minimum=-273.15, positive=True)
    input_seal_count: int = count(0, "radial lip seals on the input shaft", minimum=0)
    input_seal_diameter: float = quantity(0.0, "mm", "shaft diameter at the input seals' lips "
                                          "(ISO/TR 14179-2 drag)")
    output_seal_count: int = count(0, "radial lip seals on the output (carrier in the "
                                   "housing)", minimum=0)
    output_seal_diameter: float = quantity(0.0, "mm", "diameter at the output seals' lips "
                                           "(ISO/TR 14179-2 drag)")
    arm_bearing_f0: float = quantity(0.0, "-", "Palmgren f0 (speed-dependent, viscous torque) "
                                     "of each turning-arm bearing (eccentric in its disc hole)")
    arm_bearing_f1: float = quantity(0.0, "-", "Palmgren f1 (load-dependent torque) of each "
                                     "turning-arm bearing", maximum=0.1)
    arm_bearing_diameter: float = quantity(0.0, "mm", "mean (pitch) diameter dm of a turning-"
                                           "arm bearing (0: eccentric diameter + arm bushing "
                                           "wall)")
    support_bearing_f0: float = quantity(0.0, "-", "Palmgren f0 of each crank support bearing "
                                         "(journal in the carrier / flange)")
    support_bearing_f1: float = quantity(0.0, "-", "Palmgren f1 of each crank support bearing",
                                         maximum=0.1)
    support_bearing_diameter: float = quantity(0.0, "mm", "mean (pitch) diameter dm of a "
                                               "support bearing (0: journal diameter + arm "
                                               "bushing wall)")


@dataclasses.dataclass(frozen=True)
class Bearings:
    """Crank bearings (docs/model.md "Bearings"; sizes of RV-40E-bearings: docs/parameters.md).

    The paper replaces every bearing by a bushing (the default); a switch per location puts
    rolling bearings there instead.  The paper's clearances K-O (``clearances.*``) add their
    radial play to either element; a rolling bearing's own radial internal clearance
    (diametral, ISO 5753) adds half of itself.  The main bearings (carrier in the housing)
    are not in the planar kernel: their stiffness is reported (rvsim.bearings,
    docs/decisions.md).
    """

    arm_needles: bool = flag(False, "needle roller bearings at the crank eccentrics "
                             "(false: the paper's arm bushings)")
    support_rollers: bool = flag(False, "tapered roller bearings at the crank supports "
                                 "(false: the paper's support bushings)")
    bushing_min_radial_difference: float = quantity(0.005 * _MM, "mm", "smallest radial "
                                                    "difference of a bushing's conforming "
                                                    "surfaces used by the contact law (a "
                                                    "smaller clearance is conforming to this): "
                                                    "the two surfaces' summed roughness Rz",
                                                    positive=True)
    needle_count: int = count(20, "needle rollers per eccentric", minimum=3)
    needle_diameter: float = quantity(3.0 * _MM, "mm", "needle roller diameter", positive=True)
    needle_length: float = quantity(12.0 * _MM, "mm", "needle effective contact length",
                                    positive=True)
    needle_clearance: float = quantity(0.0, "mm", "radial internal clearance of a needle "
                                       "bearing (diametral; negative: preload)", minimum=None)
    support_roller_count: int = count(15, "rollers per tapered support bearing", minimum=3)
    support_roller_diameter: float = quantity(5.0 * _MM, "mm", "tapered roller mean diameter",
                                              positive=True)
    support_roller_length: float = quantity(8.0 * _MM, "mm", "tapered roller effective "
                                            "length", positive=True)
    support_contact_angle: float = quantity(15.0 * _DEG, "deg", "contact angle of the tapered "
                                            "rollers (cup angle)", maximum=45.0 * _DEG)
    support_clearance: float = quantity(0.0, "mm", "radial internal clearance of a support "
                                        "bearing (diametral; negative: preload)", minimum=None)
    main_ball_count: int = count(30, "balls per main bearing (angular contact, carrier in "
                                 "the housing; reported only)", minimum=3)
    main_ball_diameter: float = quantity(9.0 * _MM, "mm", "main bearing ball diameter",
                                         positive=True)
    main_pitch_diameter: float = quantity(140.0 * _MM, "mm", "main bearing ball pitch "
                                          "diameter", positive=True)
    main_contact_angle: float = quantity(40.0 * _DEG, "deg", "main bearing contact angle",
                                         maximum=80.0 * _DEG)
    main_span: float = quantity(60.0 * _MM, "mm", "axial distance between the two main "
                                "bearings' load centres", positive=True)
    main_preload: float = quantity(2.0 * _MM * 1e-3, "mm", "axial preload deflection of "
                                   "each main bearing (contact approach at zero load)")


@dataclasses.dataclass(frozen=True)
class Stiffness:
    """Stiffness scalings of the compliance budget's element groups (issue 33 item 5).

    Each factor s makes every force law of its group give s times its force at every approach,
    the budget's stiffening (rvsim.physics.stiffening, docs/model.md section 12) applied by
    every engine; 1 is the model as built.  The names are those of
    ``rvsim hysteresis --budget`` (tests/unit/test_stiffness_scaling.py keeps them equal); a
    factor other than 1 for a group the model does not have is refused.  What a calibration
    to a bench's torque-reversal curve fits (docs/user_guide.md section 9).
    """

    gear_mesh: float = quantity(1.0, "-", "scales the sun-planet mesh stiffness (first stage)",
                                positive=True)
    input_coupling: float = quantity(1.0, "-", "single-stage: scales the input coupling "
                                     "(input shaft - eccentric shaft)", positive=True)
    arm_bearings: float = quantity(1.0, "-", "scales the force laws of the arm bearings "
                                   "(bushings or needle rollers; single-stage: the discs' "
                                   "bearings on the eccentric)", positive=True)
    pins: float = quantity(1.0, "-", "scales the pin - disc contacts with the pin and tooth "
                           "bodies", positive=True)
    fe_disc: float = quantity(1.0, "-", "with model = fe and A: scales the finite-element "
                              "discs' stiffness", positive=True)
    fe_crank: float = quantity(1.0, "-", "with model = fe: scales the finite-element "
                               "crankshafts' stiffness", positive=True)
    support_bearings: float = quantity(1.0, "-", "scales the force laws of the crank support "
                                       "bearings (bushings or tapered rollers)", positive=True)
    fe_carrier: float = quantity(1.0, "-", "with model = fe: scales the finite-element carrier "
                                 "and flange", positive=True)
    output_pins: float = quantity(1.0, "-", "single-stage: scales the output pins in the "
                                  "discs' holes", positive=True)


@dataclasses.dataclass(frozen=True, repr=False)
class Reducer(Headline):
    """A complete RV reducer: geometry, materials, errors and operating point.

    Shown as its name and main dimensions in mm (:meth:`headline`); every value with
    ``rvsim.parameters.parameter_table(reducer)`` or ``rvsim params``."""

    name: str = "RV-40E"
    citation: str = ""
    gears: GearStage = dataclasses.field(default_factory=GearStage)
    cycloid: CycloidStage = dataclasses.field(default_factory=CycloidStage)
    crank: Crankshaft = dataclasses.field(default_factory=Crankshaft)
    materials: Materials = dataclasses.field(default_factory=Materials)
    errors: Errors = dataclasses.field(default_factory=Errors)
    clearances: Clearances = dataclasses.field(default_factory=Clearances)
    flexibility: Flexibility = dataclasses.field(default_factory=Flexibility)
    operating: Operating = dataclasses.field(default_factory=Operating)
    contact: ContactModel = dataclasses.field(default_factory=ContactModel)
    rating: Rating = dataclasses.field(default_factory=Rating)
    layout: Layout = dataclasses.field(default_factory=Layout)
    friction: Friction = dataclasses.field(default_factory=Friction)
    bearings: Bearings = dataclasses.field(default_factory=Bearings)
    stiffness: Stiffness = dataclasses.field(default_factory=Stiffness)
    #: per-part errors (issue 11; not in TOML / --set: a tolerance study draws them)
    parts: PartErrors = dataclasses.field(default_factory=PartErrors)

    @property
    def ratio(self) -> float:
        """Ideal signed speed ratio input angle / output angle (fixed housing).

        RV reducer: i = 1 + (z2/z1) * zp (carrier output, same sense as the input).  Single-stage
        drive with output pins: i = -zc / (zp - zc), negative because the output turns against
        the eccentric shaft; with the pin ring as output (``layout.ring_output``, the output
        pins fixed): i = +zp / (zp - zc); the transmission error theta_in / i - theta_out
        then has the same sign convention in all (positive: the output lags behind its ideal
        angle in its direction of motion; docs/model.md section 13).
        """
        if self.layout.single_stage:
            c = self.cycloid
            if self.layout.ring_output:
                return c.pin_count / (c.pin_count - c.disc_teeth)
            return -c.disc_teeth / (c.pin_count - c.disc_teeth)
        g = self.gears
        return 1.0 + g.planet_teeth / g.sun_teeth * self.cycloid.pin_count

    def headline(self) -> tuple[str, list[tuple[str, str]]]:
        """Name, drive, main dimensions [mm], rating and operating point (its repr)."""
        c, g, r, o = self.cycloid, self.gears, self.rating, self.operating
        rpm = 60.0 / (2.0 * math.pi)
        kind = ("single-stage cycloid drive" if self.layout.single_stage else "RV reducer")
        rows = [("cycloid stage", f"{c.pin_count} pins r {number(c.pin_radius * 1e3, 'mm')} "
                 f"on r {number(c.pin_circle_radius * 1e3, 'mm')}, {c.disc_teeth} teeth, "
                 f"eccentricity {number(c.eccentricity * 1e3, 'mm')}, width "
                 f"{number(c.disc_width * 1e3, 'mm')}, {self.layout.disc_count} discs")]
        if not self.layout.single_stage:
            rows.append(("gear stage", f"{g.sun_teeth}/{g.planet_teeth} teeth, module "
                         f"{number(g.module * 1e3, 'mm')}, {g.planet_count} planets"))
        rows += [("rating", f"{number(r.rated_torque, 'N*m')} rated, "
                  f"{number(r.momentary_torque, 'N*m')} momentary, at "
                  f"{number(r.rated_output_speed * rpm, 'rpm')} output"),
                 ("operating", f"{number(o.input_speed * rpm, 'rpm')} input, "
                  f"{number(o.load_torque, 'N*m')} load"),
                 ("flexibility", f"{self.flexibility.model}"
                  f"{'' if self.layout.single_stage else ', ' + self._bearing_kinds()}")]
        return f"Reducer {self.name!r}: {kind}, ratio {self.ratio:.6g}", rows

    def _bearing_kinds(self) -> str:
        b = self.bearings
        return (f"{'needle' if b.arm_needles else 'bushing'} arm bearings, "
                f"{'tapered roller' if b.support_rollers else 'bushing'} supports")

    @property
    def curtate_ratio(self) -> float:
        """K1 = a * zp / r_p of the design profile."""
        c = self.cycloid
        return c.eccentricity * c.pin_count / c.pin_circle_radius
