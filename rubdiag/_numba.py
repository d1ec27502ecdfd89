"""The one place where Numba is configured.

Every kernel in rubdiag is decorated with :func:`njit` from here, so that all of them are
cached on disk (``cache=True``: compiled once per machine, not once per process) and none
uses ``fastmath`` (the contact law compares small differences of large numbers).

Kernel contract: arguments are float64/int64 C-contiguous arrays, floats and ints in SI units;
no Python objects; outputs are preallocated by the caller; status codes, not exceptions.
"""

from __future__ import annotations

import functools

import numba

njit = functools.partial(numba.njit, cache=True, fastmath=False, nogil=True)
