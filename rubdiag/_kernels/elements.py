"""The seam for the simulator's nonlinear elements: local coordinates, one law per kind, and
the per-step element solve in the Schur complement.

An element has a kind, DOFs, a few local coordinates ``x = B u`` (its rows ``row .. row + n
- 1`` of the local vectors, n <= :data:`N_LOCAL_MAX`), parameters (a row of ``par``) and a
state (a row of ``es``). Local row r is ``x_r = Σ_c T[r, c] u_c`` over its element's rows,
with the relative displacement ``u_c = q[plus_c] - q[minus_c]`` (``rmap`` (m, 3): plus, minus
or -1 for ground, and the element) and T the element's square block (``tmat`` (m,
N_LOCAL_MAX)).

The Newton iteration of a step asks :func:`element_laws` for each element's local force p(x)
and Jacobian dp/dx at the trial local displacements (and, through the records, its velocity
ẋ from the Newmark relation ``ẋ_1 = cv (x - x_n) + cvv ẋ_n + cva ẍ_n``, the step's times and
the shaft's speed and angle); the law also writes its trial record (status, forces, gap)
and its trial state ``es[1]``. When the step is accepted, :func:`element_books` gives its
energy terms (elastic energy stored, dissipation, work of prescribed motions) for the
ledger, and the trial state is committed. Kinds:

* :mod:`rubdiag._kernels.point_contact` (1) — point–point contact;
* :mod:`rubdiag._kernels.annular_contact` (2) — shaft–stator annular clearance;
* :mod:`rubdiag._kernels.crack` (3) — a breathing transverse crack in a shaft element;
* :mod:`rubdiag._kernels.pedestal` (4) — a loose bearing pedestal on its seat;
* :mod:`rubdiag._kernels.journal` (5) — a plain journal bearing's oil film.

Adding a kind
-------------
1. A kernel module ``rubdiag/_kernels/<kind>.py`` with ``KIND`` (a new code), ``N_LOCAL`` and
   ``law(e, el, wc, xs, par, es, track, trial, prog, jac)``, which reads element e's local
   displacements ``wc[D_NEW, row:row+n]`` and writes its force ``wc[P_NEW, row:row+n]``,
   Jacobian ``jac[row + i, j] = dp_i/dx_j``, its trial record
   ``trial[e]`` (records.TRIAL: status — OPEN when its Jacobian is zero —, the forces and
   energy terms it has, zeros for those it has not) and its new state ``es[1, e]``, and
   returns its status; and ``books(e, el, par, es, track, trial, prog)``, which writes the
   accepted step's energy terms into ``trial[e]``. ``xs`` (3, m) holds the local
   displacement, velocity and acceleration at the step's start (set ``KINEMATICS = True``
   to have the velocity and acceleration tracked); ``prog[0]`` the step's clock
   (records.PROGRESS). Its docstring states the law and its source; a test checks the law
   against its definition and the Jacobian against finite differences.
2. Its loops in :func:`element_laws` and :func:`element_books` below: ``_x_laws =
   laws_of(x)`` and a call in ``element_laws`` (the same for its books, if it keeps them
   apart from its law): one loop per kind over the elements, with its law inlined (see the
   note on reference counting).
3. A description in :mod:`rubdiag.simulation._elements`: a frozen dataclass (SI, validated at
   construction) with ``pack(omega, ramp)`` giving its DOFs, T block, parameter row and
   state, and its step requirement.

Numba compiles the kinds' loops statically (a law passed as an argument would be compiled
again in every process); :func:`rubdiag._kernels.extend.kernel_with` compiles, once per
process and without the disk cache, a kernel that also runs kinds defined outside rubdiag
(the tests add a linear spring and damper that way).
"""

from __future__ import annotations

import numpy as np

from rubdiag._kernels import annular_contact, crack, journal, pedestal, point_contact
from rubdiag._kernels.records import D_LIN, D_NEW, OPEN, P_NEW, SLIDING, STICKING, V2, V
from rubdiag._numba import njit

