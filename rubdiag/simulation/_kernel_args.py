"""The Python mirror of the kernel's arguments: fills the bundles the kernel reads and writes.

:func:`rubdiag._kernels.newmark.newmark_contact` takes its inputs and outputs as bundles of
preallocated arrays (:mod:`rubdiag._kernels.interface`: ``Linear``, ``Elements``, ``State``,
``Outputs``, ``Logs``, ``Work``, the ``run`` record; the record types are
:mod:`rubdiag._kernels.records`). This module makes each from checked inputs, packing every
element description once (:meth:`pack`), and grows the logs when the kernel finds one full.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import scipy.sparse as sp

from rubdiag._kernels import records
from rubdiag._kernels.elements import KINDS, N_LOCAL_MAX
from rubdiag._kernels.extend import Kernel, kernel_with
from rubdiag._kernels.interface import (
    WC_SIZE,
    WN_SIZE,
    Elements,
    Linear,
    Logs,
    Outputs,
    State,
    Work,
)
from rubdiag._kernels.newmark import PROFILE_SECTIONS
from rubdiag.simulation._elements import Packed, impacts
from rubdiag.simulation._grid import Ticks
from rubdiag.simulation._solver import Settings

__all__ = ["b_matrix", "coupled", "element_bundle", "empty_logs", "grown_logs", "kernel_for",
           "linear_arrays", "output_arrays", "packed_elements", "run_record", "start_state",
           "with_acceleration", "work_arrays"]


def kernel_for(elements) -> Kernel:
    """The kernel whose element dispatch knows every element's kind: the built-in (cached)
    one, or one extended by kinds defined outside rubdiag (:mod:`rubdiag._kernels.extend`)."""
    extra = []
    for element in elements:
        module = type(element).kernel
        if KINDS.get(module.KIND) is module or module in extra:
            continue
        extra.append(module)
    return kernel_with(tuple(sorted(extra, key=lambda m: m.KIND)))


def packed_elements(elements, omega: float, ramps) -> list[Packed]:
    """Each element as the kernel reads it at shaft speed ``omega`` (rad/s), with its gap
    ramp (None: none)."""
    return [el.pack(omega, ramp) for el, ramp in zip(elements, ramps, strict=True)]


def b_matrix(packed: Sequence[Packed], n: int) -> np.ndarray:
    """Dense B (m, n) of the elements' local coordinates ``x = B q``: row r of an element is
    ``Σ_c T[r, c] (q[plus_c] - q[minus_c])``."""
    m = sum(p.rows.shape[0] for p in packed)
    B = np.zeros((m, n))
    r0 = 0
    for p in packed:
        k = p.rows.shape[0]
        for r in range(k):
            for c in range(k):
                B[r0 + r, p.rows[c, 0]] += p.tmat[r, c]
                if p.rows[c, 1] >= 0:
                    B[r0 + r, p.rows[c, 1]] -= p.tmat[r, c]
        r0 += k
    return B


def linear_arrays(M, C, K, dense: bool) -> Linear:
    """M and C in CSR, the union pattern of M and K with both value arrays (one pass
    computes M dq and K dq), and for a dense system M and K as dense arrays."""
    n = M.shape[0]
    pat = sp.csr_matrix(abs(M) + abs(K))
    pat.sort_indices()
    rows = np.repeat(np.arange(n), np.diff(pat.indptr))
    mk_m = np.ascontiguousarray(np.asarray(M[rows, pat.indices]).ravel(), dtype=np.float64)
    mk_k = np.ascontiguousarray(np.asarray(K[rows, pat.indices]).ravel(), dtype=np.float64)
    empty = np.zeros((0, 0))
    return Linear(
        M.indptr.astype(np.int64), M.indices.astype(np.int64), M.data,
        C.indptr.astype(np.int64), C.indices.astype(np.int64), C.data,
        pat.indptr.astype(np.int64), pat.indices.astype(np.int64), mk_m, mk_k,
        M.toarray() if dense else empty, K.toarray() if dense else empty)


def coupled(M: np.ndarray, K: np.ndarray) -> int:
    """How many leading coordinates of a dense system are coupled in M and K: the others
    form a modal tail, K diagonal in their rows and M diagonal in their block, exactly (a
    Craig–Bampton model's fixed-interface modes), which the kernel's products skip."""
    n = M.shape[0]
    modal = [not (np.any(K[i, :i]) or np.any(K[i, i + 1:]) or np.any(M[i, i + 1:]))
             for i in range(n)]
    tail = 0
    while tail < n and modal[n - 1 - tail]:
        tail += 1
    return n - tail


def element_bundle(packed: Sequence[Packed], lev_req, aug_k, elements) -> Elements:
    """The elements as the kernel reads them (:data:`~rubdiag._kernels.interface.Elements`)."""
    ne = len(packed)
    el = np.zeros(ne, records.ELEMENT)
    m = sum(p.rows.shape[0] for p in packed)
    rmap = np.zeros((m, 3), np.int64)
    tmat = np.zeros((m, N_LOCAL_MAX))
    par = np.zeros((ne, max((p.par.size for p in packed), default=0)))
    r0 = 0
    for e, p in enumerate(packed):
        k = p.rows.shape[0]
        el[e]["kind"], el[e]["row"], el[e]["n"] = p.kind, r0, k
        el[e]["aug"], el[e]["eps"], el[e]["lev_req"] = int(p.augmented), p.eps, lev_req[e]
        el[e]["impact"] = impacts(elements[e])
        rmap[r0:r0 + k, :2] = p.rows
        rmap[r0:r0 + k, 2] = e
        tmat[r0:r0 + k, :k] = p.tmat
        par[e, : p.par.size] = p.par
        r0 += k
    return Elements(el, rmap, tmat, par, np.ascontiguousarray(aug_k))


def start_state(M, K, q0, v0, B, bundle: Elements, packed, at_rest,
          omega: float = 0.0) -> tuple[State, float]:
    """The kernel's state at t = 0 (copies: the inputs stay as they are) — the elements'
    laws evaluated at q0 and the shaft speed ``omega`` (rad/s), committed — and the
    elements' elastic energy there. The local acceleration is set with a0
    (:func:`with_acceleration`). ``at_rest``: the kernel's
    (:func:`rubdiag._kernels.elements.at_rest`, or the one of an extended kernel)."""
    ne = len(packed)
    n_state = max((p.state.size for p in packed), default=0)
    es = np.zeros((2, ne, n_state))
    for e, p in enumerate(packed):
        es[0, e, : p.state.size] = p.state
        es[1, e, : p.state.size] = p.state
    xs = np.zeros((3, B.shape[0]))
    xs[records.X_N] = B @ q0
    xs[records.XV_N] = B @ v0
    track = np.zeros(ne, records.TRACK)
    prog = np.zeros(1, records.PROGRESS)       # h = 0: at rest, where ẋ = ẋ_n
    prog["cvv"] = 1.0
    prog["omega"] = omega                      # a journal bearing's film turns at it
    wc = np.zeros((WC_SIZE, B.shape[0]))
    wc[records.D_NEW] = xs[records.X_N]
    e_c0 = at_rest(bundle.el, wc, xs, bundle.par, es, track, np.zeros(ne, records.TRIAL), prog,
                   np.zeros((B.shape[0], N_LOCAL_MAX)))
    pc = wc[records.P_NEW].copy()
    prog["e_contact"] = e_c0
    prog["fail_time"] = np.nan
    prog["fail_element"] = -1
    state = State(q0.copy(), v0.copy(), np.zeros_like(q0), np.ascontiguousarray(M @ v0),
                  np.ascontiguousarray(K @ q0), pc, xs, es, track, prog)
    return state, e_c0


def with_acceleration(state: State, a0, B) -> None:
    """Set the state's acceleration, and the elements' local one, to ``a0``."""
    state.a[:] = a0
    state.xs[records.XA_N] = B @ a0


def output_arrays(grid: Ticks, ne: int, record_dofs, sensor_dofs, recovery) -> Outputs:
    """The recorded samples and the sensor stream, zeros, with the recovery maps."""
    n_out, n_sen = grid.n_out, grid.n_sensor_samples(sensor_dofs.size)
    empty = np.zeros((0, 0))
    shape = (n_sen, sensor_dofs.size)     # np.zeros, not zeros_like: pages untouched
    return Outputs(
        record_dofs, np.zeros((n_out, record_dofs.size)), np.zeros((n_out, ne), records.SAMPLE),
        np.zeros(n_out, records.ENERGY), sensor_dofs, np.zeros(shape), np.zeros(shape),
        np.zeros(shape),
        empty if recovery is None else np.ascontiguousarray(recovery[record_dofs].T),
        empty if recovery is None else np.ascontiguousarray(recovery[sensor_dofs].T))


def empty_logs(ne: int, n_lev: int, episode_capacity: int) -> Logs:
    """Empty logs (the segment log starts at four times the episode capacity)."""
    return Logs(np.zeros(episode_capacity, records.EPISODE),
                np.zeros(4 * episode_capacity, records.SEGMENT),
                np.zeros(256), np.zeros(256, np.int64), np.zeros(ne, records.STATS),
                np.zeros(n_lev, np.int64))


def grown_logs(logs: Logs, prog, ne: int) -> Logs:
    """``logs`` with room for another step (the kernel returned ``STATUS_LOG_FULL``): each
    log that could overflow doubled (the episode log plus n_e rows)."""
    ep, sg, lv_t, lv_l = logs.ep, logs.sg, logs.lv_t, logs.lv_l
    pr = prog[0]
    if pr["n_episodes"] + ne > ep.shape[0]:
        ep = np.concatenate([ep, np.zeros(ep.shape[0] + ne, records.EPISODE)])
    if pr["n_segments"] + ne > sg.shape[0]:
        sg = np.concatenate([sg, np.zeros_like(sg)])
    if pr["n_level_changes"] + 2 > lv_t.shape[0]:
        lv_t = np.concatenate([lv_t, np.zeros(lv_t.shape[0])])
        lv_l = np.concatenate([lv_l, np.zeros(lv_l.shape[0], np.int64)])
    return logs._replace(ep=ep, sg=sg, lv_t=lv_t, lv_l=lv_l)


def work_arrays(n: int, m: int, ne: int, profile: bool) -> Work:
    """Work arrays, and the cycle counters when profiling (else empty)."""
    return Work(np.zeros((WN_SIZE, n)), np.zeros((WC_SIZE, m)), np.zeros((m, m)),
                np.zeros((m, N_LOCAL_MAX)), np.zeros(5 * m, np.int64),
                np.zeros(ne, records.TRIAL),
                np.zeros(len(PROFILE_SECTIONS) if profile else 0, np.int64))


def run_record(grid: Ticks, settings: Settings) -> np.ndarray:
    """The kernel's ``run`` record (the end tick is set per call)."""
    run = np.zeros(1, records.RUN)
    run["dt"] = grid.dt_max
    run["base_level"] = grid.base
    run["step_error"] = settings.step_error if grid.base else 0.0
    run["tick_stop"] = grid.tick_total
    run["newton_tol"] = settings.newton_tol
    run["gap_jump"] = settings.gap_jump
    # the boosted update's landing point in the band (see augment_boost)
    run["aug_shift"] = 0.98 if settings.augment_boost > 0 else 0.0
    run["beta"] = settings.beta
    run["gamma"] = settings.gamma
    run["n_lev"] = grid.n_lev
    run["fixed"] = int(bool(grid.fixed_step))
    run["grow_after"] = settings.grow_after
    run["max_newton"] = settings.max_newton
    run["max_aug"] = settings.max_augment
    run["out_ticks"] = grid.out_ticks
    run["aug_strict"] = int(settings.augment_strict)
    run["sen_ticks"] = grid.sen_ticks
    return run
