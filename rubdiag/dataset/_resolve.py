"""What a design's runs refer to before they are made, each computed once, in parallel.

A design point's speed is a ratio of a speed of its own rotor — a forward critical speed
(``speed_ratio``) or the threshold of instability (``whirl_speed_ratio``), an eigenvalue
search each — and a rub run's gap with ``interference_ratio`` is its linear approach over
the ratio (a harmonic solve per speed). Many points share a rotor: the model-uncertainty
factors take a few levels each, so a design of hundreds of runs has a few dozen rotors.

:func:`critical_speeds_rad_s` and :func:`whirl_threshold_rad_s` keep each rotor's value
for the process; :func:`resolve_rotors` computes the missing ones of a design at once,
spread over worker processes (:class:`Workers`), and :func:`start_approaches` the runs'
linear approaches, one task per rig (one model for all its runs). Every value is
computed by the same code on one BLAS thread wherever it runs, so a design's runs, and
their ids, are the same bits on any number of workers.
"""

from __future__ import annotations

import os
from collections.abc import Callable, Sequence

__all__ = ["Workers", "critical_speeds_rad_s", "resolve_rotors", "start_approaches",
           "whirl_threshold_rad_s"]

# (rig, n) -> its n lowest forward critical speeds; rig -> its threshold of instability
_CRITICAL: dict = {}
_THRESHOLD: dict = {}


def critical_speeds_rad_s(rig, n: int) -> tuple[float, ...]:
    """The ``n`` lowest forward critical speeds (rad/s) of ``rig``
    (:func:`rubdiag.simulation._rig_cache.forward_critical_speeds`), once per process."""
    key = (rig, n)
    if key not in _CRITICAL:
        _CRITICAL[key] = _one_thread(_critical, key)
    return _value(_CRITICAL[key])


def whirl_threshold_rad_s(rig, critical_rig) -> float:
    """The threshold of instability (rad/s) of ``rig``
    (:func:`rubdiag.dataset._faults.threshold_for`), searched between the critical speeds
    of ``critical_rig`` — the same rotor, whatever its damping (the critical speed map is
    undamped) — once per process."""
    if rig not in _THRESHOLD:
        _THRESHOLD[rig] = _one_thread(_threshold, (rig, critical_speeds_rad_s(critical_rig, 2)))
    return _value(_THRESHOLD[rig])


def _value(found):
    """A kept value, or the ValueError its computation raised (raised again for each point
    that needs it, so that its message names that point)."""
    if isinstance(found, ValueError):
        raise ValueError(str(found))
    return found


def resolve_rotors(critical: Sequence, thresholds: Sequence,
                   workers: Workers) -> Callable[[], None]:
    """Compute, on ``workers``, what :func:`critical_speeds_rad_s` and
    :func:`whirl_threshold_rad_s` do not hold yet: ``critical``, (rig, n) pairs, and
    ``thresholds``, (rig, critical_rig) pairs. The critical speeds are computed here (the
    thresholds' searches start from them); the thresholds are started, and the returned
    function waits for them."""
    needed = [*critical, *((rig, 2) for _, rig in thresholds)]
    missing = [key for key in dict.fromkeys(needed) if key not in _CRITICAL]
    _CRITICAL.update(zip(missing, workers.map(_critical, missing), strict=True))
    pending = [(rig, _CRITICAL[(base, 2)]) for rig, base in dict.fromkeys(thresholds)
               if rig not in _THRESHOLD and not isinstance(_CRITICAL[(base, 2)], ValueError)]
    found = workers.start(_threshold, pending)

    def wait() -> None:
        _THRESHOLD.update(zip((rig for rig, _ in pending), found(), strict=True))

    return wait


def start_approaches(runs: Sequence, workers: Workers,
                     of: Sequence | None = None) -> Callable[[], list]:
    """Start computing the largest linear approach (m) of each run of ``runs`` over its
    analysis window (:func:`rubdiag.dataset._approach.sweep_linear_approach_m`; ``of``: for
    each run, the contacts it is taken at — None, "blades" or "seals" — default all) on
    ``workers``, one task per rig; the returned function waits for them: a list, each the
    approach or the ValueError computing it raised, in the runs' order."""
    of = [None] * len(runs) if of is None else list(of)
    by_rig: dict = {}
    for k, run in enumerate(runs):
        by_rig.setdefault(run.rig, []).append(k)
    groups = list(by_rig.values())
    found = workers.start(_approaches, [[(runs[k], of[k]) for k in group]
                                        for group in groups])

    def result() -> list:
        out = [0.0] * len(runs)
        for group, values in zip(groups, found(), strict=True):
            for k, value in zip(group, values, strict=True):
                out[k] = value
        return out

    return result


def _critical(key) -> tuple[float, ...] | ValueError:
    from rubdiag.simulation._rig_cache import forward_critical_speeds

    return _outcome(forward_critical_speeds, *key)


def _threshold(task) -> float | ValueError:
    from rubdiag.dataset._faults import threshold_for

    return _outcome(threshold_for, *task)


def _approaches(tasks) -> list[float | ValueError]:
    """The approaches of runs that share one rig (one model): ``tasks`` (run, of) pairs."""
    from rubdiag.dataset._approach import damped_model, sweep_linear_approach_m

    model = damped_model(tasks[0][0].rig)
    return [_outcome(sweep_linear_approach_m, run, model, of) for run, of in tasks]


def _outcome(function: Callable, *args):
    """``function(*args)``, or the ValueError it raised."""
    try:
        return function(*args)
    except ValueError as exc:
        return exc


def _one_thread(function: Callable, task):
    """``function(task)`` on one BLAS thread, as a worker computes it."""
    from threadpoolctl import threadpool_limits

    with threadpool_limits(limits=1):
        return function(task)


class Workers:
    """Worker processes for a design's computations (a context manager): ``jobs`` local
    processes (None: every core), or this process alone when ``jobs`` is 1 or the work has
    a single task. :meth:`map` returns the results in the tasks' order; an exception a
    task raises is raised here."""

    def __init__(self, jobs: int | None = 1):
        self.jobs = (os.cpu_count() or 1) if jobs is None else jobs
        self._pool = None

    def __enter__(self) -> Workers:
        return self

    def __exit__(self, *exc) -> None:
        if self._pool is not None:
            self._pool.shutdown(cancel_futures=True)
            self._pool = None

    def map(self, function: Callable, tasks: Sequence) -> list:
        """``[function(task) for task in tasks]``, the tasks spread over the workers."""
        return self.start(function, tasks)()

    def start(self, function: Callable, tasks: Sequence) -> Callable[[], list]:
        """Start :meth:`map`; the returned function waits for its results. This process is
        free meanwhile (in this process alone, the tasks run when the results are asked)."""
        tasks = list(tasks)
        if self.jobs == 1 or len(tasks) <= 1:
            return lambda: [_one_thread(function, task) for task in tasks]
        if self._pool is None:
            from concurrent.futures import ProcessPoolExecutor

            from rubdiag.dataset._workers import start_local_worker

            self._pool = ProcessPoolExecutor(max_workers=self.jobs,
                                             initializer=start_local_worker)
        futures = [self._pool.submit(function, task) for task in tasks]
        return lambda: [future.result() for future in futures]
