"""A kind of nonlinear element that exists only in the tests: a linear spring and dashpot from
one DOF to ground, added through the element seam by the recipe of
:mod:`rubdiag._kernels.elements` and :mod:`rubdiag.simulation._elements` — to prove that recipe.

Law: one local coordinate x = q[dof]; ``p = -k x - c ẋ`` with ẋ from the Newmark relation
``ẋ_1 = cv (x - x_n) + cvv ẋ_n + cva ẍ_n`` (records.PROGRESS), so ``dp/dx = -k - c cv``.
Always engaged (status 2). Books: the spring's energy ``k x² / 2`` and the dashpot's
dissipation over the step, ``c (x - x_n)² / h`` (the trapezoidal mean velocity squared times
c h), so that the energy ledger closes.
"""

from __future__ import annotations

import sys
from dataclasses import dataclass
from typing import ClassVar

import numba
import numpy as np

from rubdiag import _check
from rubdiag._kernels.records import D_NEW, P_NEW, SLIDING, X_N, XA_N, XV_N
from rubdiag.simulation._elements import Packed

KIND = 101
N_LOCAL = 1
KINEMATICS = True       # the dashpot reads ẋ
K, C = 0, 1             # parameters
X, X_START = 0, 1       # state: x at the step's end and start (for the books)


@numba.njit(error_model="numpy", inline="always")
def law(e, el, wc, xs, par, es, track, trial, prog, jac):
    r = el[e].row
    x = wc[D_NEW, r]
    x_n = xs[X_N, r]
    cv = prog[0].cv
    xdot = cv * (x - x_n) + prog[0].cvv * xs[XV_N, r] + prog[0].cva * xs[XA_N, r]
    wc[P_NEW, r] = -par[e, K] * x - par[e, C] * xdot
    jac[r, 0] = -par[e, K] - par[e, C] * cv
    trial[e].status = SLIDING
    trial[e].fn = 0.0
    trial[e].ft = 0.0
    trial[e].gap = np.inf
    trial[e].z = 1.0
    trial[e].slip = 0.0
    es[1, e, X] = x
    es[1, e, X_START] = x_n
    return SLIDING


@numba.njit(error_model="numpy", inline="always")
def books(e, el, par, es, track, trial, prog):
    x = es[1, e, X]
    dx = x - es[1, e, X_START]
    h = prog[0].h
    trial[e].elastic = 0.5 * par[e, K] * x * x
    trial[e].dissipated = par[e, C] * dx * dx / h if h > 0.0 else 0.0
    trial[e].w_ramp = 0.0
    trial[e].w_surface = 0.0
    trial[e].cone = 0.0


@dataclass(frozen=True, kw_only=True)
class GroundSpring:
    """A spring ``stiffness`` (N/m) and a dashpot ``damping`` (N s/m) from ``dof`` to ground."""

    dof: int
    stiffness: float
    damping: float = 0.0

    kernel: ClassVar = sys.modules[__name__]

    def __post_init__(self):
        object.__setattr__(self, "dof", int(_check.indices("GroundSpring.dof", [self.dof])[0]))
        _check.number("GroundSpring.stiffness", self.stiffness, lo=0.0, allowed=">= 0 N/m")
        _check.number("GroundSpring.damping", self.damping, lo=0.0, allowed=">= 0 N s/m")

    def pack(self, omega: float, ramp=None) -> Packed:
        return Packed(KIND, np.array([[self.dof, -1]]), np.eye(1),
                      np.array([self.stiffness, self.damping], dtype=float), np.zeros(2),
                      False, 0.0)

    def stiffness_ratio(self, w: np.ndarray) -> float:
        return 0.0      # no step requirement

    def multiplier_stiffness(self, w: np.ndarray, boost: float) -> float:
        return 0.0

    def dofs(self) -> np.ndarray:
        return np.array([self.dof])
