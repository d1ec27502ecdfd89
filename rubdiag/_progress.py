"""Progress of long work on stderr: a tqdm bar with an ETA on a terminal, silence elsewhere.

Every long command (``dataset``, ``faults``, ``train``, ``evaluate``, ``table2``,
``simulate``, ``runup``, ``campbell``, a multi-file ``predict``…) reports through
:func:`bar`, so they all look alike and all obey the same rule: shown only when stderr is a
terminal and the user did not ask for quiet (``--quiet``), so that logs, pipes and tests see
nothing. The Python functions behind them take ``progress=False`` by default and pass it
here. A finished bar stays on screen: its last line says how long the work took.

Work that calls another piece of long work passes its open bar down as ``progress``
(:func:`shared`: the callee adds its steps to the caller's bar); simulations report the
seconds they have simulated (:func:`simulated`, :func:`following`).
"""

from __future__ import annotations

import sys
from collections.abc import Callable
from contextlib import contextmanager
from functools import cache

__all__ = ["bar", "counted", "following", "label", "part", "shared", "simulated", "steps",
           "write"]

#: A bar over simulated time: seconds to two decimals, not a rate of "s/s".
_SIMULATED_FORMAT = ("{desc}: {percentage:3.0f}%|{bar}| {n:.2f}/{total:.2f} s simulated "
                     "[{elapsed}<{remaining}{postfix}]")


@cache
def _tqdm():
    from tqdm import tqdm

    class Bar(tqdm):
        # No monitor thread: worker pools fork after a bar opens, and a fork must not copy
        # a thread that may hold tqdm's lock. miniters=1 does the monitor's job: every
        # update is checked against mininterval.
        monitor_interval = 0

    return Bar


def bar(total: int | float | None, desc: str, unit: str = "run", enabled: bool = True,
        stream=None, **options):
    """A progress bar over ``total`` items of ``unit`` (None: unknown) on ``stream`` (default
    stderr), labelled ``desc``; disabled unless ``enabled`` and ``stream`` is a terminal. Use
    it as tqdm's: ``update(n)``, ``close()`` or a ``with`` block. ``options`` go to tqdm
    (``bar_format`` …)."""
    return _tqdm()(total=total, desc=desc, unit=unit,
                   file=sys.stderr if stream is None else stream,
                   disable=None if enabled else True, dynamic_ncols=True, mininterval=0.5,
                   miniters=1, leave=True, **options)


def steps(items, desc: str, unit: str = "run", enabled: bool = True, total: int | None = None,
          stream=None):
    """``items`` as they are iterated, with a :func:`bar` over them (``total``: their count,
    default ``len(items)`` where it has one)."""
    if total is None and hasattr(items, "__len__"):
        total = len(items)
    with bar(total, desc, unit, enabled, stream) as progress:
        yield from counted(items, progress.update)


def counted(items, on_item: Callable[[], object] | None = None):
    """``items`` as they are iterated, calling ``on_item()`` (e.g. an open bar's ``update``)
    after each, once the loop's body is done with it (a ``continue`` included)."""
    for item in items:
        yield item
        if on_item is not None:
            on_item()


@contextmanager
def part(progress, n: int):
    """A part of the work worth ``n`` steps of the open bar ``progress``, which counts its
    own steps with the ``update`` it is given: the steps it did not count (work it found it
    could skip) are counted when it ends, so that the bar reaches its total."""
    start = progress.n
    yield progress.update
    if progress.n < start + n:
        progress.update(start + n - progress.n)


@contextmanager
def shared(progress, total: int, desc: str, unit: str = "step", stream=None):
    """A bar for ``total`` more steps of work: ``progress`` itself when it is an open bar
    (a caller's, e.g. ``train``'s around ``evaluate``: its total grows by ``total`` and it
    stays open), else a new :func:`bar` shown when ``progress`` is true."""
    if hasattr(progress, "update"):
        progress.total = (progress.total or 0) + total
        progress.refresh()
        yield progress
        return
    with bar(total, desc, unit, bool(progress), stream) as new:
        yield new


def simulated(total_s: float, desc: str, enabled: bool = True, stream=None):
    """A :func:`bar` over ``total_s`` seconds of simulated time (the durations of the runs
    to simulate, summed); :func:`following` moves it as a run goes."""
    return bar(round(total_s, 3), desc, "s", enabled, stream, bar_format=_SIMULATED_FORMAT)


def following(progress, start_s: float, span_s: float) -> Callable[[float, float], None] | None:
    """The ``progress(t, duration)`` callback of :func:`rubdiag.simulation.simulate` that moves
    the bar ``progress`` (a :func:`simulated` bar) from ``start_s`` to ``start_s + span_s``
    as the run goes from 0 to its end (s); None when the bar is not shown, so that a quiet
    run is integrated in one piece, as without a bar."""
    if progress.disable:
        return None

    def report(t: float, duration: float) -> None:
        progress.update(round(start_s + span_s * min(t / duration, 1.0), 3) - progress.n)
    return report


def label(progress, text: str) -> None:
    """Say beside the bar ``progress`` what it is doing now."""
    progress.set_postfix_str(text)


def write(message: str, stream=None) -> None:
    """``message`` as a line on ``stream`` (default stderr), above any bar open on it."""
    _tqdm().write(message, file=sys.stderr if stream is None else stream)
