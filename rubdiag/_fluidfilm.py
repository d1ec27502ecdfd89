"""Plain journal bearings: the nonlinear short-bearing film force, one formula for two uses.

The formula (:func:`film_force`, a Numba function) gives the force the oil film exerts on the
journal at any position and velocity, and its Jacobian. :func:`linearised_coefficients`
calls it at the static equilibrium, where its Jacobian is the speed-dependent, cross-coupled
stiffness and damping of the bearing; the element of the time integrator evaluates the same
integral at every Newton iteration through :func:`step_film_terms`, with as few Gauss points
as the eccentricity needs (the same terms to round-off, at a tenth of the cost). The
reference keeps its own arithmetic: the critical speeds and thresholds that define dataset
runs come from it, to the bit. This module imports nothing of rubdiag but Numba's set-up, so
that the kernels and the modal layer may both use it.

Model: the short-bearing (Ocvirk) approximation of Reynolds' equation, in which the axial
pressure gradient dominates (L/D small; DuBois & Ocvirk, NACA Report 1157, 1953), with the
π-film (Gümbel) cavitation condition: where the film pressure would be negative it is zero
(ambient). With the journal centre at (x, y) relative to the bearing centre (m), the film
thickness at the angle θ from x towards y is ``h = c − x cos θ − y sin θ`` (c the radial
clearance) and, for a journal turning at ω from x towards y,

    p(θ, z) = (3 μ / h³) (z² − L²/4) G(θ),   G = ω ∂h/∂θ + 2 ∂h/∂t
            = (ω x − 2 ẏ) sin θ − (ω y + 2 ẋ) cos θ,

positive where G < 0: a half circle θ ∈ (α − π/2, α + π/2). Over the length L the pressure
integrates to ``−μ L³ G / (2 h³)``, so the force on the journal is

    F = (μ R L³ / 2) ∫_{G<0} G(θ) (cos θ, sin θ) / h³ dθ.

Its derivatives need no term from the moving ends of the half circle, where G = 0. The
integral is evaluated by :data:`N_GAUSS`-point Gauss–Legendre quadrature over the half circle
(relative error against adaptive quadrature of the same integral, for moving journals:
2e-15 up to ε = 0.8, 4e-14 at 0.9, 5e-10 at 0.95, 4e-7 at 0.98; ``tests/test_fluidfilm.py``).
At the static equilibrium it reduces to the closed forms of the short π-film bearing: a
radial force ``μ R L³ ω ε² / (c² (1−ε²)²)`` towards the centre and a tangential one
``π μ R L³ ω ε / (4 c² (1−ε²)^{3/2})``, the load
``W = (μ ω R L³ / (4 c²)) ε √(16 ε² + π² (1 − ε²)) / (1 − ε²)²`` and the attitude angle
``tan φ = π √(1 − ε²) / (4 ε)`` (Friswell, Penny, Garvey & Lees, *Dynamics of Rotating
Machines*, Cambridge University Press 2010, section 5.5.1).

Units SI: m, m/s, rad/s, Pa·s, N.
"""

from __future__ import annotations

import math

import numpy as np

from rubdiag._numba import njit

__all__ = ["N_GAUSS", "STEP_RULES", "attitude_angle", "eccentricity_for_load", "film_force",
           "film_terms", "linearised_coefficients", "load_capacity", "step_film_terms"]

#: quadrature points over the half circle of positive pressure
N_GAUSS = 64
#: The eccentricity search's bracket stays this far inside (0, 1) (the load capacity is 0 at
#: 0 and infinite at 1); its tolerance, a few ulps of a ratio: the root to the last bits.
_ECCENTRICITY_MARGIN = 1e-12
_ECCENTRICITY_TOL = 1e-15
_T, _W = np.polynomial.legendre.leggauss(N_GAUSS)

#: The integrator's Gauss rules, as (largest eccentricity ratio, points): the fewest points
#: that keep every term of :func:`step_film_terms` within round-off of a 400-point rule up
#: to that eccentricity (relative error below 3e-13, as :data:`N_GAUSS` points reach;
#: measured on random moving journals, ``tests/test_fluidfilm.py``: four points fewer miss
#: it); above 0.8, the :data:`N_GAUSS` points of :func:`film_terms`. The twin of
#: :func:`film_terms` spends a tenth of its time: 0.16-0.26 µs instead of 1.7-2.6 µs.
STEP_RULES = ((0.2, 18), (0.3, 20), (0.4, 24), (0.5, 26), (0.6, 30), (0.7, 36), (0.8, 46),
              (math.inf, N_GAUSS))


