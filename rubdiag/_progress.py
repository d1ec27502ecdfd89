"""Progress of long work on stderr: a tqdm bar with an ETA on a terminal, silence elsewhere.

Every long command (``dataset``, ``faults``, ``train``, ``evaluate``, ``table2``, a
multi-file ``predict``…) reports through :func:`bar`, so they all look alike and all obey
the same rule: shown only when stderr is a terminal and the user did not ask for quiet
(``--quiet``), so that logs, pipes and tests see nothing. The Python functions behind them
take ``progress=False`` by default and pass it here.
"""

from __future__ import annotations

import sys

__all__ = ["bar", "steps"]


def bar(total: int | float | None, desc: str, unit: str = "run", enabled: bool = True,
        stream=None):
    """A progress bar over ``total`` items of ``unit`` (None: unknown) on ``stream`` (default
    stderr), labelled ``desc``; disabled unless ``enabled`` and ``stream`` is a terminal. Use
    it as tqdm's: ``update(n)``, ``close()`` or a ``with`` block."""
    from tqdm import tqdm

    return tqdm(total=total, desc=desc, unit=unit, file=sys.stderr if stream is None
                else stream, disable=None if enabled else True, dynamic_ncols=True,
                mininterval=0.5, leave=False)


def steps(items, desc: str, unit: str = "run", enabled: bool = True, total: int | None = None,
          stream=None):
    """``items`` as they are iterated, with a :func:`bar` over them (``total``: their count,
    default ``len(items)`` where it has one)."""
    if total is None and hasattr(items, "__len__"):
        total = len(items)
    with bar(total, desc, unit, enabled, stream) as progress:
        for item in items:
            yield item
            progress.update(1)
