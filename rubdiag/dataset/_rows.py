"""One dataset row per run: what a worker computes and sends back to the writer.

:func:`make_row` simulates one :class:`~rubdiag.dataset.DesignRun`, labels it
(:mod:`rubdiag.dataset._labels`) and computes the features of its sensors as a plant would
measure them: the anti-alias-filtered channels of ``run.sensors`` over the analysis window,
plus measurement noise (:mod:`rubdiag.dataset._noise`, seeded by the run id). It never
raises for the run's sake: a diverging, failing or timed-out run becomes a row with its
``status`` and ``message`` and no labels or features. It runs in a local worker process or
on a Dask worker alike and holds no state between calls, so a row depends on the run alone
— whatever the worker, the number of workers or the scheduler. BLAS is held to one thread
while it runs (the linear algebra is then the same on every worker, and parallelism is
across runs).

Columns, in order: :data:`ID_COLUMNS`, the design point's factors (as the design names
them), ``speed_rpm`` (the run's speed; the design point's), for a design with a speed ramp
:data:`RAMP_COLUMNS`, ``model`` (``"full"`` or ``"reduced"``: which model
the run simulated, in every row, failed ones included), the measures and labels (with a
``fault`` factor also :data:`rubdiag.dataset._faults.FAULT_MEASURES` and ``FAULT_LABELS``),
the sensor features
``CHANNEL__FEATURE`` (e.g. ``shaft11_y_disp__amp_1x``, :mod:`rubdiag.signal._table`), the
probe pairs' features ``PAIR__FEATURE`` (e.g. ``shaft11_yz_disp__rev_2x``; below), the
ground truth a plant cannot measure — contact statistics ``contact<k>__…`` and
``contacts__…`` (:mod:`rubdiag.runs._contact_stats`) and ``truth__casing_max_y_m`` — then
:data:`PROVENANCE` (``rubdiag_version``, ``status``, ``message``, ``wall_s``: the row's
wall time, ``simulate_s``: the simulation's part of it), which the determinism checks
leave out.

**Probe pairs.** Every point with a y and a z displacement sensor among ``run.sensors``
(:func:`sensor_pairs`: with the default sensors the bearings' and the disc's shaft nodes)
is a pair of orthogonal probes, the shaft turning from y towards z. Its channel is named
by :func:`rubdiag.dataset._schema.pair_channel` (``shaft11_y_disp`` and ``shaft11_z_disp``
make ``shaft11_yz_disp``) and its columns are
:data:`~rubdiag.dataset._schema.PAIR_FEATURES` in that order — the forward and reverse
amplitudes at each searched order and the orbit measures of
:func:`rubdiag.signal._fullspectrum.orbit_features`, in m — computed from the same noisy,
windowed channels as the single-channel features, so the noise floor reaches them too.
Pairs follow the order of their y sensor; a pair of freely named probes whose names do not
differ by y/z alone gets no columns.

**Runs along a speed ramp** (a design's ``[ramp]``, :mod:`rubdiag.dataset._ramp`).
``speed_rpm`` is the design point's speed, the middle of the sweep; ``ramp_from_rpm`` and
``ramp_to_rpm`` are the sweep's start and end, ``ramp_rate_rpm_s`` its rate, and
``ramp_mean_rpm`` the mean speed of the record the features are measured on. The features
come from the window's measured channels order-tracked on the run's exact shaft angle
(:func:`rubdiag.runs._features.order_tracked`: equal angle steps, 32 per revolution,
anti-aliased in the angle domain, whole revolutions) and presented as a constant-speed
record at that mean speed, so the columns are those of a constant-speed dataset: every
order is a steady line, its ``freq_*_hz`` in Hz at ``ramp_mean_rpm``; ``rms`` covers the
orders up to 12.5 (the angle-domain low-pass); phases are against the shaft angle. The
labels' ``interference_ratio`` takes the largest linear approach over the sweep
(:mod:`rubdiag.dataset._approach`), and the ``…_per_rev`` contact statistics count the
window's revolutions from the shaft angle. The pairs' features come from the same
order-tracked record, so their ``near_limit_share`` is a share of the shaft angle rather
than of time.
"""

from __future__ import annotations

import math
import time

import numpy as np

