"""Element matrices: Timoshenko shaft, planar Timoshenko frame, rigid disc.

All beam matrices come from one place: the interdependent interpolation of a Timoshenko
beam (cubic deflection, quadratic rotation, exact for a uniform beam under end loads;
Friedman & Kosmatka, Computers & Structures 47, 1993), integrated by Gauss quadrature that
is exact for the polynomial degrees involved. With φ = 12EI/(κGAL²) → 0 they reduce to the
Euler-Bernoulli Hermite element.

DOF order
---------
Shaft element (rotation axis x), 8 DOF: ``[u_y1, u_z1, θ_y1, θ_z1, u_y2, u_z2, θ_y2, θ_z2]``
with θ_z = du_y/dx and θ_y = −du_z/dx (right-handed small rotations).

Planar frame element in the y-z plane, 6 DOF: ``[u_y1, u_z1, φ_x1, u_y2, u_z2, φ_x2]``.
"""

from __future__ import annotations

import functools
import math

import numpy as np

__all__ = [
    "circular_section",
    "disc_matrices",
    "frame_element",
    "rectangular_section",
    "shaft_element",
    "timoshenko_shape",
]

# Gauss-Legendre on [0, 1]: 6 points integrate degree 11 exactly (we need degree 6).
_XG, _WG = np.polynomial.legendre.leggauss(6)
_XG = 0.5 * (_XG + 1.0)
_WG = 0.5 * _WG


def circular_section(d_outer: float, d_inner: float, nu: float):
    """Area, second moment, polar moment and Cowper's shear coefficient of a tube."""
    area = math.pi / 4.0 * (d_outer**2 - d_inner**2)
    inertia = math.pi / 64.0 * (d_outer**4 - d_inner**4)
    m2 = (d_inner / d_outer) ** 2
    kappa = 6.0 * (1 + nu) * (1 + m2) ** 2 / ((7 + 6 * nu) * (1 + m2) ** 2 + (20 + 12 * nu) * m2)
    return area, inertia, 2.0 * inertia, kappa


def rectangular_section(width: float, height: float, nu: float):
    """Area, second moment for bending across ``height`` and Cowper's shear coefficient."""
    return width * height, width * height**3 / 12.0, 10.0 * (1 + nu) / (12 + 11 * nu)


def timoshenko_shape(xi: float, length: float, phi: float):
    """Shape functions of the Timoshenko beam for DOFs ``(v1, θ1, v2, θ2)``, θ = dv/dx.

    Returns ``(Nv, dNv, Nθ, dNθ)`` at ``xi = x/L``: deflection, its x-derivative, rotation
    and its x-derivative, each an array of 4.
    """
    L, f, c = length, phi, 1.0 / (1.0 + phi)
    x2, x3 = xi * xi, xi * xi * xi
    nv = c * np.array([2 * x3 - 3 * x2 - f * xi + 1 + f,
                       L * (x3 - (2 + f / 2) * x2 + (1 + f / 2) * xi),
                       -2 * x3 + 3 * x2 + f * xi,
                       L * (x3 - (1 - f / 2) * x2 - (f / 2) * xi)])
    dnv = c * np.array([(6 * x2 - 6 * xi - f) / L,
                        3 * x2 - (4 + f) * xi + 1 + f / 2,
                        (-6 * x2 + 6 * xi + f) / L,
                        3 * x2 - (2 - f) * xi - f / 2])
    nt = c * np.array([6 * (x2 - xi) / L,
                       3 * x2 - (4 + f) * xi + 1 + f,
                       -6 * (x2 - xi) / L,
                       3 * x2 - (2 - f) * xi])
    dnt = c * np.array([6 * (2 * xi - 1) / L**2,
                        (6 * xi - 4 - f) / L,
                        -6 * (2 * xi - 1) / L**2,
                        (6 * xi - 2 + f) / L])
    return nv, dnv, nt, dnt


# Scatter the 4 bending DOFs (v1, θ1, v2, θ2) of each plane into the shaft's 8 DOFs.
# x-y plane: v = u_y, θ = θ_z.  x-z plane: v = u_z, θ = -θ_y (hence the sign).
_XY = np.zeros((4, 8))
_XY[[0, 1, 2, 3], [0, 3, 4, 7]] = 1.0
_XZ = np.zeros((4, 8))
_XZ[[0, 1, 2, 3], [1, 2, 5, 6]] = [1.0, -1.0, 1.0, -1.0]


