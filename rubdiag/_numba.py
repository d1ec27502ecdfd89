"""The one place where Numba is configured.

Every kernel in rubdiag is decorated with :func:`njit` from here, so that all of them are
cached on disk (``cache=True``: compiled once per machine, not once per process) and none
uses ``fastmath`` (the contact law compares small differences of large numbers).

Kernel contract: arguments are float64/int64 C-contiguous arrays, floats and ints in SI units;
no Python objects; outputs are preallocated by the caller; status codes, not exceptions.
"""

from __future__ import annotations

import contextlib
import functools
import hashlib
import os
from pathlib import Path

import numba

try:
    import fcntl
except ImportError:     # Windows: no advisory locks; the check still runs once per process
    fcntl = None

njit = functools.partial(numba.njit, cache=True, fastmath=False, nogil=True)

_FINGERPRINT = "rubdiag-sources.sha256"


@functools.cache
def fresh_cache(package: str | Path) -> bool:
    """:func:`drop_stale_cache` once per process, under an exclusive lock shared by every
    process (parallel workers starting together must not delete a cache another has just
    rebuilt). Call before a package's first kernel call. Returns True when it was dropped."""
    package = Path(package)
    with _locked(package / "__pycache__" / "rubdiag-cache.lock"):
        return drop_stale_cache(package)


@contextlib.contextmanager
def _locked(path: Path):
    try:
        path.parent.mkdir(exist_ok=True)
        handle = open(path, "a")
    except OSError:                 # a read-only install: Numba caches elsewhere
        yield
        return
    with handle:
        if fcntl is not None:
            fcntl.flock(handle, fcntl.LOCK_EX)
        yield


def drop_stale_cache(package: str | Path) -> bool:
    """Delete a kernel package's Numba cache when any of its source files changed.

    Numba keys a cached kernel on its own file only: a kernel that calls functions from
    another file keeps a stale build when only that file changes. A fingerprint of all the
    package's sources, kept beside the cache, catches that. Returns True when the cache was
    dropped. A cache folder we cannot write to is left alone (Numba then caches elsewhere).
    """
    package = Path(package)
    digest = hashlib.sha256()
    for source in sorted(package.glob("*.py")):
        digest.update(source.name.encode() + source.read_bytes())
    fingerprint = digest.hexdigest()
    cache = package / "__pycache__"
    stamp = cache / _FINGERPRINT
    try:
        if stamp.is_file() and stamp.read_text() == fingerprint:
            return False
        cache.mkdir(exist_ok=True)
        for entry in [*cache.glob("*.nbi"), *cache.glob("*.nbc")]:
            entry.unlink(missing_ok=True)
        tmp = stamp.with_name(f"{stamp.name}.{os.getpid()}")
        tmp.write_text(fingerprint)
        tmp.replace(stamp)
    except OSError:
        return False
    return True