__all__ = [
    "AUGMENT_FAILED",
    "AUGMENT_PENDING",
    "CONVERGED",
    "KINDS",
    "NEWTON_FAILED",
    "NONFINITE",
    "N_LOCAL_MAX",
    "SINGULAR",
    "add_bt_p",
    "at_rest",
    "books_of",
    "element_books",
    "element_laws",
    "laws_of",
    "local_coords",
    "solve_elements",
]

#: the built-in kinds by code
KINDS = {point_contact.KIND: point_contact, annular_contact.KIND: annular_contact,
         crack.KIND: crack, pedestal.KIND: pedestal, journal.KIND: journal}
#: the most local coordinates of one element (a cracked shaft element has 8)
N_LOCAL_MAX = 8

# codes returned by solve_elements
CONVERGED = 0
NEWTON_FAILED = 1
AUGMENT_FAILED = 2
SINGULAR = 3
AUGMENT_PENDING = 4  # accepted although the band was not reached (aug_strict off)
NONFINITE = 5  # non-finite local displacements or forces

_PLAIN_NEWTON = 8          # full Newton steps before some relaxed ones
_RELAX = (0.5, 0.3, 0.7)   # varied, so that a relaxed step cannot fall into a cycle of its own

# Reference counting (see rubdiag._kernels.newmark): the functions here are called per step,
# and the laws per element and Newton iteration. Numba prunes the counting of their array
# arguments only where no exception path, helper call or branch with arrays crosses a loop,
# so they use error_model="numpy", index the work rows (``wc[D_NEW, r]``) instead of taking
# views, spell out small loops, and dispatch kind by kind: one loop per kind over the
# elements, each with its law inlined (a branch per element over kinds costs 9 increfs per
# element and iteration, 0.25-0.3 µs per step in rub, measured 2026-11-25).


def laws_of(kind, cache: bool = True):
    """The loop that runs ``kind``'s law on its elements (the others left alone), inlined
    into :func:`element_laws`: a loop per kind, not a branch per element (see the note on
    reference counting above). ``cache`` False for a kind defined outside rubdiag."""
    @njit(error_model="numpy", inline="always", cache=cache)
    def laws_of_kind(el, wc, xs, par, es, track, trial, prog, jac):
        for e in range(el.shape[0]):
            if el[e].kind == kind.KIND:
                kind.law(e, el, wc, xs, par, es, track, trial, prog, jac)

    return laws_of_kind


def books_of(kind, cache: bool = True):
    """The loop that runs ``kind``'s books on its elements, inlined into
    :func:`element_books`."""
    @njit(error_model="numpy", inline="always", cache=cache)
    def books_of_kind(el, par, es, track, trial, prog):
        for e in range(el.shape[0]):
            if el[e].kind == kind.KIND:
                kind.books(e, el, par, es, track, trial, prog)

    return books_of_kind


_point_laws = laws_of(point_contact)
_annular_laws = laws_of(annular_contact)
_crack_laws = laws_of(crack)
_pedestal_laws = laws_of(pedestal)
_journal_laws = laws_of(journal)
_point_books = books_of(point_contact)
_annular_books = books_of(annular_contact)


@njit(error_model="numpy")
def element_laws(el, wc, xs, par, es, track, trial, prog, jac):
    """Every element's law at the trial local displacements ``wc[D_NEW]``, kind by kind
    (module docstring): forces into ``wc[P_NEW]``, Jacobians into ``jac``, the trial records
    and states."""
    _point_laws(el, wc, xs, par, es, track, trial, prog, jac)
    _annular_laws(el, wc, xs, par, es, track, trial, prog, jac)
    _crack_laws(el, wc, xs, par, es, track, trial, prog, jac)
    _pedestal_laws(el, wc, xs, par, es, track, trial, prog, jac)
    _journal_laws(el, wc, xs, par, es, track, trial, prog, jac)


@njit(error_model="numpy")
def element_books(el, par, es, track, trial, prog):
    """Every element's books of its trial state, kind by kind: its energy terms and cone
    excess into ``trial`` (records.TRIAL). The crack, the pedestal and the journal bearing
    keep theirs in their laws: a third books loop here made Numba count six arrays'
    references per call (its pruning gives up on the larger function), 0.07 µs per step in
    rub."""
    _point_books(el, par, es, track, trial, prog)
    _annular_books(el, par, es, track, trial, prog)


