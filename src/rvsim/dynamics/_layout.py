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
N_CRANKS = 2
N_DISCS = 2

# ---- constants vector P ---------------------------------------------------------------------
_names = """
DT N_STEPS_UNUSED RATIO
INPUT_SPEED RAMP_TIME
LOAD LOAD_T0 LOAD_T1 FLUCT_AMP FLUCT_FREQ
RB1 RB2 CENTRE_DIST SIN_AW BACKLASH BASE_PITCH CONTACT_RATIO K_MESH MESH_MASS
RG A_GEN ZP ZC PROFILE_OFFSET PIN_RADIUS ECC PROFILE_ROT
PIN_C PIN_CB ARM_C ARM_CB ARM_CLEAR SUP_C SUP_CB SUP_CLEAR_L SUP_CLEAR_U
ZETA MU V_FRIC
J_CARRIER M_DISC J_DISC J_CRANK MINV_LL MINV_LU MINV_UU M_NODE
W_D1_L W_D1_U W_D2_L W_D2_U W_G_L W_G_U
PEN_LIMIT STEADY_START
RUNOUT_X0 RUNOUT_Y0 RUNOUT_X1 RUNOUT_Y1
""".split()
for _i, _n in enumerate(_names):
    globals()[_n] = _i
N_PARAMS = len(_names)
PARAM_NAMES = tuple(_names)

# ---- per-sample output channels (columns of the ``channels`` array) -------------------------
_channels = """
TIME THETA_IN OMEGA_IN THETA_OUT OMEGA_OUT TORQUE_IN TORQUE_LOAD
MESH_F0 MESH_F1 ARM_F00 ARM_F01 ARM_F10 ARM_F11 SUP_FL0 SUP_FU0 SUP_FL1 SUP_FU1
""".split()
for _i, _n in enumerate(_channels):
    globals()["CH_" + _n] = _i
N_CHANNELS = len(_channels)
CHANNEL_NAMES = tuple(c.lower() for c in _channels)

# ---- energy accumulators over the steady window ---------------------------------------------
E_INPUT, E_OUTPUT, E_DISSIPATED, E_PARAMETRIC, E_KIN0, E_POT0, E_KIN1, E_POT1 = range(8)
N_ENERGY = 8

# ---- status codes returned by the kernel ----------------------------------------------------
STATUS_OK = 0
STATUS_NONFINITE = 1
STATUS_PENETRATION = 2
STATUS_TEXT = {STATUS_OK: "ok", STATUS_NONFINITE: "diverged",
               STATUS_PENETRATION: "runaway_penetration"}
