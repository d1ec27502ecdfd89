"""The record types the time-loop kernel and its caller share, field by name.

The kernel (:mod:`rubdiag._kernels.newmark`) and its caller (:mod:`rubdiag.simulation._kernel_args`)
exchange a run's parameters, the loop's counters, each element's state and the logs as NumPy
structured arrays: the caller writes ``run["dt"] = ...``, the kernel reads ``run[0].dt``.
Numba compiles a field access to a load at a fixed offset, with no reference counting, so a
name costs nothing over the integer row constants it replaces — and a misspelt one fails to
compile instead of reading the wrong row.

Element status codes are the seam's (:mod:`rubdiag._kernels.elements`): every kind reports
``OPEN`` (its law is not engaged: no force, a zero Jacobian) or one of two engaged statuses,
which the books count separately (for contacts: sliding and sticking).
"""

from __future__ import annotations

import numpy as np

__all__ = [
    "D_LIN",
    "D_NEW",
    "ELEMENT",
    "ENERGY",
    "EPISODE",
    "OPEN",
    "PROGRESS",
    "P_NEW",
    "RUN",
    "SAMPLE",
    "SEGMENT",
    "SLIDING",
    "STATS",
    "STICKING",
    "TRACK",
    "TRIAL",
    "V2",
    "XA_N",
    "XV_N",
    "X_N",
    "V",
    "zeros",
]

OPEN = 1
SLIDING = 2
STICKING = 3

# Rows of the elements' local vectors (m local coordinates): the work ``local_work`` (5, m)
# of a step and the state ``local_state`` (3, m). The laws read ``local_work[D_NEW]`` and
# write ``local_work[P_NEW]``.
D_LIN = 0       # the linear predictor's local displacements
D_NEW = 1       # the trial (then the solution's) local displacements
P_NEW = 2       # the trial local forces
V = 3           # work of the solve, then B dq
V2 = 4          # work of the solve, then Δp
X_N, XV_N, XA_N = 0, 1, 2     # local displacement, velocity, acceleration at the step start

_F, _I = np.float64, np.int64


def _record(*fields) -> np.dtype:
    # np.record as the scalar type: an element of the array takes its fields as attributes
    # in NumPy as in Numba (``run[0].dt``), so the kernels also run as plain Python
    return np.dtype((np.record, np.dtype(list(fields), align=True)))


#: A run's parameters, and the end tick of the current call.
RUN = _record(
    ("dt", _F),              # largest step (s)
    ("newton_tol", _F),      # element Newton tolerance (m)
    ("gap_jump", _F),        # deepest penetration an element may close to in one step (m)
    ("aug_shift", _F),       # where a boosted multiplier update lands in the band (of eps)
    ("beta", _F),            # Newmark beta
    ("gamma", _F),           # Newmark gamma
    ("n_lev", _I),           # step levels dt / 2^k
    ("fixed", _I),           # 1: fixed step (nothing is rejected)
    ("grow_after", _I),      # accepted steps at a level before the step doubles
    ("max_newton", _I),
    ("max_aug", _I),
    ("tick_end", _I),        # the call returns at this tick (the caller runs in chunks)
    ("out_ticks", _I),       # ticks between recorded samples
    ("aug_strict", _I),      # 1: multipliers that miss the band fail the element solve
    ("sen_ticks", _I),       # ticks between sensor samples
    ("coupled", _I),         # dense system: its leading coordinates coupled in M and K
    ("kinematics", _I),      # 1: a kind reads the local velocity, acceleration or the angle
    ("base_level", _I),      # the level of the base step: longer ones (lev < base) are long
    ("tick_stop", _I),       # a long step does not cross this tick (the run's or stretch's end)
    ("step_error", _F),      # long steps' local error tolerance, of ``scale``; 0: none
)