@njit(error_model="numpy", inline="always")
def local_coords(el, ne, rmap, tmat, q, out, row):
    """Local coordinates ``out[row] = B q`` (out (k, m)) of the first ``ne`` elements."""
    for e in range(ne):
        r0 = el[e].row
        n = el[e].n
        if n == 2:      # today's elements, spelled out
            uy = q[rmap[r0, 0]]
            if rmap[r0, 1] >= 0:
                uy -= q[rmap[r0, 1]]
            uz = q[rmap[r0 + 1, 0]]
            if rmap[r0 + 1, 1] >= 0:
                uz -= q[rmap[r0 + 1, 1]]
            out[row, r0] = tmat[r0, 0] * uy + tmat[r0, 1] * uz
            out[row, r0 + 1] = tmat[r0 + 1, 0] * uy + tmat[r0 + 1, 1] * uz
            continue
        for r in range(r0, r0 + n):
            u = q[rmap[r0, 0]]
            if rmap[r0, 1] >= 0:
                u -= q[rmap[r0, 1]]
            acc = tmat[r, 0] * u
            for c in range(1, n):
                u = q[rmap[r0 + c, 0]]
                if rmap[r0 + c, 1] >= 0:
                    u -= q[rmap[r0 + c, 1]]
                acc += tmat[r, c] * u
            out[row, r] = acc


@njit(error_model="numpy", inline="always")
def add_bt_p(el, rmap, tmat, p, scale, out):
    """``out += scale Bᵀ p`` for local forces p (m)."""
    for e in range(el.shape[0]):
        r0 = el[e].row
        n = el[e].n
        if n == 2:      # today's elements, spelled out
            fy = tmat[r0, 0] * p[r0] + tmat[r0 + 1, 0] * p[r0 + 1]
            fz = tmat[r0, 1] * p[r0] + tmat[r0 + 1, 1] * p[r0 + 1]
            out[rmap[r0, 0]] += scale * fy
            out[rmap[r0 + 1, 0]] += scale * fz
            if rmap[r0, 1] >= 0:
                out[rmap[r0, 1]] -= scale * fy
            if rmap[r0 + 1, 1] >= 0:
                out[rmap[r0 + 1, 1]] -= scale * fz
            continue
        for c in range(n):      # on the plus DOFs, then the minus ones
            f = tmat[r0, c] * p[r0]
            for r in range(1, n):
                f += tmat[r0 + r, c] * p[r0 + r]
            out[rmap[r0 + c, 0]] += scale * f
        for c in range(n):
            if rmap[r0 + c, 1] >= 0:
                f = tmat[r0, c] * p[r0]
                for r in range(1, n):
                    f += tmat[r0 + r, c] * p[r0 + r]
                out[rmap[r0 + c, 1]] -= scale * f


@njit(error_model="numpy")
def at_rest(el, wc, xs, par, es, track, trial, prog, jac):
    """Every element's law at the state at t = 0 (``wc[D_NEW]`` = ``xs[X_N]``, no step:
    ``prog``'s h = 0), committed as its state and current episode (forces in
    ``wc[P_NEW]``). Returns the elastic energy stored."""
    element_laws(el, wc, xs, par, es, track, trial, prog, jac)
    element_books(el, par, es, track, trial, prog)
    energy = 0.0
    for e in range(el.shape[0]):
        st = trial[e].status
        track[e].status = st
        track[e].fn = trial[e].fn
        track[e].ft = trial[e].ft
        track[e].gap = trial[e].gap
        track[e].z = trial[e].z
        track[e].slip = trial[e].slip
        track[e].ep_slide_entries = 1 if st == SLIDING else 0
        track[e].ep_stick_entries = 1 if st == STICKING else 0
        if st != OPEN:
            energy += trial[e].elastic
        for j in range(es.shape[2]):
            es[0, e, j] = es[1, e, j]
    return energy