@functools.lru_cache(maxsize=1024)
def shaft_element(length: float, d_outer: float, d_inner: float, E: float, nu: float,
                  rho: float):
    """Mass, stiffness and gyroscopic matrices (8×8) of a Timoshenko shaft element (kept
    per argument set, read-only: the rig variants of a design share their elements).

    ``G`` is for a unit spin speed: the equations of motion are
    ``M q'' + (C + Ω G) q' + K q = f`` with ``G`` skew-symmetric. Rotary inertia is included
    in ``M`` (diametral ρI per unit length) and ``G`` holds the polar inertia ρ·2I.
    """
    area, inertia, polar, kappa = circular_section(d_outer, d_inner, nu)
    shear = E / (2 * (1 + nu))
    phi = 12.0 * E * inertia / (kappa * shear * area * length**2)
    M, K, G = np.zeros((8, 8)), np.zeros((8, 8)), np.zeros((8, 8))
    for xi, w in zip(_XG, _WG, strict=True):
        nv, dnv, nt, dnt = timoshenko_shape(xi, length, phi)
        uy, uz = nv @ _XY, nv @ _XZ
        rz, ry = nt @ _XY, -(nt @ _XZ)      # θ_z and θ_y fields
        duy, duz = dnv @ _XY, dnv @ _XZ
        kz, ky = dnt @ _XY, -(dnt @ _XZ)    # curvatures
        wl = w * length
        M += wl * (rho * area * (np.outer(uy, uy) + np.outer(uz, uz))
                   + rho * inertia * (np.outer(ry, ry) + np.outer(rz, rz)))
        shear_y, shear_z = duy - rz, duz + ry   # γ_xy = u_y' − θ_z, γ_xz = u_z' + θ_y
        K += wl * (E * inertia * (np.outer(ky, ky) + np.outer(kz, kz))
                   + kappa * shear * area * (np.outer(shear_y, shear_y)
                                             + np.outer(shear_z, shear_z)))
        G += wl * rho * polar * (np.outer(ry, rz) - np.outer(rz, ry))
    return _read_only(M, K, G)


@functools.lru_cache(maxsize=1024)
def frame_element(length: float, angle: float, width: float, height: float, E: float,
                  nu: float, rho: float):
    """Mass and stiffness (6×6, global y-z axes) of a planar Timoshenko frame element (kept
    per argument set, read-only, as :func:`shaft_element`).

    The element runs from node 1 at ``angle`` (rad, from +y towards +z); its section is
    ``width`` out of plane by ``height`` in plane (the bending thickness). Consistent mass
    with rotary inertia; the axial part is a linear bar.
    """
    area, inertia, kappa = rectangular_section(width, height, nu)
    shear = E / (2 * (1 + nu))
    phi = 12.0 * E * inertia / (kappa * shear * area * length**2)
    bend = [1, 2, 4, 5]
    M, K = np.zeros((6, 6)), np.zeros((6, 6))
    for xi, w in zip(_XG, _WG, strict=True):
        nv, dnv, nt, dnt = timoshenko_shape(xi, length, phi)
        v, dv, t, dt = (np.zeros(6) for _ in range(4))
        v[bend], dv[bend], t[bend], dt[bend] = nv, dnv, nt, dnt
        u = np.zeros(6)
        u[[0, 3]] = 1.0 - xi, xi
        wl = w * length
        M += wl * rho * (area * (np.outer(u, u) + np.outer(v, v)) + inertia * np.outer(t, t))
        gamma = dv - t
        K += wl * (E * inertia * np.outer(dt, dt) + kappa * shear * area * np.outer(gamma, gamma))
    K[np.ix_([0, 3], [0, 3])] += E * area / length * np.array([[1.0, -1.0], [-1.0, 1.0]])
    c, s = math.cos(angle), math.sin(angle)
    node = np.array([[c, s, 0.0], [-s, c, 0.0], [0.0, 0.0, 1.0]])   # global -> local
    T = np.kron(np.eye(2), node)
    return _read_only(T.T @ M @ T, T.T @ K @ T)


def _read_only(*matrices: np.ndarray) -> tuple[np.ndarray, ...]:
    for matrix in matrices:
        matrix.flags.writeable = False
    return matrices


def disc_matrices(mass: float, polar: float, diametral: float):
    """Mass and unit-speed gyroscopic matrices (4×4) of a rigid disc on a shaft node.

    DOFs ``[u_y, u_z, θ_y, θ_z]``; from the disc's angular momentum,
    I_d θ_y'' + Ω I_p θ_z' = M_y and I_d θ_z'' − Ω I_p θ_y' = M_z.
    """
    M = np.diag([mass, mass, diametral, diametral])
    G = np.zeros((4, 4))
    G[2, 3], G[3, 2] = polar, -polar
    return M, G