def _rule_tables():
    """Each step rule's cos φ, sin φ and weight × π/2 (rows, padded with zeros), φ the
    node's angle from the middle of the half circle."""
    out = np.zeros((3, len(STEP_RULES), N_GAUSS))
    for k, (_, n) in enumerate(STEP_RULES):
        t, w = np.polynomial.legendre.leggauss(n)
        out[:, k, :n] = np.cos(0.5 * math.pi * t), np.sin(0.5 * math.pi * t), 0.5 * math.pi * w
    return out


_RULE_COS, _RULE_SIN, _RULE_WEIGHT = _rule_tables()
_RULE_EPS = np.array([eps for eps, _ in STEP_RULES])
_RULE_N = np.array([n for _, n in STEP_RULES])


@njit(error_model="numpy", inline="always")
def film_terms(x, y, vx, vy, omega, mu, radius, length, clearance):
    """The film force and its Jacobian as a tuple of floats, nothing allocated (for the
    element's law, which runs at every Newton iteration): ``(Fx, Fy, ∂Fx/∂x, ∂Fy/∂x,
    ∂Fx/∂y, ∂Fy/∂y, ∂Fx/∂vx, ∂Fy/∂vx, ∂Fx/∂vy, ∂Fy/∂vy, thinnest)`` (:func:`film_force`)."""
    a = omega * x - 2.0 * vy
    b = omega * y + 2.0 * vx
    fx = fy = fxx = fyx = fxy = fyy = fxu = fyu = fxv = fyv = 0.0
    if a == 0.0 and b == 0.0:
        return fx, fy, fxx, fyx, fxy, fyy, fxu, fyu, fxv, fyv, 1.0 - math.hypot(x, y) / clearance
    alpha = math.atan2(-a, b)
    half = 0.5 * math.pi
    scale = 0.5 * mu * radius * length ** 3 * half   # (μ R L³ / 2) dθ/dt of the map
    thinnest = 1.0
    for k in range(N_GAUSS):
        theta = alpha + half * _T[k]
        cs = math.cos(theta)
        sn = math.sin(theta)
        h = clearance - x * cs - y * sn
        thinnest = min(thinnest, h / clearance)
        g = a * sn - b * cs
        w = scale * _W[k]
        h3 = h * h * h
        f = w * g / h3                       # the force's weight at θ
        dx = w * (omega * sn / h3 + 3.0 * g * cs / (h3 * h))
        dy = w * (-omega * cs / h3 + 3.0 * g * sn / (h3 * h))
        du = w * (-2.0 * cs / h3)
        dv = w * (-2.0 * sn / h3)
        fx += f * cs
        fy += f * sn
        fxx += dx * cs
        fyx += dx * sn
        fxy += dy * cs
        fyy += dy * sn
        fxu += du * cs
        fyu += du * sn
        fxv += dv * cs
        fyv += dv * sn
    return fx, fy, fxx, fyx, fxy, fyy, fxu, fyu, fxv, fyv, thinnest


@njit(error_model="numpy", inline="always")
def step_film_terms(x, y, vx, vy, omega, mu, radius, length, clearance):
    """:func:`film_terms` as the time integrator evaluates it at every Newton iteration:
    the same integral, with the fewest Gauss points that its eccentricity needs
    (:data:`STEP_RULES`: round-off of the same terms), the nodes' angles turned from a table
    (two products each instead of a cosine and a sine), and the thinnest film over the half
    circle in closed form (not sampled at the nodes): ``c − max(x cos θ + y sin θ)`` over
    θ ∈ α ± π/2, which is ``c − e`` when the line of centres lies in the half circle, else
    the film at its nearer end."""
    a = omega * x - 2.0 * vy
    b = omega * y + 2.0 * vx
    fx = fy = fxx = fyx = fxy = fyy = fxu = fyu = fxv = fyv = 0.0
    e = math.hypot(x, y)
    if a == 0.0 and b == 0.0:
        return fx, fy, fxx, fyx, fxy, fyy, fxu, fyu, fxv, fyv, 1.0 - e / clearance
    rho = math.hypot(a, b)
    ca = b / rho                 # the middle of the half circle, α = atan2(-a, b)
    sa = -a / rho
    along = x * ca + y * sa      # the journal's position along α and across it
    across = -x * sa + y * ca
    thinnest = 1.0 - (e if along >= 0.0 else abs(across)) / clearance
    k = 0
    while e > _RULE_EPS[k] * clearance:
        k += 1
    scale = 0.5 * mu * radius * length ** 3    # μ R L³ / 2; the weights hold dθ/dt
    for i in range(_RULE_N[k]):
        cp = _RULE_COS[k, i]
        sp = _RULE_SIN[k, i]
        cs = ca * cp - sa * sp   # θ = α + φ
        sn = sa * cp + ca * sp
        h = clearance - x * cs - y * sn
        g = -rho * cp            # a sin θ − b cos θ
        w = scale * _RULE_WEIGHT[k, i] / (h * h * h)
        f = w * g                # the force's weight at θ
        t = 3.0 * f / h
        dx = w * omega * sn + t * cs
        dy = -w * omega * cs + t * sn
        du = -2.0 * w * cs
        dv = -2.0 * w * sn
        fx += f * cs
        fy += f * sn
        fxx += dx * cs
        fyx += dx * sn
        fxy += dy * cs
        fyy += dy * sn
        fxu += du * cs
        fyu += du * sn
        fxv += dv * cs
        fyv += dv * sn
    return fx, fy, fxx, fyx, fxy, fyy, fxu, fyu, fxv, fyv, thinnest


