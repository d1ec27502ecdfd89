"""One Newmark step's algebra: the right-hand side of the increment equation, the increment
with the elements' forces, and the state at the step's end (the equations are in
:mod:`rubdiag._kernels.newmark`'s docstring).

A step solves ``K_eff Δq = rhs`` for the linear predictor (:func:`rhs_average`, or
:func:`rhs_general` and :func:`load_increment` for γ ≠ 1/2), adds the elements' change of
force ``Δq += S Δp`` once their solve converged (:func:`increment`) and moves the state on
(:func:`new_state`).
"""

from __future__ import annotations

from rubdiag._kernels.elements import add_bt_p
from rubdiag._kernels.sparse_lu import csr_matvec
from rubdiag._numba import njit

__all__ = ["add_force", "increment", "load_increment", "new_state", "rhs_average",
           "rhs_general"]

#: The smallest normal float64: below it, numbers are subnormal.
_TINY = 2.2250738585072014e-308


@njit(error_model="numpy", inline="always")
def add_force(load_dofs, load_re, load_im, load_groups, group_factors, end, scale, out):
    """``out[load_dofs] += scale f(t)`` at the step's start or end.

    Parameters
    ----------
    load_dofs : ndarray (n_terms) int
        Each load term's DOF.
    load_re, load_im : ndarray (n_terms)
        Each term's complex amplitude (N): ``f_k(t) = load_re Re z - load_im Im z``.
    load_groups : ndarray (n_terms) int
        Each term's group, whose factor z it takes.
    group_factors : ndarray (G, 4)
        Each group's factor (Re z, Im z) at the step's start and at its end
        (:func:`~rubdiag._kernels.load.load_factors`).
    end : int
        0 for the step's start, 2 for its end.
    scale : float
        The factor the force is added with.
    out : ndarray (n)
        Added to in place (N).
    """
    for k in range(load_dofs.shape[0]):
        g = load_groups[k]
        out[load_dofs[k]] += scale * (load_re[k] * group_factors[g, end]
                                      - load_im[k] * group_factors[g, end + 1])


@njit(error_model="numpy")
def rhs_average(h, momentum, elastic_force, local_force, load_dofs, load_re, load_im,
                load_groups, group_factors, elements, row_dofs, transforms, rhs):
    """The right-hand side of the increment equation for average acceleration:
    ``f_{n+1} + f_n + 2 Bᵀ p_n + 4/h M v_n - 2 K q_n``, no product.

    Parameters
    ----------
    h : float
        The step (s).
    momentum, elastic_force : ndarray (n)
        M v_n (N s) and K q_n (N).
    local_force : ndarray (m)
        The elements' local forces p_n (N).
    load_dofs, load_re, load_im, load_groups, group_factors : ndarray
        The load (:func:`add_force`).
    elements, row_dofs, transforms : ndarray
        The elements' records and local coordinates
        (:func:`~rubdiag._kernels.elements.local_coords`).
    rhs : ndarray (n)
        The right-hand side (N), overwritten.
    """
    # r_n = M (4/h v + 2 a) + 2 C v = 4/h M v + 2 (f_n + B^T p_n - K q)
    c4 = 4.0 / h
    for i in range(rhs.shape[0]):
        rhs[i] = c4 * momentum[i] - 2.0 * elastic_force[i]
    # + Δf + 2 f_n = f_{n+1} + f_n
    add_force(load_dofs, load_re, load_im, load_groups, group_factors, 0, 1.0, rhs)
    add_bt_p(elements, row_dofs, transforms, local_force, 2.0, rhs)
    add_force(load_dofs, load_re, load_im, load_groups, group_factors, 2, 1.0, rhs)


