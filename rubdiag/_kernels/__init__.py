"""Numba kernels: sparse triangular solves, contact laws and the Newmark time loop.

* :mod:`rubdiag._kernels.newmark` — the time loop's controller (variable step, rejections,
  the order of a step's parts), on named bundles of arrays laid out as
  :mod:`rubdiag._kernels.interface` says, with record types from
  :mod:`rubdiag._kernels.records`. Its parts: :mod:`~rubdiag._kernels.increment` (the
  right-hand side, the increment, the new state), :mod:`~rubdiag._kernels.products` (dense
  and M, K products), :mod:`~rubdiag._kernels.sparse_lu` (CSR products, SuperLU factors
  applied), :mod:`~rubdiag._kernels.load` (the load's factors),
  :mod:`~rubdiag._kernels.step_control` (levels, rejections, long steps' error),
  :mod:`~rubdiag._kernels.ledger` (energy, episodes, each element's totals) and
  :mod:`~rubdiag._kernels.recording` (the samples).
* :mod:`rubdiag._kernels.elements` — the seam for nonlinear elements: local coordinates and
  the law of each kind (:mod:`~rubdiag._kernels.point_contact`,
  :mod:`~rubdiag._kernels.annular_contact` with :mod:`~rubdiag._kernels.contact_books`,
  :mod:`~rubdiag._kernels.crack`, :mod:`~rubdiag._kernels.pedestal`,
  :mod:`~rubdiag._kernels.journal`); :mod:`~rubdiag._kernels.element_solve` the per-step
  element solve in the Schur complement (Newton + augmented Lagrangian);
  :mod:`rubdiag._kernels.extend` compiles a kernel that also knows kinds defined elsewhere.
* :mod:`rubdiag._kernels.clock` — a CPU cycle counter for the kernels' profiled runs.

Kernel contract (see :mod:`rubdiag._numba`): float64 / int64 C-contiguous arrays and scalars in
SI units, outputs and work arrays preallocated by the caller, status codes instead of
exceptions. The public door is :mod:`rubdiag.simulation`. With ``NUMBA_DISABLE_JIT=1`` the
kernels run as plain Python on the same arrays (``make test-nojit``), which is how their
coverage is measured and a failing step can be stepped through in a debugger.

Numba's on-disk cache is keyed on the source file of the *called* kernel only:
``newmark_contact`` inlines code from its parts' modules and the kinds', and its cache entry
would not be invalidated when only those files change. :func:`ensure_fresh_cache` drops the
whole cache when any kernel source changed; callers run it before their first kernel call
(importing the package has no side effect).
"""

from pathlib import Path

from rubdiag._numba import fresh_cache

__all__ = ["ensure_fresh_cache"]


def ensure_fresh_cache() -> bool:
    """Drop the kernels' Numba cache if any kernel source changed since it was built (once
    per process, under a lock shared with other processes). True when it was dropped."""
    return fresh_cache(Path(__file__).parent)
