"""Index layout of the arrays passed to the compiled kernel (no objects cross that boundary).

``P`` is one float64 vector of model constants, ``q``/``v`` the generalised coordinates and
velocities.  Symbols map to docs/model.md.
"""

from __future__ import annotations

# ---- generalised coordinates (all in the fixed housing frame) ------------------------------
CARRIER = 0                 # carrier / output rotation theta_c
CRANK0 = 1                  # crank j: CRANK0 + 5 j + (x_lower, y_lower, x_upper, y_upper, phi)
CRANK_STRIDE = 5
DISC0 = 11                  # disc k: DISC0 + 3 k + (x, y, theta)
DISC_STRIDE = 3
N_DOF = 17
#: columns of the kernel's ``arm_elastic`` array: arm_elastic[crank, disc] the arm bushing's
#: elastic force, arm_elastic[crank, SUP_SLOT0 + upper] the support bushing's (Newton starts),
#: arm_elastic[crank, FE_CRANK_SLOT0 + 2 disc + (0, 1)] the arm bushing's elastic force vector
#: (x, y, housing frame) with a finite-element crank (rvsim.physics._fe_crank),
#: arm_elastic[crank, PLATE_SLOT0 + 2 upper + (0, 1)] the support force vector on a
#: finite-element carrier / flange (rvsim.physics._fe_carrier),
#: arm_elastic[disc, HOLE_SLOT0 + (0 .. HOLE_COLUMNS - 1)] the FE disc's crank-hole state
#: (rvsim.physics._fe_holes: Q, Q summed, stretch and the quasi-static engine's derivatives
#: and predictor),
#: arm_elastic[crank, BUSH_SLOT0 + BUSH_COLUMNS b + (0 .. 4)] what conforming bushing b (0, 1:
#: the arm bushings of discs 0 and 1; 2, 3: the lower and upper supports) carries to its next
#: step's Newton start (the elastic force it belongs to, the approach, the stiffness,
#: ln(a1 / F) and the calls since that was computed afresh;
#: rvsim.physics._bearings.conforming_force_from),
#: arm_elastic[disc, OUT_SLOT0 + m] output pin m's in disc ``disc`` (single-stage drive)
SUP_SLOT0 = 2
FE_CRANK_SLOT0 = 4
PLATE_SLOT0 = 8
HOLE_SLOT0 = 12
HOLE_COLUMNS = 9 + N_DOF
BUSH_SLOT0 = HOLE_SLOT0 + HOLE_COLUMNS
BUSH_COLUMNS = 5
OUT_SLOT0 = BUSH_SLOT0 + 4 * BUSH_COLUMNS
N_CRANKS = 2
N_DISCS = 2

_BEFORE_P = set(globals()) | {"_BEFORE_P"}

