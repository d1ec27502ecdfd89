"""The seam for the simulator's nonlinear elements: local coordinates and one law per kind
(the per-step element solve that calls them is :mod:`rubdiag._kernels.element_solve`).

An element has a kind, DOFs, a few local coordinates ``x = B u`` (its rows ``row .. row + n
- 1`` of the local vectors, n <= :data:`N_LOCAL_MAX`), parameters (a row of
``parameters``) and a state (a row of ``element_state``). Local row r is ``x_r = Σ_c T[r,
c] u_c`` over its element's rows, with the relative displacement ``u_c = q[plus_c] -
q[minus_c]`` (``row_dofs`` (m, 3): plus, minus or -1 for ground, and the element) and T the
element's square block (``transforms`` (m, N_LOCAL_MAX)).

The Newton iteration of a step asks :func:`element_laws` for each element's local force p(x)
and Jacobian dp/dx at the trial local displacements (and, through the records, its velocity
ẋ from the Newmark relation ``ẋ_1 = cv (x - x_n) + cvv ẋ_n + cva ẍ_n``, the step's times and
the shaft's speed and angle); the law also writes its trial record (status, forces, gap)
and its trial state ``element_state[1]``. When the step is accepted, :func:`element_books` gives its
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
   ``law(e, elements, local_work, local_state, parameters, element_state, track, trial,
   progress, jacobian)`` (the arguments of :func:`element_laws`), which reads element e's
   local displacements ``local_work[D_NEW, row:row+n]`` and writes its force
   ``local_work[P_NEW, row:row+n]``, Jacobian ``jacobian[row + i, j] = dp_i/dx_j``, its
   trial record ``trial[e]`` (records.TRIAL: status — OPEN when its Jacobian is zero —, the
   forces and energy terms it has, zeros for those it has not) and its new state
   ``element_state[1, e]``, and returns its status; and ``books(e, elements, parameters,
   element_state, track, trial, progress)``, which writes the accepted step's energy terms
   into ``trial[e]``. ``local_state`` (3, m) holds the local displacement, velocity and
   acceleration at the step's start (set ``KINEMATICS = True`` to have the velocity and
   acceleration tracked); ``progress[0]`` the step's clock (records.PROGRESS). Its
   docstring states the law and its source; a test checks the law against its definition
   and the Jacobian against finite differences.
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

from rubdiag._kernels import annular_contact, crack, journal, pedestal, point_contact
from rubdiag._kernels.records import OPEN, SLIDING, STICKING
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
]

#: the built-in kinds by code
KINDS = {point_contact.KIND: point_contact, annular_contact.KIND: annular_contact,
         crack.KIND: crack, pedestal.KIND: pedestal, journal.KIND: journal}
#: the most local coordinates of one element (a cracked shaft element has 8)
N_LOCAL_MAX = 8

# codes returned by the element solve (rubdiag._kernels.element_solve)
CONVERGED = 0
NEWTON_FAILED = 1
AUGMENT_FAILED = 2
SINGULAR = 3
AUGMENT_PENDING = 4  # accepted although the band was not reached (aug_strict off)
NONFINITE = 5  # non-finite local displacements or forces


# Reference counting (see rubdiag._kernels.newmark): the functions here are called per step,
# and the laws per element and Newton iteration. Numba prunes the counting of their array
# arguments only where no exception path, helper call or branch with arrays crosses a loop,
# so they use error_model="numpy", index the work rows (``local_work[D_NEW, r]``), not
# views, spell out small loops, and dispatch kind by kind: one loop per kind over the
# elements, each with its law inlined (a branch per element over kinds costs 9 increfs per
# element and iteration, 0.25-0.3 µs per step in rub).


def laws_of(kind, cache: bool = True):
    """The loop that runs ``kind``'s law on its elements (the others left alone), inlined
    into :func:`element_laws`: a loop per kind, not a branch per element (see the note on
    reference counting above). ``cache`` False for a kind defined outside rubdiag."""
    @njit(error_model="numpy", inline="always", cache=cache)
    def laws_of_kind(elements, local_work, local_state, parameters, element_state, track,
                     trial, progress, jacobian):
        for e in range(elements.shape[0]):
            if elements[e].kind == kind.KIND:
                kind.law(e, elements, local_work, local_state, parameters, element_state,
                         track, trial, progress, jacobian)

    return laws_of_kind


def books_of(kind, cache: bool = True):
    """The loop that runs ``kind``'s books on its elements, inlined into
    :func:`element_books`."""
    @njit(error_model="numpy", inline="always", cache=cache)
    def books_of_kind(elements, parameters, element_state, track, trial, progress):
        for e in range(elements.shape[0]):
            if elements[e].kind == kind.KIND:
                kind.books(e, elements, parameters, element_state, track, trial, progress)

    return books_of_kind


_point_laws = laws_of(point_contact)
_annular_laws = laws_of(annular_contact)
_crack_laws = laws_of(crack)
_pedestal_laws = laws_of(pedestal)
_journal_laws = laws_of(journal)
_point_books = books_of(point_contact)
_annular_books = books_of(annular_contact)


@njit(error_model="numpy")
def element_laws(elements, local_work, local_state, parameters, element_state, track, trial,
                 progress, jacobian):
    """Every element's law at the trial local displacements, kind by kind (module
    docstring).

    Parameters
    ----------
    elements : ndarray (n_e) records.ELEMENT
        Each element's kind and local rows.
    local_work : ndarray (WC_SIZE, m)
        Reads the trial local displacements (row ``D_NEW``, m), writes the forces (row
        ``P_NEW``, N).
    local_state : ndarray (3, m)
        The local displacement (m), velocity (m/s) and acceleration (m/s²) at the step's
        start.
    parameters : ndarray (n_e, n_par)
        Each element's parameter row (its kind's units).
    element_state : ndarray (2, n_e, n_s)
        Each element's committed state (``[0]``) and trial state (``[1]``, written).
    track : ndarray (n_e) records.TRACK
        Each element's committed record.
    trial : ndarray (n_e) records.TRIAL
        Each element's law at the trial state, written.
    progress : ndarray (1) records.PROGRESS
        The step's clock.
    jacobian : ndarray (m, N_LOCAL_MAX)
        Each element's block of dp/dx (N/m), written.
    """
    _point_laws(elements, local_work, local_state, parameters, element_state, track, trial,
                progress, jacobian)
    _annular_laws(elements, local_work, local_state, parameters, element_state, track, trial,
                  progress, jacobian)
    _crack_laws(elements, local_work, local_state, parameters, element_state, track, trial,
                progress, jacobian)
    _pedestal_laws(elements, local_work, local_state, parameters, element_state, track,
                   trial, progress, jacobian)
    _journal_laws(elements, local_work, local_state, parameters, element_state, track, trial,
                  progress, jacobian)


@njit(error_model="numpy")
def element_books(elements, parameters, element_state, track, trial, progress):
    """Every element's books of its trial state, kind by kind: its energy terms (J) and
    cone excess (N) into ``trial``.

    The crack, the pedestal and the journal bearing keep theirs in their laws: a third
    books loop here made Numba count six arrays' references per call (its pruning gives up
    on the larger function), 0.07 µs per step in rub.

    Parameters
    ----------
    elements, parameters, element_state, track, trial, progress : ndarray
        As for :func:`element_laws`.
    """
    _point_books(elements, parameters, element_state, track, trial, progress)
    _annular_books(elements, parameters, element_state, track, trial, progress)


@njit(error_model="numpy", inline="always")
def local_coords(elements, n_elements, row_dofs, transforms, x, out, row):
    """Local coordinates ``out[row] = B x`` of the first ``n_elements`` elements.

    Parameters
    ----------
    elements : ndarray (n_e) records.ELEMENT
        Each element's local rows.
    n_elements : int
        How many elements, from the first (0: none).
    row_dofs : ndarray (m, 3) int
        Each local row's plus and minus DOF (-1: ground).
    transforms : ndarray (m, N_LOCAL_MAX)
        Each element's block T.
    x : ndarray (n)
        A vector over the DOFs (m, m/s or m/s²).
    out : ndarray (k, m)
        Its row ``row`` is written.
    row : int
        The row of ``out``.
    """
    for e in range(n_elements):
        r0 = elements[e].row
        n = elements[e].n
        if n == 2:      # today's elements, spelled out
            uy = x[row_dofs[r0, 0]]
            if row_dofs[r0, 1] >= 0:
                uy -= x[row_dofs[r0, 1]]
            uz = x[row_dofs[r0 + 1, 0]]
            if row_dofs[r0 + 1, 1] >= 0:
                uz -= x[row_dofs[r0 + 1, 1]]
            out[row, r0] = transforms[r0, 0] * uy + transforms[r0, 1] * uz
            out[row, r0 + 1] = transforms[r0 + 1, 0] * uy + transforms[r0 + 1, 1] * uz
            continue
        for r in range(r0, r0 + n):
            u = x[row_dofs[r0, 0]]
            if row_dofs[r0, 1] >= 0:
                u -= x[row_dofs[r0, 1]]
            acc = transforms[r, 0] * u
            for c in range(1, n):
                u = x[row_dofs[r0 + c, 0]]
                if row_dofs[r0 + c, 1] >= 0:
                    u -= x[row_dofs[r0 + c, 1]]
                acc += transforms[r, c] * u
            out[row, r] = acc


@njit(error_model="numpy", inline="always")
def add_bt_p(elements, row_dofs, transforms, forces, scale, out):
    """``out += scale Bᵀ p``.

    Parameters
    ----------
    elements, row_dofs, transforms : ndarray
        The elements' records and local coordinates (:func:`local_coords`).
    forces : ndarray (m)
        The local forces p (N).
    scale : float
        The factor they are added with.
    out : ndarray (n)
        Added to in place (N).
    """
    for e in range(elements.shape[0]):
        r0 = elements[e].row
        n = elements[e].n
        if n == 2:      # today's elements, spelled out
            fy = transforms[r0, 0] * forces[r0] + transforms[r0 + 1, 0] * forces[r0 + 1]
            fz = transforms[r0, 1] * forces[r0] + transforms[r0 + 1, 1] * forces[r0 + 1]
            out[row_dofs[r0, 0]] += scale * fy
            out[row_dofs[r0 + 1, 0]] += scale * fz
            if row_dofs[r0, 1] >= 0:
                out[row_dofs[r0, 1]] -= scale * fy
            if row_dofs[r0 + 1, 1] >= 0:
                out[row_dofs[r0 + 1, 1]] -= scale * fz
            continue
        for c in range(n):      # on the plus DOFs, then the minus ones
            f = transforms[r0, c] * forces[r0]
            for r in range(1, n):
                f += transforms[r0 + r, c] * forces[r0 + r]
            out[row_dofs[r0 + c, 0]] += scale * f
        for c in range(n):
            if row_dofs[r0 + c, 1] >= 0:
                f = transforms[r0, c] * forces[r0]
                for r in range(1, n):
                    f += transforms[r0 + r, c] * forces[r0 + r]
                out[row_dofs[r0 + c, 1]] -= scale * f


@njit(error_model="numpy")
def at_rest(elements, local_work, local_state, parameters, element_state, track, trial,
            progress, jacobian):
    """Every element's law at the state at t = 0, committed as its state and current
    episode.

    Parameters
    ----------
    elements, local_work, local_state, parameters, element_state : ndarray
        As for :func:`element_laws`, with ``local_work[D_NEW]`` = ``local_state[X_N]`` and
        no step (``progress``'s h = 0); the forces are left in ``local_work[P_NEW]``.
    track, trial, progress, jacobian : ndarray
        As for :func:`element_laws`.

    Returns
    -------
    float
        The elastic energy stored (J).
    """
    element_laws(elements, local_work, local_state, parameters, element_state, track, trial,
                 progress, jacobian)
    element_books(elements, parameters, element_state, track, trial, progress)
    energy = 0.0
    for e in range(elements.shape[0]):
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
        for j in range(element_state.shape[2]):
            element_state[0, e, j] = element_state[1, e, j]
    return energy