@njit(error_model="numpy", inline="always")
def _dense_solve(A, wc, row, m, work, off):
    """Solve the leading m x m block ``A x = b`` in place, b = ``wc[row, :m]`` (b <- x), by
    LU with partial pivoting (pivots in ``work[off:off + m]``). Returns False if A is
    numerically singular."""
    for k in range(m):
        p = k
        amax = abs(A[k, k])
        for i in range(k + 1, m):
            if abs(A[i, k]) > amax:
                amax = abs(A[i, k])
                p = i
        if amax == 0.0 or not np.isfinite(amax):
            return False
        work[off + k] = p
        if p != k:
            for j in range(m):
                tmp = A[k, j]
                A[k, j] = A[p, j]
                A[p, j] = tmp
            tmp = wc[row, k]
            wc[row, k] = wc[row, p]
            wc[row, p] = tmp
        inv = 1.0 / A[k, k]
        for i in range(k + 1, m):
            f = A[i, k] * inv
            if f != 0.0:
                A[i, k] = f
                for j in range(k + 1, m):
                    A[i, j] -= f * A[k, j]
                wc[row, i] -= f * wc[row, k]
    for i in range(m - 1, -1, -1):
        acc = wc[row, i]
        for j in range(i + 1, m):
            acc -= A[i, j] * wc[row, j]
        wc[row, i] = acc / A[i, i]
    return True


@njit(error_model="numpy", inline="always")
def _w_jac(W, jac, i, rj, r0, n):
    """``(W Jp)[i, rj]``: row i of W times column rj of the block-diagonal Jacobian (the
    block of rj's element, rows ``r0 .. r0 + n - 1``)."""
    cj = rj - r0
    acc = W[i, r0] * jac[r0, cj]
    if n == 2:
        return acc + W[i, r0 + 1] * jac[r0 + 1, cj]
    for k in range(1, n):
        acc += W[i, r0 + k] * jac[r0 + k, cj]
    return acc


