"""A loose bearing pedestal (kind 4): a mass pressed onto its seat, which lifts off.

Model (derived here; a piecewise-linear support of the kind Muszynska & Goldman study, whose
paper is the reference for the behaviour — ½× and ⅓× subharmonics, many harmonics and
chaotic windows as the unbalance grows: A. Muszynska and P. Goldman, "Chaotic responses of
unbalanced rotor/bearing/stator systems with looseness or rubs", Chaos, Solitons & Fractals
5 (1995) 1683-1704; their equations are not reproduced here).

One local coordinate ``x = s (q[dof] - q[base])`` (``s`` = ±1: x is positive away from the
seat, the lift-off direction; base -1: ground), measured from the static equilibrium of the
seated pedestal. A dead load ``F_0 >= 0`` (N: the weight the pedestal carries, or the bolts'
preload) presses the pedestal onto its seat, a spring of stiffness ``k_s`` that acts in
compression only. The seat is unloaded at ``x_c = F_0 / k_s - c`` (``c`` >= 0 a clearance
between pedestal and seat at q = 0, only without a preload). The law's force on x (dead load
and seat together) is

    p(x) = -F_0 - k_s (x - x_c)       x <  x_c   seated (status 2),
    p(x) = -F_0 - k_l (x - x_c)       x >= x_c   lifted off,

continuous at ``x_c``, with ``k_l >= 0`` an optional soft retaining stiffness (loose bolts:
the "rattle" law). Seated and preloaded, ``p = -k_s x``: the linear pedestal, with its spring
in the law instead of in K, below the lift-off threshold (the seat force ``k_s (x_c - x)``
never reaches 0). Lifted with ``k_l = 0`` the status is OPEN (a constant force, zero
Jacobian: the element solve keeps the dead load as a frozen force); with ``k_l > 0`` it is 3
(engaged: the Jacobian is ``-k_l``). The step's record:
``fn`` the seat's compressive force ``k_s (x_c - x)`` (0 lifted), ``ft`` 0, ``gap = x -
x_c`` (< 0: the seat is compressed), ``z = -k_s gap`` (> 0 seated), ``slip`` 0.

Books (the energy ledger closes up to the switching steps): the elastic energy of the
engaged spring, ``k_s (x - x_c)² / 2`` seated and ``k_l (x - x_c)² / 2`` lifted; the dead
load's work on the structure over the step, ``-F_0 Δx``, is the work of a load from outside
the structure's ``f(t)``: it is booked as the element's drive work (``w_ramp = F_0 Δx``, which
the ledger subtracts into ``work_drive``). No damping in the law (``KINEMATICS`` False): a
seated support's damping goes into the system's C.

Lift-off time fraction (the raw measure for labels): the time the element spends not seated
(status 1 or 3) over the run time, from ``time_in_status``
(:func:`rubdiag.simulation._pedestal.lift_off_fraction`).
"""

from __future__ import annotations

from rubdiag._kernels.records import D_NEW, OPEN, P_NEW, SLIDING, STICKING, X_N
from rubdiag._numba import njit

__all__ = ["KIND", "KINEMATICS", "LIFTED", "N_LOCAL", "PARAMS", "SEATED", "STATE", "books",
           "force", "law"]

KIND = 4
N_LOCAL = 1
KINEMATICS = False
#: engaged statuses: seated on the seat spring, lifted on the retaining spring (k_l > 0)
SEATED = SLIDING
LIFTED = STICKING
#: the parameter row, by name (N/m, N/m, N, m)
PARAMS = ("k_s", "k_l", "f_0", "x_c")
K_S, K_L, F_0, X_C = range(len(PARAMS))
#: the state: x at the step's end and start (m), for the books
STATE = ("x", "x_start")
X, X_START = range(len(STATE))


@njit(error_model="numpy", inline="always")
def force(x, k_s, k_l, f_0, x_c):
    """The law at x (module docstring).

    Parameters
    ----------
    x : float
        The local coordinate, away from the seat (m).
    k_s, k_l : float
        The seat's and the retaining spring's stiffness (N/m).
    f_0 : float
        The dead load (N).
    x_c : float
        Where the seat is unloaded (m).

    Returns
    -------
    tuple
        ``(p (N), dp/dx (N/m), status, seat force (N))``.
    """
    gap = x - x_c
    if gap < 0.0:
        return -f_0 - k_s * gap, -k_s, SEATED, -k_s * gap
    status = LIFTED if k_l > 0.0 else OPEN
    return -f_0 - k_l * gap, -k_l, status, 0.0


@njit(error_model="numpy", inline="always")
def law(e, elements, local_work, local_state, parameters, element_state, track, trial, progress,
        jacobian):
    """The seam's law for element ``e`` (module docstring).

    Parameters
    ----------
    e : int
        The element.
    elements, local_work, local_state, parameters, element_state : ndarray
        As for :func:`rubdiag._kernels.elements.element_laws`.
    track, trial, progress, jacobian : ndarray
        As for :func:`rubdiag._kernels.elements.element_laws`.

    Returns
    -------
    int
        The element's status.
    """
    r = elements[e].row
    x = local_work[D_NEW, r]
    k_s = parameters[e, K_S]
    x_c = parameters[e, X_C]
    p, dp, status, fn = force(x, k_s, parameters[e, K_L], parameters[e, F_0], x_c)
    local_work[P_NEW, r] = p
    jacobian[r, 0] = dp
    trial[e].status = status
    trial[e].fn = fn
    trial[e].ft = 0.0
    trial[e].gap = x - x_c
    trial[e].z = -k_s * (x - x_c)
    trial[e].slip = 0.0
    element_state[1, e, X] = x
    element_state[1, e, X_START] = local_state[X_N, r]
    _energy(e, parameters, element_state, trial)
    return status


@njit(error_model="numpy", inline="always")
def books(e, elements, parameters, element_state, track, trial, progress):
    """Nothing: the law keeps its books (:func:`_energy`; a books loop of its own in the seam
    made Numba count six arrays' references once per element solve).

    Parameters
    ----------
    e : int
        The element.
    elements, parameters, element_state, track, trial, progress : ndarray
        As for :func:`rubdiag._kernels.elements.element_books`.
    """


@njit(error_model="numpy", inline="always")
def _energy(e, parameters, element_state, trial):
    """Element ``e``'s energy terms at its trial state (module docstring), from its
    ``parameters`` row and ``element_state``, into ``trial[e]`` (J)."""
    x = element_state[1, e, X]
    gap = x - parameters[e, X_C]
    k_s = parameters[e, K_S]       # both read: an array read in a branch only brings reference
    k_l = parameters[e, K_L]       # counting into the caller
    k = k_s if gap < 0.0 else k_l
    trial[e].elastic = 0.5 * k * gap * gap
    trial[e].dissipated = 0.0
    trial[e].w_ramp = parameters[e, F_0] * (x - element_state[1, e, X_START])
    trial[e].w_surface = 0.0
    trial[e].cone = 0.0