from rubdiag._blas import one_thread
from rubdiag._version import __version__
from rubdiag.dataset._labels import LabelRules, label_run
from rubdiag.dataset._noise import NoiseFloors, add_noise, noise_seed
from rubdiag.dataset._schema import (
    ID_COLUMNS,
    MODEL_COLUMN,
    PAIR_FEATURES,
    PROVENANCE,
    SEPARATOR,
    STATUSES,
    pair_channel,
)

__all__ = ["ID_COLUMNS", "PROVENANCE", "RAMP_COLUMNS", "SEPARATOR", "STATUSES", "RunTimeout",
           "make_row", "make_row_and_waveforms", "sensor_pairs"]

#: The columns of a run along a design's speed ramp, after ``speed_rpm`` (module docstring).
RAMP_COLUMNS = ("ramp_from_rpm", "ramp_to_rpm", "ramp_rate_rpm_s", "ramp_mean_rpm")


def sensor_pairs(sensors) -> list[tuple[str, str, str]]:
    """``(pair channel, y sensor, z sensor)`` of every point with a y and a z displacement
    sensor among ``sensors`` (the first of each direction there), in the order of the y
    sensors; a pair whose names give no pair channel, or one that is already a sensor's
    name, is left out."""
    names = {s.name for s in sensors}
    z_at = {}
    for s in sensors:
        if s.quantity == "displacement" and s.direction == "z":
            z_at.setdefault(s.point, s.name)
    out, seen = [], set()
    for s in sensors:
        if (s.quantity != "displacement" or s.direction != "y" or s.point in seen
                or s.point not in z_at):
            continue
        seen.add(s.point)
        channel = pair_channel(s.name, z_at[s.point])
        if channel is not None and channel not in names:
            out.append((channel, s.name, z_at[s.point]))
    return out


class RunTimeout(RuntimeError):
    """A run took longer than its wall-time limit."""


def make_row(item, rules: LabelRules | None = None, noise: NoiseFloors | None = None,
             run_timeout_s: float | None = None) -> dict:
    """The dataset row of ``item`` (a :class:`~rubdiag.dataset.DesignRun`)."""
    return make_row_and_waveforms(item, rules, noise, run_timeout_s)[0]


def make_row_and_waveforms(item, rules: LabelRules | None = None,
                           noise: NoiseFloors | None = None,
                           run_timeout_s: float | None = None) -> tuple[dict, dict | None]:
    """The row of ``item`` and its measured waveforms: ``{"fs": Hz, "channels": {name:
    float32 array over the whole run, noise included}}``, for a run along a speed profile
    also ``"angle_rad"`` (the shaft angle at the samples), or None when the run failed."""
    rules = LabelRules() if rules is None else rules
    noise = NoiseFloors() if noise is None else noise
    start = time.perf_counter()
    row = {"run_id": item.run_id, "point_id": item.point_id, "replicate": item.replicate,
           **item.point, "speed_rpm": item.speed_rpm}
    if item.ramp is not None:
        from_rpm, to_rpm = item.ramp.speeds_rpm(item.speed_rpm)
        row.update(ramp_from_rpm=from_rpm, ramp_to_rpm=to_rpm,
                   ramp_rate_rpm_s=item.ramp.rate_rpm_s, ramp_mean_rpm=float("nan"))
    row[MODEL_COLUMN] = item.run.model_kind
    waves = None
    with one_thread(user_api=None):     # BLAS and OpenMP
        try:
            computed, waves = _simulate_and_describe(item, rules, noise, run_timeout_s, start)
            status, message = "ok", ""
        except RunTimeout as exc:
            computed, status, message = {}, "timeout", str(exc)
        except Exception as exc:   # a failed run is data, never the end of the job
            from rubdiag.simulation import SimulationDiverged

            kind = "diverged" if isinstance(exc, SimulationDiverged) else "error"
            computed, status = {}, kind
            message = f"{type(exc).__name__}: {exc}".splitlines()[0][:500]
    simulate_s = computed.pop("simulate_s", float("nan"))
    row.update(computed)
    row.update(rubdiag_version=__version__, status=status, message=message,
               wall_s=time.perf_counter() - start, simulate_s=simulate_s)
    return row, waves


