"""The law of a breathing transverse crack in one shaft element (element kind 3).

Local coordinates: the element's 8 DOFs ``x = [u_y1, u_z1, θ_y1, θ_z1, u_y2, u_z2, θ_y2,
θ_z2]`` (relative to ground, T = identity; the order of
:func:`rubdiag.assembly._elements.shaft_element`). The intact element stays in the global K;
this law adds the crack's stiffness loss, ``p = -f ΔK(ψ) x`` with

* ``ΔK(ψ) = Q(ψ) ΔK_open Q(ψ)ᵀ``: the fully open crack's loss ΔK_open (8 x 8, negative
  semidefinite, in the crack's frame whose y axis is the crack normal:
  :class:`rubdiag.simulation._crack.BreathingCrack`) turned with the crack; Q(ψ) turns each
  node's (u_y, u_z) and (θ_y, θ_z) pairs by ``ψ = φ + angle`` (φ the shaft angle,
  ``progress[0].phi`` at the step's end, set by the kernel's clock);
* the breathing function f in [0, 1]:

  - Mayes & Davies: ``f = (1 + cos ψ) / 2`` (Mayes I.W., Davies W.G.R., "Analysis of the
    response of a multi-rotor-bearing system containing a transverse crack in a rotor",
    J. Vib. Acoust. Stress Reliab. Des. 106 (1984) 139-145): fully open when the crack
    normal points along +y, closed half a turn later — a function of the angle only;
  - Gasch: open (f = 1) while the bending moment at the crack across its depth stretches
    the crack's mouth, closed (f = 0) otherwise (Gasch R., "A survey of the dynamic
    behaviour of a simple rotating shaft with a transverse crack", J. Sound Vib. 160(2)
    (1993) 313-332). The moment is that of the intact element at the crack's position,
    ``M_n = g · (Q(ψ)ᵀ x)`` (g from the element's flexibility; tension at the mouth when
    M_n < 0, as ``M = EI v''``). It reads x, so the law is displacement-dependent; its
    Jacobian is ``-f ΔK(ψ)`` in each state. Switching on this moment (rather than on a
    difference of the end rotations) makes the force's part across the depth continuous
    at the switch: that part is proportional to M_n itself.

The Jacobian is ``dp/dx = -f ΔK(ψ)``. Status OPEN (law not engaged: the crack is shut, no
force) when f = 0, else SLIDING; ``z`` is f for Mayes and ``-M_n`` (N m, > 0 open) for
Gasch. Books: the elastic energy ``½ f xᵀ ΔK(ψ) x`` (<= 0: the loss of the intact strain
energy) and, as ``w_ramp``, minus the work the turning and breathing stiffness does on the
structure over the step, ``½ x_nᵀ (S_1 - S_n) x_1`` with ``S = f ΔK(ψ)`` (the exact
trapezoidal remainder), so that the energy ledger closes: a time-varying stiffness
exchanges energy with the drive.

Parameters (a ``parameters`` row): the law code, the angle offset (rad), g (8), ΔK_open (64, row
major). State: f, ψ and x at the step's end (the books read the start's from the committed
state).
"""

from __future__ import annotations

import numpy as np

from rubdiag._kernels.records import D_NEW, OPEN, P_NEW, SLIDING
from rubdiag._numba import njit

KIND = 3
N_LOCAL = 8
KINEMATICS = True       # reads the shaft angle (records.RUN: kinematics)

MAYES, GASCH = 0, 1     # breathing laws
LAW, ANGLE, G0, DK0 = 0, 1, 2, 10       # parameters
N_PAR = DK0 + 64
F, PSI, X0, P0 = 0, 1, 2, 10            # state: f, ψ, x (8) and p (8) at the trial
N_STATE = P0 + 8


@njit(error_model="numpy", inline="always")
def _in_crack_frame(local_work, r, j, c, s):
    """Component j of ``Q(ψ)ᵀ x`` (the crack's frame) for the trial x at
    ``local_work[D_NEW, r .. r + 7]`` (m or rad), with ``c, s = cos ψ, sin ψ``."""
    if j % 2 == 0:
        return c * local_work[D_NEW, r + j] + s * local_work[D_NEW, r + j + 1]
    return -s * local_work[D_NEW, r + j - 1] + c * local_work[D_NEW, r + j]


