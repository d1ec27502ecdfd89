"""One dataset row per run: what a worker computes and sends back to the writer.

:func:`make_row` simulates one :class:`~rubdiag.dataset.DesignRun`, labels it
(:mod:`rubdiag.dataset.labels`) and computes its features (:func:`rubdiag.runs.run_features`);
it never raises for the run's sake: a diverging, failing or timed-out run becomes a row with
its ``status`` and ``message`` and no labels or features. It runs in a local worker process
or on a Dask worker alike and holds no state between calls, so a row depends on the run
alone — whatever the worker, the number of workers or the scheduler. BLAS is held to one
thread while it runs (the linear algebra is then the same on every worker, and parallelism
is across runs).

Columns, in order: :data:`ID_COLUMNS`, the design point's factors (as the design names
them), ``speed_rpm`` (the run's speed), the measures and labels, the features, then
:data:`PROVENANCE` (``rubdiag_version``, ``status``, ``message``, ``wall_s``), which the
determinism checks leave out.
"""

from __future__ import annotations

import math
import time

from rubdiag._version import __version__
from rubdiag.dataset.labels import LabelRules, label_run

__all__ = ["ID_COLUMNS", "PROVENANCE", "STATUSES", "RunTimeout", "make_row"]

ID_COLUMNS = ("run_id", "point_id", "replicate")
PROVENANCE = ("rubdiag_version", "status", "message", "wall_s")
#: ``status`` of a row: finished; stopped by the simulator (no convergence, non-finite
#: state); over the per-run wall-time limit; anything else that raised.
STATUSES = ("ok", "diverged", "timeout", "error")

# run_features' description columns that the row states otherwise (ids, factors, status)
_DROPPED = ("label", "status", "gap_m", "friction_coefficient", "dt_s", "speed_rpm",
            "window_s")


class RunTimeout(RuntimeError):
    """A run took longer than its wall-time limit."""


def make_row(item, rules: LabelRules | None = None,
             run_timeout_s: float | None = None) -> dict:
    """The dataset row of ``item`` (a :class:`~rubdiag.dataset.DesignRun`)."""
    from threadpoolctl import threadpool_limits  # installed with scikit-learn

    rules = LabelRules() if rules is None else rules
    start = time.perf_counter()
    row = {"run_id": item.run_id, "point_id": item.point_id, "replicate": item.replicate,
           **item.point, "speed_rpm": item.run.speed_rpm}
    with threadpool_limits(limits=1):
        try:
            computed = _simulate_and_describe(item.run, rules, run_timeout_s, start)
            status, message = "ok", ""
        except RunTimeout as exc:
            computed, status, message = {}, "timeout", str(exc)
        except Exception as exc:   # a failed run is data, never the end of the job
            from rubdiag.simulate import SimulationDiverged

            kind = "diverged" if isinstance(exc, SimulationDiverged) else "error"
            computed, status = {}, kind
            message = f"{type(exc).__name__}: {exc}".splitlines()[0][:500]
    row.update(computed)
    row.update(rubdiag_version=__version__, status=status, message=message,
               wall_s=time.perf_counter() - start)
    return row


def _simulate_and_describe(run, rules, run_timeout_s, start) -> dict:
    from rubdiag.runs import run_features
    from rubdiag.simulate import simulate

    def watchdog(t, duration):
        elapsed = time.perf_counter() - start
        if elapsed > run_timeout_s:
            raise RunTimeout(f"stopped after {elapsed:.1f} s of wall time at t = {t:.4g} s "
                             f"of {duration:.4g} s (--run-timeout {run_timeout_s:g} s)")

    result = simulate(run, progress=None if run_timeout_s is None else watchdog)
    labelled = label_run(result, rules)
    features = run_features(result).iloc[0].to_dict()
    for key in _DROPPED:
        features.pop(key, None)
    return {**labelled, **{k: _plain(v) for k, v in features.items()}}


def _plain(value):
    """Python scalars (numpy scalars would not round-trip through Arrow identically)."""
    if hasattr(value, "item"):
        value = value.item()
    if isinstance(value, float) and math.isnan(value):
        return float("nan")
    return value
