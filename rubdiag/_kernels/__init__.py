"""Numba kernels: sparse triangular solves, contact laws and the Newmark time loop.

* :mod:`rubdiag._kernels.sparse_lu` — CSR products, SuperLU factors applied in Numba.
* :mod:`rubdiag._kernels.elements` — the seam for nonlinear elements: local coordinates,
  the law of each kind (:mod:`~rubdiag._kernels.point_contact`,
  :mod:`~rubdiag._kernels.annular_contact`, with :mod:`~rubdiag._kernels.contact_books`) and
  the per-step element solve in the Schur complement (Newton + augmented Lagrangian);
  :mod:`rubdiag._kernels.extend` compiles a kernel that also knows kinds defined elsewhere.
* :mod:`rubdiag._kernels.newmark` — the whole time loop (variable step, event log, energy),
  on named bundles of arrays (``Linear``, ``Factors``, ``Elements``, ``State`` …).
* :mod:`rubdiag._kernels.clock` — a CPU cycle counter for the kernels' profiled runs.
* :mod:`rubdiag._kernels.records` — the structured records the kernel and its caller share
  (the run's parameters, the loop's counters, each element's record, the logs), by name.

Kernel contract (see :mod:`rubdiag._numba`): float64 / int64 C-contiguous arrays and scalars in
SI units, outputs and work arrays preallocated by the caller, status codes instead of
exceptions. The public door is :mod:`rubdiag.simulation`.

Numba's on-disk cache is keyed on the source file of the *called* kernel only:
``newmark_contact`` inlines code from ``elements.py``, the kinds' modules and
``sparse_lu.py``, and its cache entry would not be invalidated when only those files
change. :func:`ensure_fresh_cache` drops the whole cache when any kernel source changed;
callers run it before their first kernel call (importing the package has no side effect).
"""

from pathlib import Path

from rubdiag._numba import fresh_cache

__all__ = ["ensure_fresh_cache"]


def ensure_fresh_cache() -> bool:
    """Drop the kernels' Numba cache if any kernel source changed since it was built (once
    per process, under a lock shared with other processes). True when it was dropped."""
    return fresh_cache(Path(__file__).parent)