@njit(error_model="numpy", inline="always")
def _openness(e, local_work, r, parameters, c, s, psi):
    """f, and the engagement function z (module docstring), of element e (its trial x at
    ``local_work[D_NEW, r ..]``, its ``parameters`` row) at the angle ψ (rad; ``c, s = cos
    ψ, sin ψ``)."""
    if parameters[e, LAW] == MAYES:
        f = 0.5 * (1.0 + np.cos(psi))
        return f, f
    moment = 0.0
    for j in range(8):
        moment += parameters[e, G0 + j] * _in_crack_frame(local_work, r, j, c, s)
    return (1.0 if moment < 0.0 else 0.0), -moment


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
    psi = progress[0].phi + parameters[e, ANGLE]
    c = np.cos(psi)
    s = np.sin(psi)
    f, z = _openness(e, local_work, r, parameters, c, s, psi)
    # p = -f Q ΔK Qᵀ x: ΔK Qᵀ x into P_NEW, then turned back pair by pair
    for i in range(8):
        acc = 0.0
        for j in range(8):
            acc += parameters[e, DK0 + 8 * i + j] * _in_crack_frame(local_work, r, j, c, s)
        local_work[P_NEW, r + i] = acc
    for k in range(4):
        a = local_work[P_NEW, r + 2 * k]
        b = local_work[P_NEW, r + 2 * k + 1]
        local_work[P_NEW, r + 2 * k] = -f * (c * a - s * b)
        local_work[P_NEW, r + 2 * k + 1] = -f * (s * a + c * b)
    # dp/dx = -f Q ΔK Qᵀ, block by 2 x 2 block: R(ψ) D Rᵀ(ψ), R = [[c, -s], [s, c]]
    for i in range(0, 8, 2):
        for j in range(0, 8, 2):
            k = DK0 + 8 * i + j
            d00 = parameters[e, k]
            d01 = parameters[e, k + 1]
            d10 = parameters[e, k + 8]
            d11 = parameters[e, k + 9]
            a00 = c * d00 - s * d10      # R D
            a01 = c * d01 - s * d11
            a10 = s * d00 + c * d10
            a11 = s * d01 + c * d11
            jacobian[r + i, j] = -f * (a00 * c - a01 * s)
            jacobian[r + i, j + 1] = -f * (a00 * s + a01 * c)
            jacobian[r + i + 1, j] = -f * (a10 * c - a11 * s)
            jacobian[r + i + 1, j + 1] = -f * (a10 * s + a11 * c)
    status = OPEN if f == 0.0 else SLIDING
    trial[e].status = status
    trial[e].fn = 0.0
    trial[e].ft = 0.0
    trial[e].gap = np.inf
    trial[e].z = z
    trial[e].slip = 0.0
    element_state[1, e, F] = f
    element_state[1, e, PSI] = psi
    for i in range(8):
        element_state[1, e, X0 + i] = local_work[D_NEW, r + i]
        element_state[1, e, P0 + i] = local_work[P_NEW, r + i]
    _energy(e, element_state, trial, progress)
    return status


@njit(error_model="numpy", inline="always")
def books(e, elements, parameters, element_state, track, trial, progress):
    """Nothing: the law keeps its books (:func:`_energy`).

    A books loop of its own in the seam made Numba count six arrays' references once per
    element solve (the seam's note on reference counting); the energy terms cost 24
    products per evaluation of a crack.

    Parameters
    ----------
    e : int
        The element.
    elements, parameters, element_state, track, trial, progress : ndarray
        As for :func:`rubdiag._kernels.elements.element_books`.
    """


@njit(error_model="numpy", inline="always")
def _energy(e, element_state, trial, progress):
    """The energy terms of element e's trial state (written at every evaluation of the law:
    the last one is the solution's), from the forces p = -S x, S = f Q ΔK_open Qᵀ
    (symmetric), kept in the state: the elastic energy ``½ x₁ᵀ S₁ x₁ = -½ x₁·p₁`` and the
    work of the turning, breathing stiffness over the step ``½ x_nᵀ (S₁ - S_n) x₁ = ½ (x₁·p_n
    - x_n·p₁)`` (booked as ``w_ramp``, which the ledger subtracts: ``-½ (...)``; none at
    rest, h = 0) into ``trial[e]`` (J). 24 products instead of three turned 8 x 8 quadratic
    forms."""
    elastic = 0.0
    s1 = 0.0
    s0 = 0.0
    for i in range(8):
        x1 = element_state[1, e, X0 + i]
        p1 = element_state[1, e, P0 + i]
        elastic += x1 * p1
        s1 += element_state[0, e, X0 + i] * p1
        s0 += x1 * element_state[0, e, P0 + i]
    trial[e].elastic = -0.5 * elastic
    trial[e].dissipated = 0.0
    trial[e].w_ramp = 0.5 * (s1 - s0) if progress[0].h > 0.0 else 0.0
    trial[e].w_surface = 0.0
    trial[e].cone = 0.0