# ---- constants vector P (model.build_model fills it; docs/model.md gives the meaning) ------
DT             = 0
INPUT_SPEED    = 1
RAMP_TIME      = 2
LOAD           = 3
LOAD_T0        = 4
LOAD_T1        = 5
FLUCT_AMP      = 6
FLUCT_FREQ     = 7
RB1            = 8
RB2            = 9
CENTRE_DIST    = 10
SIN_AW         = 11
BACKLASH       = 12
BASE_PITCH     = 13
CONTACT_RATIO  = 14
K_MESH         = 15
MESH_MASS      = 16
RG             = 17
A_GEN          = 18
ZP             = 19
ZC             = 20
PROFILE_OFFSET = 21
PIN_RADIUS     = 22
ECC            = 23
PROFILE_ROT    = 24
PIN_C          = 25
PIN_CB         = 26
ARM_C          = 27
ARM_CB         = 28
ARM_CLEAR      = 29
SUP_C          = 30
SUP_CB         = 31
SUP_CLEAR_L    = 32
SUP_CLEAR_U    = 33
ZETA           = 34
MU             = 35
V_FRIC         = 36
J_CARRIER      = 37
M_DISC         = 38
J_DISC         = 39
J_CRANK        = 40
MINV_LL        = 41
MINV_LU        = 42
MINV_UU        = 43
M_NODE         = 44
W_D1_L         = 45
W_D1_U         = 46
W_D2_L         = 47
W_D2_U         = 48
W_G_L          = 49
W_G_U          = 50
PEN_LIMIT      = 51
STEADY_START   = 52
RUNOUT_X0      = 53
RUNOUT_Y0      = 54
RUNOUT_X1      = 55
RUNOUT_Y1      = 56
# topology (docs/model.md section 13): RV reducer or single-stage drive
STAGES         = 57        # 2: RV reducer; 1: single-stage drive (eccentric shaft = input)
CRANK_COUNT    = 58        # cranks that carry forces (RV: 2; single-stage: 1, on the axis)
DISC_COUNT     = 59        # discs that carry forces (RV: 2; single-stage: 1 or 2)
K_INPUT        = 60        # single-stage: torsional stiffness input coupling - eccentric shaft
OUT_COUNT      = 61        # single-stage: output pins on the flange (RV: 0)
OUT_RADIUS     = 62        # output pin centre circle radius R_w
OUT_CLEAR      = 63        # hole radius - pin radius = design a + clearance
OUT_C          = 64        # Palmgren coefficient of an output pin in its hole
OUT_CB         = 65        # linear compliance in series (none so far)
# Index blocks reserved for work in progress, so that parallel additions merge cleanly: add
# constants inside your block only (PARAM_NAMES is built from the names defined here).
# ---- bearings (rolling bearings, conforming bushings): 66-85 ----------------------------
# ARM_CLEAR / SUP_CLEAR_L / SUP_CLEAR_U hold the radial play of either element (rolling: half
# the radial internal clearance plus the K-O play, negative: preload); ARM_C / SUP_C the
# Palmgren coefficient of one roller on both raceways (rolling bearings only); ARM_CB the
# bushing ring's compliance (factor C; bushings only)
ARM_KIND       = 66        # 0: conforming bushing (paper); 1: needle roller bearing
SUP_KIND       = 67        # 0: conforming bushing (paper); 1: tapered roller bearing
ARM_J1         = 68        # conforming interface crank - bushing: 1 / (pi L E*)
ARM_A1         = 69        # ... and 4 pi L E* dR
ARM_J2         = 70        # conforming interface bushing - disc hole
ARM_A2         = 71
SUP_J1         = 72        # conforming interface journal - support bushing
SUP_A1         = 73
SUP_J2         = 74        # conforming interface support bushing - flange / carrier bore
SUP_A2_L       = 75        # lower (flange) support
SUP_A2_U       = 76        # upper (carrier) support
ARM_ROLLERS    = 77        # needle rollers per eccentric
ARM_CAGE_IN    = 78        # cage angle = w phi_inner + (1 - w) theta_outer, w = r_i / (r_i + r_o)
SUP_ROLLERS    = 79        # rollers per support bearing
SUP_CAGE_IN    = 80
SUP_COS_ALPHA  = 81        # cosine of the tapered rollers' contact angle
ARM_SHIFT      = 82        # ln(ARM_A2 / ARM_A1) of the arm bushing (0 without one) ...
SUP_SHIFT_L    = 83        # ... ln(SUP_A2_L / SUP_A1) of the lower support bushing ...
SUP_SHIFT_U    = 84        # ... and ln(SUP_A2_U / SUP_A1) of the upper one


# ---- friction and efficiency: 86-99 ------------------------------------------------------
# (docs/model.md section 15; the pin-disc coefficient stays in MU: model.build_model sets it to
# the effective tangential coefficient of the pin contact)
MESH_LOSS      = 86        # mu_m H_V: mesh friction coefficient x Ohlendorf's gear loss factor
NU_OIL         = 87        # lubricant kinematic viscosity [m^2/s]
ARM_F0         = 88        # Palmgren f0, f1 and mean diameter dm [m] of a turning-arm bearing
ARM_F1         = 89
ARM_DM         = 90
SUP_F0         = 91        # ... of a crank support bearing
SUP_F1         = 92
SUP_DM         = 93
FRICTION_ON    = 94        # 1: some bearing, mesh or seal friction to evaluate (0: skip the calls)
SEAL_IN        = 95        # drag torque of the input shaft's lip seals [N*m] (ISO/TR 14179-2) ...
SEAL_IN_R      = 96        # ... and their lip radius [m] (regularisation speed)
SEAL_OUT       = 97        # drag torque of the output's lip seals [N*m] ...
SEAL_OUT_R     = 98        # ... and their lip radius [m]


