"""A plain journal bearing (kind 5): the nonlinear short-bearing oil film, velocity-dependent.

Two local coordinates: the journal centre relative to the bearing housing, ``x = q[journal
y] - q[housing y]`` and ``y = q[journal z] - q[housing z]`` (housing -1: ground), so that
the journal turns from x towards y at the shaft's speed ``progress[0].omega``. The law is the
film force of :func:`rubdiag._fluidfilm.step_film_terms` (the short-bearing π-film force of
:func:`~rubdiag._fluidfilm.film_terms` with as many Gauss points as its eccentricity needs; its
model and sources there) at the trial position and at the velocity the Newmark relation
gives, ``ẋ₁ = cv (x − x_n) + cvv ẋ_n + cva ẍ_n``; its Jacobian is
``∂p/∂x + cv ∂p/∂ẋ``. Always engaged (status 2); ``gap`` is the thinnest film over the
clearance (≤ 0: the journal left its clearance, where the short-bearing force is not
physical: a run refuses a start there, and a dataset row records the thinnest film as
``min_film_ratio``).

Books (kept by the law, as the crack does): the film stores no energy; the work it does on
the structure over a step, ``½ (p_n + p₁)·(x₁ − x_n)`` (the trapezoidal rule, exact for the
average-acceleration scheme's mean velocity), is booked with the opposite sign as the
element's dissipation — negative where the film feeds the whirl. At rest (h = 0) none.
"""

from __future__ import annotations

from rubdiag._fluidfilm import step_film_terms
from rubdiag._kernels.records import D_NEW, P_NEW, SLIDING, X_N, XA_N, XV_N
from rubdiag._numba import njit

__all__ = ["KIND", "KINEMATICS", "N_LOCAL", "PARAMS", "STATE", "books", "law"]

KIND = 5
N_LOCAL = 2
KINEMATICS = True
#: the parameter row (Pa s, m, m, m): viscosity, journal radius, length, radial clearance
PARAMS = ("mu", "radius", "length", "clearance")
MU, RADIUS, LENGTH, CLEARANCE = range(len(PARAMS))
#: the state: position and force at the step's end (m, N), for the books
STATE = ("x", "y", "px", "py")
X, Y, PX, PY = range(len(STATE))


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
    y = local_work[D_NEW, r + 1]
    cv = progress[0].cv
    cvv = progress[0].cvv
    cva = progress[0].cva
    vx = (cv * (x - local_state[X_N, r]) + cvv * local_state[XV_N, r]
          + cva * local_state[XA_N, r])
    vy = (cv * (y - local_state[X_N, r + 1]) + cvv * local_state[XV_N, r + 1]
          + cva * local_state[XA_N, r + 1])
    fx, fy, fxx, fyx, fxy, fyy, fxu, fyu, fxv, fyv, thinnest = step_film_terms(
        x, y, vx, vy, progress[0].omega, parameters[e, MU], parameters[e, RADIUS],
        parameters[e, LENGTH], parameters[e, CLEARANCE])
    local_work[P_NEW, r] = fx
    local_work[P_NEW, r + 1] = fy
    jacobian[r, 0] = fxx + cv * fxu
    jacobian[r, 1] = fxy + cv * fxv
    jacobian[r + 1, 0] = fyx + cv * fyu
    jacobian[r + 1, 1] = fyy + cv * fyv
    trial[e].status = SLIDING
    trial[e].fn = 0.0
    trial[e].ft = 0.0
    trial[e].gap = thinnest
    trial[e].z = 1.0
    trial[e].slip = 0.0
    element_state[1, e, X] = x
    element_state[1, e, Y] = y
    element_state[1, e, PX] = fx
    element_state[1, e, PY] = fy
    work = 0.5 * ((element_state[0, e, PX] + fx) * (x - element_state[0, e, X])
                  + (element_state[0, e, PY] + fy) * (y - element_state[0, e, Y]))
    trial[e].elastic = 0.0
    trial[e].dissipated = -work if progress[0].h > 0.0 else 0.0
    trial[e].w_ramp = 0.0
    trial[e].w_surface = 0.0
    trial[e].cone = 0.0
    return SLIDING


@njit(error_model="numpy", inline="always")
def books(e, elements, parameters, element_state, track, trial, progress):
    """Nothing: the law keeps its books (module docstring).

    Parameters
    ----------
    e : int
        The element.
    elements, parameters, element_state, track, trial, progress : ndarray
        As for :func:`rubdiag._kernels.elements.element_books`.
    """
