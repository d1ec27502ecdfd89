"""What each row or entry of the time-loop kernel's packed arrays holds, by name.

The kernel (:mod:`rubdiag.kernels.newmark`) keeps its per-element state, parameters, logs and
work in a few 2-D arrays; these constants name their rows (columns for the logs) for the
kernel and for its caller (:mod:`rubdiag.simulate.system`, which allocates and reads them).
They are module-level integers because Numba compiles a module global as a constant (it
cannot read class attributes). ``*_SIZE`` is the length of that axis.
"""

from __future__ import annotations

# ---- fpar (float64): a run's parameters
FP_DT = 0  # largest step (s)
FP_T_RAMP = 1  # end of the gap ramp (s); 0 = no ramp
FP_NEWTON_TOL = 2  # contact Newton tolerance (m)
FP_GAP_JUMP = 3  # deepest penetration an element may close to in one step (m)
FP_AUG_SHIFT = 4  # where a boosted multiplier update lands in the band (fraction of eps)
FP_BETA = 5  # Newmark beta
FP_GAMMA = 6  # Newmark gamma
FP_SIZE = 7

# ---- ipar (int64)
IP_N_LEV = 0  # number of step levels dt / 2^k
IP_FIXED = 1  # 1: fixed step (nothing is rejected)
IP_GROW_AFTER = 2  # accepted steps at a level before the step doubles
IP_MAX_NEWTON = 3
IP_MAX_AUG = 4
IP_TICK_END = 5  # the call returns at this tick (the caller runs the kernel in chunks)
IP_OUT_TICKS = 6  # ticks between recorded samples
IP_AUG_STRICT = 7  # 1: a step whose multipliers miss the band is a failed contact solve
IP_SEN_TICKS = 8  # ticks between sensor samples
IP_COUPLED = 9  # dense system: its leading coordinates coupled in M and K (rest: modal)
IP_SIZE = 10

# ---- istate (int64): the loop's counters, carried from call to call
I_TICK = 0
I_LEVEL = 1
I_QUIET = 2  # accepted steps since the last level change
I_N_ACCEPTED = 3
I_N_REJ_NEWTON = 4
I_N_REJ_ABRUPT = 5
I_NEWTON_TOTAL = 6
I_NEWTON_MAX = 7
I_AUG_TOTAL = 8
I_N_EPISODES = 9
I_N_LEVEL_CHANGES = 10
I_FAIL_ELEMENT = 11
I_N_ABRUPT_AT_MIN = 12
I_SAMPLE0_DONE = 13
I_AUG_MAX = 14
I_FAIL_CODE = 15  # contact-solve code of the failure
I_AUG_PENDING = 16  # steps accepted with the penetration band not yet reached
I_N_SEGMENTS = 17
I_SIZE = 18

# ---- fstate (float64): the energy ledger (J unless stated) and the failure time
F_W_EXT = 0
F_W_DRIVE = 1
F_D_VISC = 2
F_D_FRIC = 3
F_D_NUM = 4
F_CONE_EXCESS = 5  # max over steps/elements of |F_T| - mu F_N (N)
F_FAIL_TIME = 6  # s
F_E_CONTACT = 7  # contact elastic energy at the current state
F_SIZE = 8

# ---- cf (CF_SIZE, n_c) float64: each contact element's state
CF_E = 0  # elastic tangential displacement e (m)
CF_LAM = 1  # augmented-Lagrangian multiplier (N)
CF_SLIP = 2  # slip s (m): kind 1 the tangential coordinate, kind 2 the sum of e increments
CF_FN = 3  # F_N (N)
CF_FT = 4  # F_T (N)
CF_GAP = 5  # gap (m)
CF_Z = 6  # trial normal force z (N): where it crosses 0 dates a closing or an opening
# the current episode (a maximal run of closed steps) and status segment
CF_EP_START = 7  # s
CF_EP_PEAK_FN = 8  # N
CF_EP_SLIDE_TIME = 9  # s
CF_EP_STICK_TIME = 10  # s
CF_EP_SLIDE_IMPULSE = 11  # normal impulse while sliding (N s)
CF_EP_STICK_IMPULSE = 12  # normal impulse while sticking (N s)
CF_SEG_START = 13  # s
CF_SIZE = 14