# ---- per-part manufacturing errors (tolerances): 100-119 ---------------------------------
# (rvsim.geometry.deviations; per-pin and per-tooth errors travel in the ``pins`` array,
# per-disc crank-hole offsets in ``holes`` columns 2-5)
ECC_ERR0       = 100       # eccentric of crank j for disc k larger by P[ECC_ERR0 + 2 j + k]
ECC_PHASE0     = 104       # ... and turned forwards by P[ECC_PHASE0 + 2 j + k] [rad]
BORE_DR0       = 108       # crank j's carrier bores moved outwards by P[BORE_DR0 + j] ...
BORE_DT0       = 110       # ... and along the crank circle by P[BORE_DT0 + j] [m]
FRAME_TURN0    = 112       # cos, sin of disc k's profile angle less its rotation q[theta_k]
                           # (-k pi / zc + PROFILE_ROT): P[FRAME_TURN0 + 2 k + (0, 1)]
ECC_TURN0      = 116       # cos, sin of crank j's eccentric for disc 1 less that for disc 0
                           # (pi + ECC_PHASE[j, 1] - ECC_PHASE[j, 0]): P[ECC_TURN0 + 2 j + (0, 1)]


# ---- mesh, variants: 120-129 -------------------------------------------------------------
RING_OUTPUT    = 120       # single-stage: 1.0 = the pin ring is the output (CARRIER turns the
                           # ring pins), the output pins are fixed to the frame; 0.0 = pins


# ---- finite-element bodies: 130-139 ------------------------------------------------------
FE_DISC        = 130       # 1: the discs' pins are coupled through finite-element tables
# the disc's crank holes as load points (flexibility.fe_disc_holes; physics._fe_holes): 1 on;
# c_ss of disc 1 and 2 [m/N] (the holes' stretch under unit Q; the c_sp column is the last
# column of each disc's table)
FE_HOLES       = 131
FE_HOLE_CSS0   = 132
FE_HOLE_CSS1   = 133
FE_HOLE_EX     = 134       # unit vector from hole 0 (crank 0's) to hole 1, disc axes
FE_HOLE_EY     = 135
# (disc: 130-139; crankshaft: 140-149; carrier and flange: 150-159; disc modes: 160-169;
# finite-element pins: 170-179)
# carrier and flange (docs/model.md section 17, rvsim.physics._fe_carrier): the upper
# triangle of the plates' 4 x 4 bore table (x1, y1, x2, y2; carrier frame, bore 1 = crank 0's
# on +x) [m/N], packed as the crank's; one table for both plates; FE_PLATE_XX1 > 0: flexible
FE_PLATE_XX1   = 150
FE_PLATE_XY1   = 151
FE_PLATE_X1X2  = 152
FE_PLATE_X1Y2  = 153
FE_PLATE_YY1   = 154
FE_PLATE_Y1X2  = 155
FE_PLATE_Y1Y2  = 156
FE_PLATE_XX2   = 157
FE_PLATE_XY2   = 158
FE_PLATE_YY2   = 159
# crankshaft (docs/model.md section 17, rvsim.physics._fe_crank): the upper triangle of the
# crank's 4 x 4 compliance of its eccentric centres (x1, y1, x2, y2; crank frame, eccentric 1
# towards +x) relative to its support line [m/N]; FE_CRANK_XX1 > 0: the crank is flexible
FE_CRANK_XX1   = 140
FE_CRANK_XY1   = 141
FE_CRANK_X1X2  = 142
FE_CRANK_X1Y2  = 143
FE_CRANK_YY1   = 144
FE_CRANK_Y1X2  = 145
FE_CRANK_Y1Y2  = 146
FE_CRANK_XX2   = 147
FE_CRANK_XY2   = 148
FE_CRANK_YY2   = 149


# ---- disc modes: 160-169 (rvsim.physics._fe_modes; the modes travel in the ``modal`` array)
FE_MODES       = 160       # flexibility.fe_modes: modes of each disc the kernel integrates
                           # (their modal damping ratio is the contacts', P[ZETA])


# ---- finite-element pins in their grooves: 170-179 (rvsim.fe.pin) --------------------------
PIN_FE_STEP    = 170       # psi step of the pin table [rad]; 0: no finite-element pin
PIN_FE0        = 171       # c_pin(k step) [m/N], k = 0 .. PIN_FE_N - 1 (added to PIN_CB):
                           # slots 171-179


