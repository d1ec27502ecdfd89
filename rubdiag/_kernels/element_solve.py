"""The elements' problem of one Newmark step, solved in the Schur complement.

With the linear predictor's local displacements ``d_lin`` (the elements' forces frozen at
their values at the step's start, p_n) and the flexibility ``W = B K_eff^-1 Bᵀ`` at the
local coordinates, the step's local displacements d solve ``R(d) = d - d_lin - W (p(d) -
p_n) = 0``, with each element's law p(d) by its kind (the seam,
:func:`~rubdiag._kernels.elements.element_laws`). :func:`solve_elements` solves it by
semi-smooth Newton, with an augmented Lagrangian around it for the elements that ask for
one; the codes it returns are the seam's (:mod:`rubdiag._kernels.elements`).
"""

from __future__ import annotations

import numpy as np

from rubdiag._kernels.elements import (
    AUGMENT_FAILED,
    AUGMENT_PENDING,
    CONVERGED,
    NEWTON_FAILED,
    NONFINITE,
    SINGULAR,
    element_books,
    element_laws,
)
from rubdiag._kernels.records import D_LIN, D_NEW, OPEN, P_NEW, V2, V
from rubdiag._numba import njit

__all__ = ["solve_elements"]

_PLAIN_NEWTON = 8          # full Newton steps before some relaxed ones
_RELAX = (0.5, 0.3, 0.7)   # varied, so that a relaxed step cannot fall into a cycle of its own


@njit(error_model="numpy", inline="always")
def _dense_solve(matrix, local_work, row, m, index_work, off):
    """Solve the leading m x m block ``A x = b`` in place by LU with partial pivoting.

    Parameters
    ----------
    matrix : ndarray (>= m, >= m)
        A, overwritten by its factors.
    local_work : ndarray (WC_SIZE, >= m)
        ``b = local_work[row, :m]``, overwritten by x.
    row : int
        The row of ``local_work`` that holds b.
    m : int
        The size of the block.
    index_work : ndarray int
        The pivots go to ``index_work[off:off + m]``.
    off : int
        Where.

    Returns
    -------
    bool
        False if A is numerically singular.
    """
    for k in range(m):
        p = k
        amax = abs(matrix[k, k])
        for i in range(k + 1, m):
            if abs(matrix[i, k]) > amax:
                amax = abs(matrix[i, k])
                p = i
        if amax == 0.0 or not np.isfinite(amax):
            return False
        index_work[off + k] = p
        if p != k:
            for j in range(m):
                tmp = matrix[k, j]
                matrix[k, j] = matrix[p, j]
                matrix[p, j] = tmp
            tmp = local_work[row, k]
            local_work[row, k] = local_work[row, p]
            local_work[row, p] = tmp
        inv = 1.0 / matrix[k, k]
        for i in range(k + 1, m):
            f = matrix[i, k] * inv
            if f != 0.0:
                matrix[i, k] = f
                for j in range(k + 1, m):
                    matrix[i, j] -= f * matrix[k, j]
                local_work[row, i] -= f * local_work[row, k]
    for i in range(m - 1, -1, -1):
        acc = local_work[row, i]
        for j in range(i + 1, m):
            acc -= matrix[i, j] * local_work[row, j]
        local_work[row, i] = acc / matrix[i, i]
    return True


@njit(error_model="numpy", inline="always")
def _w_jac(flexibility, jacobian, i, rj, r0, n):
    """``(W Jp)[i, rj]``: row i of W times column rj of the block-diagonal Jacobian (the
    block of rj's element, rows ``r0 .. r0 + n - 1``).

    Parameters
    ----------
    flexibility : ndarray (m, m)
        W (m/N).
    jacobian : ndarray (m, N_LOCAL_MAX)
        Each element's block of dp/dx (N/m).
    i, rj : int
        The row of W and the column of the Jacobian.
    r0, n : int
        The first row and the size of rj's element.

    Returns
    -------
    float
    """
    cj = rj - r0
    acc = flexibility[i, r0] * jacobian[r0, cj]
    if n == 2:
        return acc + flexibility[i, r0 + 1] * jacobian[r0 + 1, cj]
    for k in range(1, n):
        acc += flexibility[i, r0 + k] * jacobian[r0 + k, cj]
    return acc