# ---- ci (CI_SIZE, n_c) int64
CI_STATUS = 0  # OPEN, SLIDING or STICKING
CI_EP_STEPS = 1  # the current episode's steps
CI_EP_SLIDE_ENTRIES = 2
CI_EP_STICK_ENTRIES = 3
CI_SIZE = 4

# ---- ciw (CR_SIZE, n_c) float64: solve_contact's per-element results (its ``cres``)
CR_FN = 0
CR_FT = 1
CR_E = 2  # elastic tangential displacement at the end of the step
CR_E_TRIAL = 3  # trial one (e_n + the step's tangential increment)
CR_GAP = 4
CR_Z = 5
CR_SIZE = 7  # solve_contact's documented shape (the last row is unused)

# ---- work: wn (WN_SIZE, n), wc (WC_SIZE, 2 n_c), wcn (WCN_SIZE, n_c) float64
WN_X = 0  # operand of the gamma != 1/2 products
WN_RHS = 1  # right-hand side; at the accept, plus Bᵀ Δp: the system dq solves
WN_DQ = 2  # displacement increment
WN_KDQ = 3  # work of the LU solve, then K dq
WN_MDQ = 4  # C x (gamma != 1/2), then M dq
WN_SIZE = 5
WC_D_LIN = 0  # contact displacements of the linear predictor
WC_D_NEW = 1  # contact displacements of the solution
WC_P_NEW = 2  # contact forces of the solution
WC_V = 3  # work of solve_contact, then B dq
WC_V2 = 4  # work of solve_contact, then Δp
WC_SIZE = 5
WCN_GAP = 0  # gaps at the end of the step
WCN_LAM = 1  # multipliers (from 0 in each step)
WCN_DRIVE = 2  # surface travel Omega R h of the step (kind 2)
WCN_GAP_START = 3  # gaps at the start of the step (gap ramp)
WCN_SIZE = 4

# ---- logs: episodes ep_f (cap, EPF_SIZE), ep_i (cap, EPI_SIZE); status segments sg_f, sg_i
EPF_T_START = 0
EPF_T_END = 1
EPF_PEAK_FN = 2
EPF_SLIDE_TIME = 3
EPF_STICK_TIME = 4
EPF_SLIDE_IMPULSE = 5
EPF_STICK_IMPULSE = 6
EPF_SIZE = 7
EPI_ELEMENT = 0
EPI_STEPS = 1
EPI_SLIDE_ENTRIES = 2
EPI_STICK_ENTRIES = 3
EPI_COMPLETE = 4  # 1: the episode ended (0 is never logged: open episodes stay in cf, ci)
EPI_SIZE = 5
SGF_T_START = 0
SGF_T_END = 1
SGI_ELEMENT = 0
SGI_STATUS = 1
SG_SIZE = 2

# ---- totals per element: tot (n_c, TOT_SIZE), status s = 1..3 at column X + s - 1
TOT_TIME = 0  # s
TOT_FN_IMPULSE = 3  # N s
TOT_FT_IMPULSE = 6  # |F_T| impulse (N s)
TOT_SIZE = 9
MX_FN = 0  # mx (n_c, MX_SIZE): largest F_N, |F_T|, penetration
MX_FT = 1
MX_PENETRATION = 2
MX_SIZE = 3

# ---- out_en (n_out, EN_SIZE): the energy ledger at each sample (J)
EN_W_EXT = 0
EN_W_DRIVE = 1
EN_D_VISC = 2
EN_D_FRIC = 3
EN_D_NUM = 4
EN_KINETIC = 5
EN_STRAIN = 6
EN_CONTACT = 7
EN_SIZE = 8

# ---- prof (P_SIZE) int64: CPU cycles per section of a step, in a profiled run
P_RHS = 0  # right-hand side of the increment equation (force, M v, K q, Bᵀp)
P_SOLVE = 1  # the linear solve with K_eff
P_CONTACT = 2  # contact predictor, the contact Newton solve, the abrupt-closing check
P_UPDATE = 3  # accept: dq += S Δp, M dq and K dq, the new state
P_LEDGER = 4  # energy ledger, episodes and totals, committing the contact state
P_OUTPUT = 5  # step-size control and the recorded samples
P_SIZE = 6
PROFILE_SECTIONS = ("rhs", "solve", "contact", "update", "ledger", "output")