#: The loop's state carried from call to call: counters, the energy ledger (J), the failure,
#: and the current trial step's clock, which the element laws read.
PROGRESS = _record(
    ("tick", _I), ("level", _I),
    ("quiet", _I),           # accepted steps since the last level change
    ("n_accepted", _I), ("n_rej_newton", _I), ("n_rej_abrupt", _I), ("n_abrupt_at_min", _I),
    ("newton_total", _I), ("newton_max", _I), ("aug_total", _I), ("aug_max", _I),
    ("aug_pending", _I),     # steps accepted with the penetration band not yet reached
    ("n_episodes", _I), ("n_segments", _I), ("n_level_changes", _I),
    ("sample0_done", _I),
    ("n_rej_error", _I),     # long steps rejected by the local error estimate
    ("scale", _F),           # the largest recorded displacement at the last sample (m)
    ("fail_element", _I), ("fail_code", _I),
    ("w_ext", _F), ("w_drive", _F), ("d_visc", _F), ("d_fric", _F), ("d_num", _F),
    ("e_contact", _F),       # the elements' elastic energy at the current state
    ("cone_excess", _F),     # max over steps and elements of |F_T| - mu F_N (N)
    ("fail_time", _F),       # s
    # the trial step: its ends (s), length (s), the shaft's speed (rad/s) and angle (rad)
    # at its end, and the Newmark velocity relation v_1 = cv Δq + cvv v_n + cva a_n
    ("t_n", _F), ("t_1", _F), ("h", _F), ("omega", _F), ("phi", _F),
    ("cv", _F), ("cvv", _F), ("cva", _F),
)

#: One nonlinear element as the seam sees it: its kind, its local rows ``row .. row + n - 1``
#: of the local vectors, the augmented Lagrangian (``aug`` 1: multiplier iterated into the
#: band ``-eps < gap <= 0``) and the smallest step level it may be engaged at (``lev_req``:
#: its step requirement; an element that can close on impact (``impact`` 1: a contact, a
#: pedestal's seat) is engaged at the base level or below, and long steps keep it open).
ELEMENT = _record(("kind", _I), ("row", _I), ("n", _I), ("aug", _I), ("eps", _F),
                  ("lev_req", _I), ("impact", _I))

#: An element's law at the trial state (written by its kind's law, read by the books):
#: status, normal and tangential force (N), gap (m, < 0 penetration), the engagement
#: function z (> 0 engaged: where it crosses 0 dates an episode's start and end), the slip
#: record (m), the step's energy terms (J: elastic energy stored, dissipated, work of the
#: prescribed gap motion and of the surface drive, each as the ledger subtracts it), the cone
#: excess |F_T| - mu F_N (N), and the multiplier the solver iterates (N).
TRIAL = _record(("status", _I), ("fn", _F), ("ft", _F), ("gap", _F), ("z", _F), ("slip", _F),
                ("elastic", _F), ("dissipated", _F), ("w_ramp", _F), ("w_surface", _F),
                ("cone", _F), ("lam", _F))

#: An element's committed record and its current episode (a maximal run of engaged steps)
#: and status segment: start (s), peak F_N (N), time (s) and normal impulse (N s) sliding and
#: sticking, steps and entries into each status.
TRACK = _record(("status", _I), ("fn", _F), ("ft", _F), ("gap", _F), ("z", _F), ("slip", _F),
                ("ep_start", _F), ("ep_peak_fn", _F), ("ep_slide_time", _F),
                ("ep_stick_time", _F), ("ep_slide_impulse", _F), ("ep_stick_impulse", _F),
                ("seg_start", _F), ("ep_steps", _I), ("ep_slide_entries", _I),
                ("ep_stick_entries", _I))

#: An element's totals by status (index status - 1): time (s), normal and |tangential|
#: impulse (N s); its largest F_N, |F_T| (N) and penetration (m).
STATS = _record(("time", _F, (3,)), ("fn_impulse", _F, (3,)), ("ft_impulse", _F, (3,)),
                ("max_fn", _F), ("max_ft", _F), ("max_penetration", _F))

#: An ended episode (the log; open episodes stay in the TRACK).
EPISODE = _record(("t_start", _F), ("t_end", _F), ("peak_fn", _F), ("slide_time", _F),
                  ("stick_time", _F), ("slide_impulse", _F), ("stick_impulse", _F),
                  ("element", _I), ("steps", _I), ("slide_entries", _I),
                  ("stick_entries", _I))

#: A status segment: a maximal run of one engaged status of one element.
SEGMENT = _record(("t_start", _F), ("t_end", _F), ("element", _I), ("status", _I))

#: Each element at a recorded sample: as its TRACK.
SAMPLE = _record(("fn", _F), ("ft", _F), ("gap", _F), ("slip", _F), ("status", _I))

#: The energy ledger at a recorded sample (J).
ENERGY = _record(("w_ext", _F), ("w_drive", _F), ("d_visc", _F), ("d_fric", _F),
                 ("d_num", _F), ("kinetic", _F), ("strain", _F), ("contact", _F))


def zeros(dtype: np.dtype, shape=1) -> np.ndarray:
    """A zeroed structured array of ``dtype`` (one record by default)."""
    return np.zeros(shape, dtype)