# Complexity (C901) allowed: one Newton loop inside one augmentation loop, called per trial
# step; a part split off into a call inside the loops brought reference counting back
# (elements.py's note)
@njit(error_model="numpy")
def solve_elements(flexibility, local_work, local_force, local_state, elements, parameters,  # noqa: C901
                   augment_stiffness, element_state, track, trial, run, progress, jacobian,
                   index_work, newton_matrix):
    """Solve the elements' problem of one Newmark step in the Schur complement.

    Unknown: the local displacements d. With ``d_lin`` those of the linear predictor
    (element forces frozen at p_n) and ``W = B K_eff^-1 Bᵀ``, the step's problem is ``R(d) =
    d - d_lin - W (p(d) - p_n) = 0``, solved by (semi-smooth) Newton with ``J = I - W
    dp/dd``. Only the rows of elements whose law is engaged enter the dense solve; the other
    rows are updated explicitly.

    Augmented Lagrangian (the study's eq. 2): after each converged Newton solve, every
    engaged element with ``aug`` and ``|gap| >= eps`` updates its multiplier ``lam <- max(0,
    lam - aug_k (gap + aug_shift eps))`` (``aug_k``: its ``augment_stiffness``) and the Newton
    solve is repeated, until every engaged augmented element is in the band ``-eps < g <=
    0`` (or ``max_aug`` updates; then ``AUGMENT_FAILED`` if ``aug_strict`` else
    ``AUGMENT_PENDING``). Eq. (2) literally is ``aug_k = k_N``, ``aug_shift = 0``: its
    iterates creep towards ``g = 0`` by a factor ``1 / (1 + k_N W_ee)`` per update and stop
    just inside the band. A larger ``aug_k`` (up to the step's dynamic stiffness at the
    contact) gets there in a few updates; aiming at ``-aug_shift eps`` instead of 0 keeps
    the landing point near where eq. (2) stops instead of pulling the contact to ``g = 0``
    within one step (which, with the trapezoidal rule, injects a large spurious rebound).
    The multipliers live in ``trial.lam``.

    Parameters
    ----------
    flexibility : ndarray (m, m)
        W at the step's level (m/N).
    local_work : ndarray (WC_SIZE, m)
        Reads ``d_lin`` (row ``D_LIN``, m); writes d (row ``D_NEW``, m) and p(d) (row
        ``P_NEW``, N); rows ``V`` and ``V2`` are work.
    local_force : ndarray (m)
        p_n, the local forces at the step's start (N).
    local_state, elements, parameters, element_state, track, trial, progress : ndarray
        As for :func:`~rubdiag._kernels.elements.element_laws`; ``trial`` ends with the
        books of the solution (:func:`~rubdiag._kernels.elements.element_books`).
    augment_stiffness : ndarray (n_e)
        Each element's multiplier update stiffness at the step's level (N/m).
    run : ndarray (1) records.RUN
        The run's parameters (tolerance (m), iteration caps, the augmentation's settings).
    jacobian : ndarray (m, N_LOCAL_MAX)
        Each element's block of dp/dx (N/m), written.
    index_work : ndarray (>= 5 m) int
        Work: the engaged rows, the pivots, each engaged row's element's first row and
        size, and the rows whose force changed.
    newton_matrix : ndarray (m, m)
        Work: the Newton matrix of the engaged rows.

    Returns
    -------
    tuple of int
        ``(code, newton_iterations, augment_updates, worst_row)``: a code of
        :mod:`~rubdiag._kernels.elements` (``CONVERGED`` …) and the local row of the largest
        residual (-1: none).
    """
    tol = run[0].newton_tol
    max_newton = run[0].max_newton
    max_aug = run[0].max_aug
    strict = run[0].aug_strict != 0
    shift = run[0].aug_shift
    m2 = local_work.shape[1]
    n_elements = elements.shape[0]
    for i in range(m2):
        local_work[D_NEW, i] = local_work[D_LIN, i]
    n_it = 0
    n_aug = 0
    worst = -1
    while True:
        it = 0
        while True:
            # law evaluation; the engaged elements' rows in index_work[:ma]
            element_laws(elements, local_work, local_state, parameters, element_state, track,
                         trial, progress, jacobian)
            ma = 0
            for e in range(n_elements):
                st = trial[e].status
                r0 = elements[e].row
                n = elements[e].n
                if st != OPEN:
                    for r in range(r0, r0 + n):
                        index_work[ma] = r
                        index_work[2 * m2 + ma] = r0
                        index_work[3 * m2 + ma] = n
                        ma += 1
            # residual R = d - d_lin - W (p - p_n), over the rows whose force changed (in
            # index_work[4 m2:4 m2 + nz]: an open contact's is zero, so a rotor on its films alone
            # sums 4 columns of W, not 20)
            nz = 0
            for i in range(m2):
                dpi = local_work[P_NEW, i] - local_force[i]
                local_work[V2, i] = dpi
                if dpi != 0.0:
                    index_work[4 * m2 + nz] = i
                    nz += 1
            rmax = 0.0
            worst = -1
            for i in range(m2):
                acc = local_work[D_NEW, i] - local_work[D_LIN, i]
                for jj in range(nz):
                    j = index_work[4 * m2 + jj]
                    acc -= flexibility[i, j] * local_work[V2, j]
                local_work[V, i] = -acc
                if not abs(acc) <= rmax:  # also catches NaN
                    rmax = abs(acc)
                    worst = i
            if rmax <= tol:
                break
            if not np.isfinite(rmax):
                return NONFINITE, n_it, n_aug, worst
            if it >= max_newton:
                return NEWTON_FAILED, n_it, n_aug, worst
            # Newton step: (I - W Jp) delta = -R; Jp non-zero only in the engaged blocks
            for ii in range(ma):
                ri = index_work[ii]
                for jj in range(ma):
                    newton_matrix[ii, jj] = -_w_jac(flexibility, jacobian, ri, index_work[jj],
                                                    index_work[2 * m2 + jj],
                                                    index_work[3 * m2 + jj])
                newton_matrix[ii, ii] += 1.0
            # right-hand side for the engaged rows (in the first ma slots of local_work[V2])
            for ii in range(ma):
                local_work[V2, ii] = local_work[V, index_work[ii]]
            if ma > 0:
                if not _dense_solve(newton_matrix, local_work, V2, ma, index_work, m2):
                    return SINGULAR, n_it, n_aug, worst
            # explicit rows: delta_i = -R_i + sum_engaged (W Jp)_ij delta_j
            for i in range(m2):
                acc = local_work[V, i]
                for jj in range(ma):
                    acc += (_w_jac(flexibility, jacobian, i, index_work[jj],
                                   index_work[2 * m2 + jj], index_work[3 * m2 + jj])
                            * local_work[V2, jj])
                local_work[V, i] = acc
            # the engaged rows take the solved values (identical up to round-off)
            for ii in range(ma):
                local_work[V, index_work[ii]] = local_work[V2, ii]
            # Semi-smooth Newton can cycle between stick and slip at the Coulomb kink;
            # relaxed steps after the first few iterations break the cycle.
            relax = _RELAX[(it // 3) % 3] if it >= _PLAIN_NEWTON and it % 3 == 2 else 1.0
            for i in range(m2):
                local_work[D_NEW, i] += relax * local_work[V, i]
            it += 1
            n_it += 1
        # the books of the solution, which the ledger adds if the step is accepted
        element_books(elements, parameters, element_state, track, trial, progress)
        # augmentation
        changed = False
        for e in range(n_elements):
            g = trial[e].gap
            eps = elements[e].eps
            engaged = trial[e].status != OPEN
            augmented = elements[e].aug != 0
            lam = trial[e].lam
            if augmented and engaged and (g <= -eps or g > 0.0):
                # aim inside the band -eps < g <= 0 rather than at g = 0 (see docstring)
                newlam = lam - augment_stiffness[e] * (g + shift * eps)
                trial[e].lam = newlam if newlam > 0.0 else 0.0
                changed = True
        converged = not changed
        pending = changed and n_aug >= max_aug and not strict
        if converged or pending:
            # pending: the updated multipliers act from the next step on
            return (CONVERGED if converged else AUGMENT_PENDING), n_it, n_aug, -1
        if n_aug >= max_aug:
            worst = -1
            pmax = -1.0
            for e in range(n_elements):
                gap = abs(trial[e].gap)
                row = elements[e].row
                if trial[e].status != OPEN and gap > pmax:
                    pmax = gap
                    worst = row
            return AUGMENT_FAILED, n_it, n_aug, worst
        n_aug += 1