def _simulate_and_describe(item, rules, noise, run_timeout_s,
                           start) -> tuple[dict, dict]:
    from rubdiag.dataset._ids import noise_id
    from rubdiag.simulation import simulate

    def watchdog(t, duration):
        elapsed = time.perf_counter() - start
        if elapsed > run_timeout_s:
            raise RunTimeout(f"stopped after {elapsed:.1f} s of wall time at t = {t:.4g} s "
                             f"of {duration:.4g} s (--run-timeout {run_timeout_s:g} s)")

    run = item.run
    result = simulate(run, progress=None if run_timeout_s is None else watchdog)
    labelled = _labels(item, result, rules)
    # noise over the whole record (what --waveforms stores), features over the window
    measured = add_noise(result.sensor_signals(),
                         {s.name: noise.floor(s.quantity) for s in run.sensors},
                         noise_seed(noise_id(run)))
    computed, record, fs, speed_rpm = _record(result, measured)
    features = _spectral_features(record, fs, speed_rpm)
    features.update(_pair_features(run.sensors, record, fs, speed_rpm))
    features.update(_truth(result))
    waves = {"fs": result.fs,
             "channels": {k: v.astype(np.float32) for k, v in measured.items()}}
    if run.speed_profile is not None:
        waves["angle_rad"] = result.angle_rad
    return {**computed, **labelled, **{k: _plain(v) for k, v in features.items()},
            "simulate_s": result.wall_s}, waves


def _labels(item, result, rules) -> dict:
    """The run's measures and labels (and each fault's, with a design's fault factor)."""
    from rubdiag.dataset._approach import approach_of, sweep_linear_approach_m
    from rubdiag.dataset._faults import fault_labels

    run = item.run
    of = approach_of(run)
    # the approach at the contacts that rub: the result's own covers every contact
    swept = run.speed_profile is not None or run.rig.stator_contacts
    labelled = label_run(result, rules, sweep_linear_approach_m(run, of=of) if swept else None,
                         clearance_m=run.seal_clearance_m if of == "seals" else None)
    if "fault" in item.point:           # a design with a fault factor: each fault's labels
        labelled.update(fault_labels(result, labelled["rub"]))
    return labelled


def _record(result, measured) -> tuple[dict, dict, float, float]:
    """``(columns, record, fs, speed_rpm)``: the measured channels over the analysis window
    as the features see them; along a speed ramp one constant-speed record at the sweep's
    mean speed (``columns``: its ``ramp_mean_rpm``)."""
    from rubdiag.runs._features import order_tracked

    window = result.window
    windowed = {k: v[window] for k, v in measured.items()}
    if result.run.speed_profile is None:
        return {}, windowed, result.fs, result.run.speed_rpm
    record, fs, speed_rpm = order_tracked(windowed, result.fs, result.angle_rad[window])
    return {"ramp_mean_rpm": float(speed_rpm)}, record, fs, speed_rpm


def _spectral_features(record, fs, speed_rpm) -> dict:
    """``CHANNEL__FEATURE`` of every channel of the record (:mod:`rubdiag.signal._table`)."""
    from rubdiag.signal._table import prefixed_feature_row

    row = prefixed_feature_row(record, fs, speed_rpm, separator=SEPARATOR)
    del row["speed_rpm"]
    return row


def _pair_features(sensors, record, fs, speed_rpm) -> dict:
    """``PAIR__FEATURE`` of every probe pair among ``sensors`` (module docstring), the pairs
    sharing the record's lock-in references."""
    from rubdiag.signal._fullspectrum import orbit_features_by_pair

    pairs = {channel: (record[y], record[z]) for channel, y, z in sensor_pairs(sensors)}
    if not pairs:
        return {}
    rows = orbit_features_by_pair(pairs, fs, speed_rpm)
    return {f"{channel}{SEPARATOR}{n}": row[n] for channel, row in rows.items()
            for n in PAIR_FEATURES}


def _truth(result) -> dict:
    """The ground truth a plant cannot measure: ``contact<k>__…``, ``contacts__…`` and
    ``truth__…`` (:mod:`rubdiag.runs._contact_stats`)."""
    from rubdiag.runs import contact_statistics

    features = {}
    for name, value in contact_statistics(result).items():
        if name == "window_s":          # the design's, not the run's
            continue
        channel, stat = name.split("_", 1) if name.startswith("contact") else ("truth", name)
        features[f"{channel}{SEPARATOR}{stat}"] = value
    return features


def _plain(value):
    """Python scalars (numpy scalars would not round-trip through Arrow identically)."""
    if hasattr(value, "item"):
        value = value.item()
    if isinstance(value, float) and math.isnan(value):
        return float("nan")
    return value
