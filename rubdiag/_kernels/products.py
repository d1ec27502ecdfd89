"""The products a step takes with the linear system: dense columns, M dq and K dq.

A dense matrix is handed over transposed (``a_t = Aᵀ``, C order), so that ``A x`` is a sum
of A's columns, rows of ``a_t``: the inner loop is then an independent update of contiguous
memory, which vectorizes (a row dot product would be a serial sum: no fastmath, no
reordering). After an accepted step the controller needs ``M dq`` and ``K dq``: one pass
over the union pattern of M and K for a sparse system (:func:`mk_products`, which also
gives the viscous dissipation from ``K_eff dq = rhs``), dense products that skip the modal
tail of a reduced model (:func:`mk_dense`, then :func:`dissipation`).
"""

from __future__ import annotations

from rubdiag._numba import njit

__all__ = ["add_columns", "dissipation", "matvec_t", "mk_dense", "mk_products"]


@njit
def matvec_t(a_t, x, out):
    """``out = A x`` for A stored transposed (:func:`add_columns`).

    Parameters
    ----------
    a_t : ndarray (n_in, n_out)
        Aᵀ, dense.
    x : ndarray (n_in)
        The operand.
    out : ndarray (n_out)
        The product (overwritten).
    """
    for i in range(out.shape[0]):
        out[i] = 0.0
    add_columns(a_t, x, 0, x.shape[0], 0, out.shape[0], out)


@njit(inline="always")
def add_columns(a_t, x, j0, j1, i0, i1, out):
    """``out[i0:i1] += A[i0:i1, j0:j1] x[j0:j1]`` for A stored transposed.

    Column by column (rows of ``a_t``), eight columns per pass over ``out``, added as two
    groups of four, ``(out + ((c0 x0 + c1 x1) + (c2 x2 + c3 x3))) + (...)``: the same sums,
    in the same order, as two passes of four (the bits of the four-column version), with
    half the passes' loads, stores and set-up; then four, then one at a time.

    Parameters
    ----------
    a_t : ndarray (n_in, n_out)
        Aᵀ, dense.
    x : ndarray (n_in)
        The operand.
    j0, j1 : int
        The columns of A to add (``j0 <= j1``).
    i0, i1 : int
        The rows of A, and of ``out``, they are added to.
    out : ndarray (n_out)
        Added to in place.
    """
    j = j0
    while j + 8 <= j1:
        x0 = x[j]
        x1 = x[j + 1]
        x2 = x[j + 2]
        x3 = x[j + 3]
        x4 = x[j + 4]
        x5 = x[j + 5]
        x6 = x[j + 6]
        x7 = x[j + 7]
        c0 = a_t[j]
        c1 = a_t[j + 1]
        c2 = a_t[j + 2]
        c3 = a_t[j + 3]
        c4 = a_t[j + 4]
        c5 = a_t[j + 5]
        c6 = a_t[j + 6]
        c7 = a_t[j + 7]
        for i in range(i0, i1):
            out[i] = ((out[i] + ((c0[i] * x0 + c1[i] * x1) + (c2[i] * x2 + c3[i] * x3)))
                      + ((c4[i] * x4 + c5[i] * x5) + (c6[i] * x6 + c7[i] * x7)))
        j += 8
    while j + 4 <= j1:
        x0 = x[j]
        x1 = x[j + 1]
        x2 = x[j + 2]
        x3 = x[j + 3]
        c0 = a_t[j]
        c1 = a_t[j + 1]
        c2 = a_t[j + 2]
        c3 = a_t[j + 3]
        for i in range(i0, i1):
            out[i] += (c0[i] * x0 + c1[i] * x1) + (c2[i] * x2 + c3[i] * x3)
        j += 4
    while j < j1:
        xj = x[j]
        c0 = a_t[j]
        for i in range(i0, i1):
            out[i] += c0[i] * xj
        j += 1