@njit(error_model="numpy")
def rhs_general(run, h, v, a, m_ptr, m_idx, m_val, c_ptr, c_idx, c_val, x, c_x, rhs):
    """The right-hand side of the increment equation for Newmark β, γ without the load:
    ``M (v_n / (β h) + a_n / (2β)) + C (γ/β v_n - h (1 - γ/(2β)) a_n)``;
    :func:`load_increment` adds Δf.

    Parameters
    ----------
    run : ndarray (1) records.RUN
        The run's parameters (β, γ).
    h : float
        The step (s).
    v, a : ndarray (n)
        Velocity (m/s) and acceleration (m/s²) at the step's start.
    m_ptr, m_idx, m_val : ndarray
        M in CSR (kg).
    c_ptr, c_idx, c_val : ndarray
        C in CSR (N s/m).
    x, c_x : ndarray (n)
        Work.
    rhs : ndarray (n)
        The right-hand side (N), overwritten.
    """
    beta = run[0].beta
    gamma = run[0].gamma
    ca2 = 1.0 / (beta * h)
    ca3 = 1.0 / (2.0 * beta)
    for i in range(rhs.shape[0]):
        x[i] = ca2 * v[i] + ca3 * a[i]
    csr_matvec(m_ptr, m_idx, m_val, x, rhs)
    cy1 = gamma / beta
    cy2 = -h * (1.0 - gamma / (2.0 * beta))
    for i in range(rhs.shape[0]):
        x[i] = cy1 * v[i] + cy2 * a[i]
    csr_matvec(c_ptr, c_idx, c_val, x, c_x)
    for i in range(rhs.shape[0]):
        rhs[i] += c_x[i]


@njit(error_model="numpy")
def load_increment(load_dofs, load_re, load_im, load_groups, group_factors, rhs):
    """``rhs += f(t_1) - f(t_n)``.

    Parameters
    ----------
    load_dofs, load_re, load_im, load_groups, group_factors : ndarray
        The load (:func:`add_force`).
    rhs : ndarray (n)
        Added to in place (N).
    """
    add_force(load_dofs, load_re, load_im, load_groups, group_factors, 0, -1.0, rhs)
    add_force(load_dofs, load_re, load_im, load_groups, group_factors, 2, 1.0, rhs)


@njit(inline="always")
def increment(level, responses, local_force, p_new, elements, row_dofs, transforms, dp, dq,
              rhs):
    """The accepted step's increment ``dq += S Δp`` and ``rhs += Bᵀ Δp``: the right-hand
    side ``K_eff dq = rhs`` actually solved.

    Parameters
    ----------
    level : int
        The step's level (S of its step size).
    responses : ndarray (L, m, n)
        S = K_eff^-1 Bᵀ per level, transposed (m/N).
    local_force, p_new : ndarray (m)
        The elements' local forces at the step's start and end (N).
    elements, row_dofs, transforms : ndarray
        The elements' records and local coordinates.
    dp : ndarray (m)
        Δp = ``p_new - local_force`` (N), written.
    dq : ndarray (n)
        The linear predictor's increment (m), then the step's.
    rhs : ndarray (n)
        The predictor's right-hand side (N), then the step's.
    """
    for j in range(dp.shape[0]):
        dpj = p_new[j] - local_force[j]
        dp[j] = dpj
        if dpj != 0.0:
            for i in range(dq.shape[0]):
                dq[i] += dpj * responses[level, j, i]
    add_bt_p(elements, row_dofs, transforms, dp, 1.0, rhs)


@njit(error_model="numpy", inline="always")
def _normal(x):
    return x if abs(x) >= _TINY else 0.0


@njit(error_model="numpy", inline="always")
def new_state(beta, gamma, h, dq, m_dq, k_dq, q, v, a, momentum, elastic_force):
    """The state at the end of the accepted step from dq and its products.

    A free, damped DOF (the casing after the last contact) decays into subnormal numbers,
    which cost ~100 cycles per operation on x86: they are flushed to 0.

    Parameters
    ----------
    beta, gamma : float
        Newmark's β and γ.
    h : float
        The step (s).
    dq : ndarray (n)
        The step's displacement increment (m).
    m_dq, k_dq : ndarray (n)
        M dq (kg m) and K dq (N).
    q, v, a : ndarray (n)
        Displacement (m), velocity (m/s), acceleration (m/s²): the step's start, then its
        end.
    momentum, elastic_force : ndarray (n)
        M v (N s) and K q (N), moved on likewise (M v right for average acceleration only:
        the caller recomputes it otherwise).
    """
    ca0 = 1.0 / (beta * h * h)
    ca2 = 1.0 / (beta * h)
    ca3 = 1.0 / (2.0 * beta) - 1.0
    cmv = gamma / (beta * h)
    for i in range(q.shape[0]):
        an = ca0 * dq[i] - ca2 * v[i] - ca3 * a[i]
        v[i] = _normal(v[i] + h * ((1.0 - gamma) * a[i] + gamma * an))
        a[i] = _normal(an)
        q[i] = _normal(q[i] + dq[i])
        elastic_force[i] = _normal(elastic_force[i] + k_dq[i])
        # M v_{n+1} = 2/h M dq - M v_n (trapezoid)
        momentum[i] = _normal(cmv * m_dq[i] - momentum[i])