# ---- integration scheme (issue 14): 180-189 -----------------------------------------------
# stability guard of the crank nodes (rvsim.dynamics._stiff_nodes, docs/model.md section 9)
NODE_OMEGA_DT  = 180       # largest omega dt of a crank's node modes before the step is
                           # divided into sub-steps (0: guard off)
NODE_REFRESH   = 181       # steps between two checks (stiffness assembled)
NODE_SUBSTEPS  = 182       # state carried between calls: sub-steps per step (0 or 1: none)
NODE_H         = 183       # state: the (sub-)step [s] of the pin loop's skip bound (0: DT)
NODE_CHECKS    = 184       # checks after which the guard sub-stepped (whole run) ...
NODE_CHECKS_STEADY = 185   # ... of them in the steady window ...
NODE_PEAK      = 186       # ... and the largest omega dt (of the whole step) found
NODE_ALERT     = 187       # state: 1 while the last check found omega h above ALERT x the
                           # limit (then checked every step), else 0
# the bearings treated linearly implicitly (rvsim.dynamics._implicit_bearings, docs/model.md
# section 9): v += h (M + theta h^2 K_b)^-1 Q, K_b the bearings' tangent stiffness
IMPLICIT_THETA = 188       # theta (0: the explicit scheme)
IMPLICIT_REFRESH = 189     # steps between two factorisations of M + theta h^2 K_b
# ---- linearly implicit bearings, state and counters (issue 14): 190-199 --------------------
IMPLICIT_FACTORS = 190     # factorisations in the run ...
IMPLICIT_ALERTS = 191      # ... of them brought forward by a bearing's rising force ...
IMPLICIT_FALLBACKS = 192   # ... and steps whose M + theta h^2 K_b was not positive definite
                           # (taken with M alone, the explicit step)
IMPLICIT_SINCE = 193       # state carried between calls: steps since the last factorisation


_P_INDEX = {name: value for name, value in dict(globals()).items()
            if name not in _BEFORE_P and name.isupper()}
N_PARAMS = 200
assert len(set(_P_INDEX.values())) == len(_P_INDEX), "two constants share one slot of P"
assert all(0 <= value < N_PARAMS for value in _P_INDEX.values()), "raise N_PARAMS"
_NAME_OF = {value: name for name, value in _P_INDEX.items()}
#: name of every slot of P ("" for a slot not in use)
PARAM_NAMES = tuple(_NAME_OF.get(i, "") for i in range(N_PARAMS))
del _BEFORE_P, _P_INDEX, _NAME_OF
#: values of the pin table in P (slots PIN_FE0 .. PIN_FE0 + PIN_FE_N - 1; a count, not a slot)
PIN_FE_N = 9
assert PIN_FE0 + PIN_FE_N <= 180, "the pin table overflows its block (170-179)"

# ---- per-sample output channels (columns of the ``channels`` array) -------------------------
CH_TIME        = 0
CH_THETA_IN    = 1
CH_OMEGA_IN    = 2
CH_THETA_OUT   = 3
CH_OMEGA_OUT   = 4
CH_TORQUE_IN   = 5
CH_TORQUE_LOAD = 6
CH_MESH_F0     = 7
CH_MESH_F1     = 8
CH_ARM_F00     = 9
CH_ARM_F01     = 10
CH_ARM_F10     = 11
CH_ARM_F11     = 12
CH_SUP_FL0     = 13
CH_SUP_FU0     = 14
CH_SUP_FL1     = 15
CH_SUP_FU1     = 16
CH_PIN_MAX     = 17        # the largest pin force of this evaluation (either disc)
N_CHANNELS = 18
CHANNEL_NAMES = (
    "time", "theta_in", "omega_in", "theta_out", "omega_out", "torque_in", "torque_load",
    "mesh_f0", "mesh_f1", "arm_f00", "arm_f01", "arm_f10", "arm_f11", "sup_fl0", "sup_fu0",
    "sup_fl1", "sup_fu1", "pin_f_max")

# ---- accumulators over the steady window ----------------------------------------------------
E_INPUT, E_OUTPUT, E_DISSIPATED, E_PARAMETRIC, E_KIN0, E_POT0, E_KIN1, E_POT1 = range(8)
E_PIN_PEAK = 8     # not energy: the window's largest pin force [N], at every (sub-)step
N_ENERGY = 9