@njit(error_model="numpy")
def film_force(x, y, vx, vy, omega, mu, radius, length, clearance, out):
    """The film force on the journal at (x, y) (m) moving at (vx, vy) (m/s), the journal
    turning at ``omega`` (rad/s, from x towards y): writes ``out`` (2, 5) with ``out[:, 0]``
    the force (Fx, Fy) (N) and ``out[:, 1:5]`` its derivatives by x, y, vx, vy (N/m, N s/m).
    Returns the smallest film thickness over the half circle of pressure over c (<= 0: the
    journal touches or leaves its clearance; the force is then not physical)."""
    t = film_terms(x, y, vx, vy, omega, mu, radius, length, clearance)
    for j in range(5):
        out[0, j] = t[2 * j]
        out[1, j] = t[2 * j + 1]
    return t[10]


def load_capacity(eccentricity_ratio: float, omega: float, mu: float, radius: float,
                  length: float, clearance: float) -> float:
    """The static load W (N) the film carries at eccentricity ratio ε (closed form, module
    docstring)."""
    e = eccentricity_ratio
    return (mu * omega * radius * length ** 3 / (4.0 * clearance ** 2) * e
            * math.sqrt(16.0 * e * e + math.pi ** 2 * (1.0 - e * e)) / (1.0 - e * e) ** 2)


def attitude_angle(eccentricity_ratio: float) -> float:
    """The angle (rad) between the load and the line of centres at ε (closed form)."""
    e = eccentricity_ratio
    return math.atan2(math.pi * math.sqrt(1.0 - e * e), 4.0 * e)


def eccentricity_for_load(load: float, omega: float, mu: float, radius: float,
                          length: float, clearance: float) -> float:
    """The eccentricity ratio in (0, 1) at which the film carries ``load`` (N, > 0): the root
    of :func:`load_capacity` (which grows monotonically from 0 to infinity with ε)."""
    from scipy.optimize import brentq

    if not load > 0.0 or not omega > 0.0:
        raise ValueError(f"load = {load!r} N and omega = {omega!r} rad/s (allowed: both > 0)")
    return brentq(lambda e: load_capacity(e, omega, mu, radius, length, clearance) - load,
                  _ECCENTRICITY_MARGIN, 1.0 - _ECCENTRICITY_MARGIN,
                  xtol=_ECCENTRICITY_TOL, rtol=_ECCENTRICITY_TOL)


def linearised_coefficients(load: float, omega: float, mu: float, radius: float,
                            length: float, clearance: float, direction=(-1.0, 0.0)):
    """The bearing's stiffness K and damping C (2×2, N/m and N s/m, in the x, y frame of
    :func:`film_force`) at the static equilibrium under ``load`` (N) acting on the journal
    along the unit vector ``direction`` (default −x), and the journal's static position
    (x, y) (m): ``(K, C, position)``. K = −∂F/∂(x, y), C = −∂F/∂(ẋ, ẏ) of the same
    :func:`film_force` the time integrator uses."""
    eps = eccentricity_for_load(load, omega, mu, radius, length, clearance)
    d = np.asarray(direction, dtype=float)
    d = d / np.hypot(*d)
    # the journal sits at ε c along the load turned by the attitude angle in the direction
    # of rotation (from x towards y): the film force then balances the load
    phi = attitude_angle(eps)
    turn = np.array([[math.cos(phi), -math.sin(phi)], [math.sin(phi), math.cos(phi)]])
    position = eps * clearance * (turn @ d)
    out = np.zeros((2, 5))
    film_force(position[0], position[1], 0.0, 0.0, omega, mu, radius, length, clearance, out)
    return -out[:, 1:3], -out[:, 3:5], position
