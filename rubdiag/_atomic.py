"""Files that are whole or absent: the one way rubdiag writes a file a reader may open.

The data goes into a hidden temporary file in the same folder (named by this process and
thread, so parallel writers never share one), is flushed to disk, and is renamed over the
target (atomic on POSIX and Windows). A job killed at any moment leaves the old file or the
new one, never half of one; what it may leave is a ``.<name>.<pid>.<thread>.tmp`` file, which
readers ignore (their names start with a dot) and the dataset folder removes on its next job.
"""

from __future__ import annotations

import os
import threading
from pathlib import Path

__all__ = ["write_bytes", "write_text"]


def write_bytes(path: str | os.PathLike, data: bytes) -> Path:
    """Write ``data`` to ``path`` atomically (module docstring); the path."""
    path = Path(path)
    tmp = path.with_name(f".{path.name}.{os.getpid()}.{threading.get_ident()}.tmp")
    try:
        with open(tmp, "wb") as f:
            f.write(data)
            f.flush()
            os.fsync(f.fileno())
        os.replace(tmp, path)
    except BaseException:
        tmp.unlink(missing_ok=True)
        raise
    return path


def write_text(path: str | os.PathLike, text: str) -> Path:
    """Write ``text`` (UTF-8) to ``path`` atomically; the path."""
    return write_bytes(path, text.encode("utf-8"))