@njit
def mk_dense(n_coupled, m_dense, k_dense, dq, m_dq, k_dq):
    """``m_dq = M dq`` and ``k_dq = K dq`` for symmetric dense M and K whose coordinates from
    ``n_coupled`` on are modal.

    There K is diagonal and uncoupled and M diagonal in that block (a Craig–Bampton model:
    contact DOFs, then fixed-interface modes): ``2 n_coupled n`` products instead of
    ``2 n²``; ``n_coupled = n`` is the plain dense product.

    Parameters
    ----------
    n_coupled : int
        How many leading coordinates are coupled in M and K (``run.coupled``).
    m_dense, k_dense : ndarray (n, n)
        M (kg) and K (N/m), symmetric: row j is column j.
    dq : ndarray (n)
        The step's displacement increment (m).
    m_dq, k_dq : ndarray (n)
        M dq (kg m) and K dq (N), overwritten.
    """
    n = dq.shape[0]
    for i in range(n):
        modal = i >= n_coupled
        m_dq[i] = m_dense[i, i] * dq[i] if modal else 0.0
        k_dq[i] = k_dense[i, i] * dq[i] if modal else 0.0
    add_columns(k_dense, dq, 0, n_coupled, 0, n_coupled, k_dq)    # K_bb dq_b
    add_columns(m_dense, dq, 0, n, 0, n_coupled, m_dq)    # M_bb dq_b + M_bm dq_m
    add_columns(m_dense, dq, 0, n_coupled, n_coupled, n, m_dq)    # M_mb dq_b


@njit(error_model="numpy")
def mk_products(beta, gamma, h, mk_ptr, mk_idx, mk_m, mk_k, dq, rhs, m_dq, k_dq):
    """``m_dq = M dq`` and ``k_dq = K dq`` in one pass over the union pattern of M and K.

    Parameters
    ----------
    beta, gamma : float
        Newmark's β and γ.
    h : float
        The step (s).
    mk_ptr, mk_idx : ndarray (n + 1), (nnz) int
        The union pattern of M and K in CSR.
    mk_m, mk_k : ndarray (nnz)
        M's (kg) and K's (N/m) values on that pattern.
    dq : ndarray (n)
        The step's displacement increment (m).
    rhs : ndarray (n)
        The right-hand side dq solves, ``K_eff dq = rhs`` (N).
    m_dq, k_dq : ndarray (n)
        M dq (kg m) and K dq (N), overwritten.

    Returns
    -------
    float
        ``dqᵀ C dq`` (J s: h times the step's viscous dissipation h v̄ᵀ C v̄, v̄ = dq / h),
        with ``C dq = (rhs - K dq - M dq / (β h²)) β h / γ``; not finite when dq is not.
    """
    ca0 = 1.0 / (beta * h * h)
    cc = beta * h / gamma
    dvisc = 0.0
    for i in range(dq.shape[0]):
        am = 0.0
        ak = 0.0
        for k in range(mk_ptr[i], mk_ptr[i + 1]):
            dj = dq[mk_idx[k]]
            am += mk_m[k] * dj
            ak += mk_k[k] * dj
        dvisc += dq[i] * cc * (rhs[i] - ak - ca0 * am)
        m_dq[i] = am
        k_dq[i] = ak
    return dvisc


@njit(error_model="numpy")
def dissipation(beta, gamma, h, dq, rhs, m_dq, k_dq):
    """``dqᵀ C dq`` from M dq, K dq and ``K_eff dq = rhs`` (:func:`mk_products`), for dense
    M and K, whose products come first (:func:`mk_dense`).

    Parameters
    ----------
    beta, gamma : float
        Newmark's β and γ.
    h : float
        The step (s).
    dq : ndarray (n)
        The step's displacement increment (m).
    rhs : ndarray (n)
        The right-hand side dq solves (N).
    m_dq, k_dq : ndarray (n)
        M dq (kg m) and K dq (N).

    Returns
    -------
    float
        ``dqᵀ C dq`` (J s).
    """
    ca0 = 1.0 / (beta * h * h)
    cc = beta * h / gamma
    dvisc = 0.0
    for i in range(dq.shape[0]):
        dvisc += dq[i] * cc * (rhs[i] - k_dq[i] - ca0 * m_dq[i])
    return dvisc