@njit(error_model="numpy")
def solve_elements(W, wc, pc, xs, el, par, aug_k, es, track, trial, run, prog, jac, work,
                   wm):
    """Solve the elements' problem of one Newmark step in the Schur complement.

    Unknown: the local displacements ``d`` (m, ``wc[D_NEW]``). With ``d_lin`` (``wc[D_LIN]``)
    those of the linear predictor (element forces frozen at ``pc``) and ``W = B K_eff^-1 Bᵀ``,
    the step's problem is ``R(d) = d - d_lin - W (p(d) - p_n) = 0``, solved by (semi-smooth)
    Newton with ``J = I - W dp/dd``. Only the rows of elements whose law is engaged enter the
    dense solve; the other rows are updated explicitly.

    Augmented Lagrangian (the study's eq. 2): after each converged Newton solve, every
    engaged element with ``aug`` and ``|gap| >= eps`` updates its multiplier ``lam <- max(0,
    lam - aug_k (gap + aug_shift eps))`` (``aug_k`` at the step's level) and the Newton
    solve is repeated, until every engaged augmented element is in the band ``-eps < g <=
    0`` (or ``max_aug`` updates; then ``AUGMENT_FAILED`` if ``aug_strict`` else
    ``AUGMENT_PENDING``). Eq. (2) literally is ``aug_k = k_N``, ``aug_shift = 0``: its
    iterates creep towards ``g = 0`` by a factor ``1 / (1 + k_N W_ee)`` per update and stop
    just inside the band. A larger ``aug_k`` (up to the step's dynamic stiffness at the
    contact) gets there in a few updates; aiming at ``-aug_shift eps`` instead of 0 keeps
    the landing point near where eq. (2) stops instead of pulling the contact to ``g = 0``
    within one step (which, with the trapezoidal rule, injects a large spurious rebound).
    The multipliers live in ``trial.lam``.

    Outputs: ``wc[D_NEW]``, ``wc[P_NEW]``, the laws' ``trial`` (with the books of the
    solution: :func:`element_books`), ``es[1]`` and ``jac``
    (m, N_LOCAL_MAX); ``work`` (>= 5 m) int (the engaged rows, the pivots, each engaged
    row's element's first row and size, and the rows whose force changed) and ``wm`` (m, m)
    are work, as ``wc[V]``, ``wc[V2]``. ``aug_k`` (n_e) the multiplier update stiffness at
    the step's level.
    Returns ``(code, newton_iterations, augment_updates, worst_row)``.
    """
    tol = run[0].newton_tol
    max_newton = run[0].max_newton
    max_aug = run[0].max_aug
    strict = run[0].aug_strict != 0
    shift = run[0].aug_shift
    m2 = wc.shape[1]
    ne = el.shape[0]
    for i in range(m2):
        wc[D_NEW, i] = wc[D_LIN, i]
    n_it = 0
    n_aug = 0
    worst = -1
    while True:
        it = 0
        while True:
            # law evaluation; the engaged elements' rows in work[:ma]
            element_laws(el, wc, xs, par, es, track, trial, prog, jac)
            ma = 0
            for e in range(ne):
                st = trial[e].status
                r0 = el[e].row
                n = el[e].n
                if st != OPEN:
                    for r in range(r0, r0 + n):
                        work[ma] = r
                        work[2 * m2 + ma] = r0
                        work[3 * m2 + ma] = n
                        ma += 1
            # residual R = d - d_lin - W (p - p_n), over the rows whose force changed (in
            # work[4 m2:4 m2 + nz]: an open contact's is zero, so a rotor on its films alone
            # sums 4 columns of W, not 20)
            nz = 0
            for i in range(m2):
                dpi = wc[P_NEW, i] - pc[i]
                wc[V2, i] = dpi
                if dpi != 0.0:
                    work[4 * m2 + nz] = i
                    nz += 1
            rmax = 0.0
            worst = -1
            for i in range(m2):
                acc = wc[D_NEW, i] - wc[D_LIN, i]
                for jj in range(nz):
                    j = work[4 * m2 + jj]
                    acc -= W[i, j] * wc[V2, j]
                wc[V, i] = -acc
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
                ri = work[ii]
                for jj in range(ma):
                    wm[ii, jj] = -_w_jac(W, jac, ri, work[jj], work[2 * m2 + jj],
                                         work[3 * m2 + jj])
                wm[ii, ii] += 1.0
            # right-hand side for the engaged rows (in the first ma slots of wc[V2])
            for ii in range(ma):
                wc[V2, ii] = wc[V, work[ii]]
            if ma > 0:
                if not _dense_solve(wm, wc, V2, ma, work, m2):
                    return SINGULAR, n_it, n_aug, worst
            # explicit rows: delta_i = -R_i + sum_engaged (W Jp)_ij delta_j
            for i in range(m2):
                acc = wc[V, i]
                for jj in range(ma):
                    acc += (_w_jac(W, jac, i, work[jj], work[2 * m2 + jj], work[3 * m2 + jj])
                            * wc[V2, jj])
                wc[V, i] = acc
            # the engaged rows take the solved values (identical up to round-off)
            for ii in range(ma):
                wc[V, work[ii]] = wc[V2, ii]
            # Semi-smooth Newton can cycle between stick and slip at the Coulomb kink;
            # relaxed steps after the first few iterations break the cycle.
            relax = _RELAX[(it // 3) % 3] if it >= _PLAIN_NEWTON and it % 3 == 2 else 1.0
            for i in range(m2):
                wc[D_NEW, i] += relax * wc[V, i]
            it += 1
            n_it += 1
        # the books of the solution, which the ledger adds if the step is accepted
        element_books(el, par, es, track, trial, prog)
        # augmentation
        changed = False
        for e in range(ne):
            g = trial[e].gap
            eps = el[e].eps
            engaged = trial[e].status != OPEN
            augmented = el[e].aug != 0
            lam = trial[e].lam
            if augmented and engaged and (g <= -eps or g > 0.0):
                # aim inside the band -eps < g <= 0 rather than at g = 0 (see docstring)
                newlam = lam - aug_k[e] * (g + shift * eps)
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
            for e in range(ne):
                gap = abs(trial[e].gap)
                row = el[e].row
                if trial[e].status != OPEN and gap > pmax:
                    pmax = gap
                    worst = row
            return AUGMENT_FAILED, n_it, n_aug, worst
        n_aug += 1
