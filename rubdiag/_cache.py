"""A disk cache of what runs compute from a rig alone: its reduced model, its critical speeds.

An entry is a NumPy ``.npz`` file of arrays named by the SHA-256 of its key: the kind of
entry, the rubdiag version and a digest of the sources that compute cached values, the numpy
and scipy versions, the machine and the BLAS libraries with their kernels
(:func:`rubdiag._blas.blas_signature`), and what the caller says the entry depends on (the
rig as in its TOML file, the reduction's settings). So an entry holds the bits the
computation gives in this environment: another version, edited code, another kernel set or a
changed rig is another file. The key is stored in the file too and compared when it is read.

Where: ``$RUBDIAG_CACHE_DIR``, else the platform's cache folder — ``$XDG_CACHE_HOME/rubdiag``
or ``~/.cache/rubdiag`` (``~/Library/Caches/rubdiag`` on macOS, ``%LOCALAPPDATA%\\rubdiag\\Cache``
on Windows). An empty ``RUBDIAG_CACHE_DIR`` switches the disk cache off. ``rubdiag cache``
prints the folder and what it holds, ``rubdiag cache --clear`` empties it; deleting the folder
by hand is safe at any time.

The cache is only a shortcut: a file that cannot be read (truncated, garbage, another key) is
ignored and rewritten; a folder that cannot be written is ignored; a file is written
atomically (:mod:`rubdiag._atomic`: a temporary file in the same folder, then renamed), so
that a parallel process never reads half of one.
"""

from __future__ import annotations

import functools
import hashlib
import io
import json
import os
import platform
import re
import sys
import zipfile
import zlib
from collections.abc import Callable
from pathlib import Path

import numpy as np

from rubdiag._atomic import write_bytes
from rubdiag._version import __version__

__all__ = ["ENV", "cached", "clear", "entries", "folder", "load", "sources_digest", "store"]

#: The environment variable naming the cache folder (empty: no disk cache)
ENV = "RUBDIAG_CACHE_DIR"
_KEY = "cache_key"
_ENTRY = re.compile(r"^[a-z0-9-]+-[0-9a-f]{32}\.npz$")
_TEMPORARY = re.compile(r"^\.[a-z0-9-]+-[0-9a-f]{32}\.npz\.[0-9]+\.[0-9]+\.tmp$")   # _atomic's
# what reading a damaged .npz raises (truncated: BadZipFile or EOFError; bad data: zlib,
# ValueError; a missing array: KeyError)
_UNREADABLE = (OSError, ValueError, KeyError, EOFError, zipfile.BadZipFile, zlib.error)


def folder() -> Path | None:
    """The cache folder (it may not exist yet), or None when the disk cache is off."""
    value = os.environ.get(ENV)
    if value is not None:
        return Path(value).expanduser() if value.strip() else None
    if sys.platform == "win32":
        local = os.environ.get("LOCALAPPDATA") or Path.home() / "AppData" / "Local"
        return Path(local) / "rubdiag" / "Cache"
    if sys.platform == "darwin":
        return Path.home() / "Library" / "Caches" / "rubdiag"
    return Path(os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache") / "rubdiag"


#: the code that computes or stores what is cached (globs under rubdiag/): its sources are
#: part of every key, so that an edited checkout (whose version string has not changed)
#: does not read stale entries
_SOURCES = ("_cache.py", "_blas.py", "_tolerances.py", "_fluidfilm.py", "model/*.py",
            "assembly/*.py", "modal/*.py", "reduce/*.py", "simulation/_rig_cache.py")


@functools.cache
def environment() -> dict:
    """What, besides its inputs, decides the bits of a cached computation."""
    import scipy

    from rubdiag._blas import blas_signature

    return {"rubdiag": __version__, "sources": sources_digest(), "numpy": np.__version__,
            "scipy": scipy.__version__, "machine": platform.machine(),
            "blas": blas_signature()}


def sources_digest(patterns: tuple[str, ...] = _SOURCES) -> str:
    """SHA-256 of the package's source files matching ``patterns`` (globs relative to the
    package folder), names and contents, as they are on disk now."""
    package = Path(__file__).parent
    digest = hashlib.sha256()
    for pattern in patterns:
        for source in sorted(package.glob(pattern)):
            digest.update(source.relative_to(package).as_posix().encode() + source.read_bytes())
    return digest.hexdigest()


def key(kind: str, depends_on: dict) -> str:
    """The key of an entry: canonical JSON of its kind, :func:`environment` and
    ``depends_on`` (JSON-ready data; floats are written exactly)."""
    if not re.fullmatch(r"[a-z0-9-]+", kind):
        raise ValueError(f"kind = {kind!r} is not allowed (allowed: lower-case letters, "
                         "digits and '-')")
    return json.dumps({"kind": kind, "environment": environment(), "depends_on": depends_on},
                      sort_keys=True, separators=(",", ":"), allow_nan=True)


def path(kind: str, depends_on: dict) -> Path | None:
    """The file of an entry (None when the disk cache is off)."""
    where = folder()
    if where is None:
        return None
    digest = hashlib.sha256(key(kind, depends_on).encode()).hexdigest()[:32]
    return where / f"{kind}-{digest}.npz"


def load(kind: str, depends_on: dict, names: tuple[str, ...]) -> dict[str, np.ndarray] | None:
    """The arrays ``names`` of an entry, or None: no such entry, the cache is off, or the
    file cannot be read or holds another key."""
    file = path(kind, depends_on)
    if file is None or not file.is_file():
        return None
    try:
        with np.load(file, allow_pickle=False) as archive:
            if str(archive[_KEY]) != key(kind, depends_on):
                return None
            return {name: archive[name] for name in names}
    except _UNREADABLE:
        return None


def store(kind: str, depends_on: dict, arrays: dict[str, np.ndarray]) -> Path | None:
    """Write an entry atomically; its path, or None when the cache is off or the folder
    cannot be written (the caller has its result either way)."""
    file = path(kind, depends_on)
    if file is None:
        return None
    sink = io.BytesIO()
    np.savez(sink, **{_KEY: np.array(key(kind, depends_on))}, **arrays)
    try:
        file.parent.mkdir(parents=True, exist_ok=True)
        return write_bytes(file, sink.getvalue())
    except OSError:
        return None


def cached(kind: str, depends_on: dict, names: tuple[str, ...],
           compute: Callable[[], dict[str, np.ndarray]]) -> tuple[dict[str, np.ndarray], bool]:
    """The arrays ``names`` of an entry from disk, or ``compute()``'s (then stored); and
    whether they were read from disk."""
    arrays = load(kind, depends_on, names)
    if arrays is not None:
        return arrays, True
    arrays = compute()
    store(kind, depends_on, arrays)
    return arrays, False


def entries() -> list[Path]:
    """The cache's entry files (not other files a user keeps in the same folder)."""
    where = folder()
    if where is None or not where.is_dir():
        return []
    return sorted(p for p in where.iterdir() if _ENTRY.match(p.name) or _TEMPORARY.match(p.name))


def clear() -> int:
    """Delete the cache's entry files; how many were deleted."""
    removed = 0
    for file in entries():
        try:
            file.unlink()
            removed += 1
        except FileNotFoundError:    # another process removed it meanwhile
            pass
    return removed
