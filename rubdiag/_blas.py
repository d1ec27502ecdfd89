"""One set of OpenBLAS kernels on every x86-64 CPU, so that a run gives the same bits anywhere.

OpenBLAS picks its kernels for the CPU it finds (SkylakeX on AVX-512 machines, Haswell or Zen
on AVX2 ones), and the kernels round differently. The simulator's inputs (steady state, Rayleigh
coefficients, modes) come from LAPACK, and a rub run is chaotic: a difference in the last bit
of an input becomes a different list of contact episodes after a second. Measured: the
documentation's case-2 sample run gives 315 sliding / 192 sticking entries with the SkylakeX
kernels and 332 / 201 with the Haswell ones, on the same machine.

OpenBLAS reads ``OPENBLAS_CORETYPE`` once, when it is loaded, so :func:`pin_blas_kernels`
must run before numpy or scipy is imported. Importing rubdiag does not call it (importing a
library changes nothing of its process); where runs start, it is called: the ``rubdiag``
command line first thing, a dataset's local workers as they start, and a library user's
script or notebook (``rubdiag.pin_blas_kernels()`` before ``import numpy``). What the
environment already says is kept (a user's choice, or a parent process's, which child
processes inherit). Where numpy came first, this process keeps the kernels OpenBLAS chose, and
the environment names them, so that the worker processes it starts use the same ones (results
still do not depend on the number of workers; they may differ in the last bits from another
CPU's).
"""

from __future__ import annotations

import os
import platform
import sys

#: the kernels pinned on x86-64 CPUs with AVX2 (every x86-64 CPU made since 2015)
KERNELS = "Haswell"
_VARIABLE = "OPENBLAS_CORETYPE"


def pin_blas_kernels() -> str | None:
    """Pin OpenBLAS's kernels to :data:`KERNELS` for this process and those it starts, so that
    runs give the same bits on every x86-64 CPU.

    Call it before numpy or scipy is imported (OpenBLAS reads its kernel choice once, when it
    loads)::

        import rubdiag
        rubdiag.pin_blas_kernels()
        import numpy as np

    The ``rubdiag`` command line and a dataset's workers call it themselves. An
    ``OPENBLAS_CORETYPE`` already in the environment is kept. Called after numpy, it cannot
    change this process's kernels: it names the ones in use in the environment, so that
    worker processes use them too, and warns (``RuntimeWarning``) when they are not
    :data:`KERNELS` (runs may then differ in their last bits from another machine's).

    Returns
    -------
    str or None
        The kernel set this process and its children run (e.g. ``'Haswell'``); None where
        none is pinned (a CPU without AVX2, or not x86-64).
    """
    late = _VARIABLE not in os.environ and ("numpy" in sys.modules or "scipy" in sys.modules)
    chosen = _pin()
    if late and chosen != KERNELS and _has_avx2():
        import warnings

        warnings.warn(f"numpy was imported before rubdiag.pin_blas_kernels(): this process "
                      f"runs OpenBLAS's {chosen} kernels, not {KERNELS}, and its runs may "
                      f"differ in the last bits from another machine's (call it before "
                      f"importing numpy, or start Python with {_VARIABLE}={KERNELS})",
                      RuntimeWarning, stacklevel=2)
    return chosen


def _pin() -> str | None:
    """:func:`pin_blas_kernels` without its warning (a worker follows its parent's kernels)."""
    if _VARIABLE in os.environ:
        return os.environ[_VARIABLE]
    if "numpy" in sys.modules or "scipy" in sys.modules:
        chosen = kernels_in_use()
    else:
        chosen = KERNELS if _has_avx2() else None
    if chosen is not None:
        os.environ[_VARIABLE] = chosen
    return chosen


def _has_avx2() -> bool:
    if platform.machine().lower() not in ("x86_64", "amd64"):
        return False
    try:
        with open("/proc/cpuinfo", encoding="ascii", errors="replace") as cpuinfo:
            for line in cpuinfo:
                if line.startswith("flags"):
                    return "avx2" in line.split()
    except OSError:
        pass
    return False


def kernels_in_use() -> str | None:
    """The kernel set this process's OpenBLAS runs (e.g. ``'Haswell'``), or None without one."""
    from threadpoolctl import threadpool_info

    names = {info.get("architecture") for info in threadpool_info()
             if info.get("internal_api") == "openblas"}
    return names.pop() if len(names) == 1 else None


def one_thread(user_api: str | None = "blas"):
    """A context in which the BLAS libraries (``user_api=None``: OpenMP ones too) run on
    one thread (threadpoolctl).

    Used around a run's dense linear algebra (the reduction, the steady state, the step
    operators). The matrices are small (≤ a few hundred rows), where threads gain nothing;
    on busy cores OpenBLAS's threads spin waiting for each other against the other jobs
    (a reduced run's set-up took 6 s instead of 0.1 s beside two CPU-bound processes); and a
    multithreaded product sums in another order, so that a reduced run's bits depended on
    the machine's core count."""
    return _controller().limit(limits=1, user_api=user_api)


_CONTROLLER: tuple = (-1, None)     # (modules loaded when it was made, the controller)


def _controller():
    """This process's thread-pool libraries (a ``threadpoolctl.ThreadpoolController``),
    found again only when a module was imported since: finding them walks every loaded
    shared object (2–3 ms, twice per dataset row, where a run's rest takes 0.1 s), and a
    library can only have come with a new module."""
    global _CONTROLLER
    from threadpoolctl import ThreadpoolController

    loaded = len(sys.modules)
    if _CONTROLLER[0] != loaded:
        _CONTROLLER = (loaded, ThreadpoolController())
    return _CONTROLLER[1]


def blas_signature() -> list[list[str]]:
    """The BLAS libraries this process runs, as ``[internal_api, version, kernels]`` rows
    (sorted; numpy's and scipy.linalg's): what, besides the library versions, decides the
    bits of a LAPACK result. Loads scipy.linalg, so that the answer does not depend on
    whether it was loaded yet."""
    import scipy.linalg  # noqa: F401  (its BLAS library, where it brings its own)
    from threadpoolctl import threadpool_info

    rows = {(str(i.get("internal_api")), str(i.get("version")), str(i.get("architecture")))
            for i in threadpool_info() if i.get("user_api") == "blas"}
    return [list(row) for row in sorted(rows)]


def no_threads_in_this_process() -> bool:
    """Tell OpenBLAS, before it loads, to start no worker threads in this process; True when
    that was still possible.

    For a process that does one run and nothing else (``rubdiag simulate``): the run's BLAS
    work is on one thread anyway (:func:`one_thread`), but threads OpenBLAS starts when it
    loads spin for a while: with numpy's and scipy's two copies on 2 cores, ≈ 0.15 s of CPU
    and 0.1 s of wall, a tenth of a reduced run's process. A user's own
    ``OPENBLAS_NUM_THREADS`` is kept; once numpy or scipy is loaded (a Python session, the
    tests) nothing is changed."""
    if "numpy" in sys.modules or "scipy" in sys.modules:
        return False
    os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
    return True
