"""The column map (``columns.csv``) and the dataset card (``README.md``) of a dataset folder.

Both are derived from the stored rows and the design, rewritten atomically at the end of
every job, so they describe what the folder holds.
"""

from __future__ import annotations

import datetime
import io
import re

import numpy as np
import pandas as pd

from rubdiag._version import __version__
from rubdiag.dataset._factors import FACTORS
from rubdiag.dataset._fault_levels import FAULT_LABELS, FAULT_MEASURES
from rubdiag.dataset._ids import SCHEMA_VERSION
from rubdiag.dataset._labels import LABELS, MEASURES, RUB_STATES, SEVERITIES
from rubdiag.dataset._rows import ID_COLUMNS, PROVENANCE, RAMP_COLUMNS, SEPARATOR
from rubdiag.dataset._schema import MODEL_COLUMN, pair_probes

__all__ = ["column_map", "write_card"]

_TRUTH = re.compile(r"^(contact\d+|contacts|truth)$")
# unit by name ending, longest first
_SUFFIX_UNITS = (("_per_rev", "1/rev"), ("_per_s", "1/s"), ("_rpm_s", "rpm/s"),
                 ("_n_m", "N/m"), ("_rpm", "rpm"),
                 ("_deg", "deg"), ("_hz", "Hz"), ("_mm", "mm"), ("_um", "µm"),
                 ("_j", "J"), ("_n", "N"), ("_m", "m"), ("_s", "s"))
# spectral amplitudes are in the unit of the signal: the responses are displacements (m)
_AMPLITUDE = re.compile(r"^(amp_|rms$|bb_\d+x_rms$|sb_\d+x_(lower|upper)$|combo_amp_)")
# a probe pair's lengths: forward and reverse lines, the clearance-limited radius
_PAIR_LENGTH = re.compile(r"^(fwd_|rev_|forward_1x$|reverse_1x$|limit_radius$)")


# text and boolean columns
_NO_UNIT = ("run_id", "point_id", "model", "rub", "rub_state", "severity", "rubdiag_version",
            "status", "message")


def _unit(feature: str, signal_unit: str = "", pair: bool = False) -> str:
    if pair:                    # a probe pair's features: lengths, or ratios and shares
        return signal_unit if _PAIR_LENGTH.match(feature) else "1"
    if _AMPLITUDE.match(feature):
        return signal_unit
    for suffix, unit in _SUFFIX_UNITS:
        if feature.endswith(suffix):
            return unit
    return "1"


def column_map(columns, sensors=()) -> pd.DataFrame:
    """One row per column: ``column``, ``group`` (id, factor, run, measure, label, feature:
    a sensor's, truth: what no sensor measures — contact statistics, the casing maximum —,
    provenance), ``channel`` (a sensor's name, ``contact<k>``, ``contacts``, ``truth``, or
    empty), ``feature`` (the name without the channel) and
    ``unit`` (amplitudes in the unit of their sensor, of ``sensors``, a probe pair's in its
    probes'; "1": dimensionless or a count; empty for text). A probe pair's channel
    (``shaft11_yz_disp``, :func:`rubdiag.dataset._schema.pair_channel`) is a feature
    channel like a sensor's."""
    signal_units = {s.name: s.unit for s in sensors}
    rows = []
    for name in columns:
        channel, feature = "", name
        if name in ID_COLUMNS:
            group = "id"
        elif name in ("speed_rpm", MODEL_COLUMN, *RAMP_COLUMNS):   # the run's speed (also
            group = "run"            # when a factor set it), its sweep, which model made it
        elif name in FACTORS:
            group = "factor"
        elif name in MEASURES or name in FAULT_MEASURES:
            group = "measure"
        elif name in LABELS or name in FAULT_LABELS:
            group = "label"
        elif name in PROVENANCE:
            group = "provenance"
        elif SEPARATOR in name:
            channel, feature = name.split(SEPARATOR, 1)
            group = "truth" if _TRUTH.match(channel) else "feature"
        else:
            group = "feature"
        probes = pair_probes(channel) if channel and channel not in signal_units else None
        if probes is not None:
            unit = _unit(feature, signal_units.get(probes[0], ""), pair=True)
        else:
            unit = "" if name in _NO_UNIT else _unit(feature, signal_units.get(channel, ""))
        if name in ("case", "replicate", "interference_ratio", "contact_time_fraction",
                    "sticking_share", "n_rub_episodes", "crack_open_fraction",
                    "crack_depth_ratio") or name.endswith("_scale"):
            unit = "1"
        if name in ("fault", "faults"):            # text: the faults by name
            unit = ""
        elif name.endswith("_mrad"):
            unit = "mrad"
        rows.append({"column": name, "group": group, "channel": channel, "feature": feature,
                     "unit": unit})
    return pd.DataFrame(rows)


def write_card(folder, design) -> None:
    """Write ``columns.csv`` and ``README.md`` of ``folder`` (a DatasetFolder)."""
    from rubdiag._atomic import write_text
    from rubdiag.dataset._store import load

    rows = load(folder.root)
    columns = column_map(rows.columns, design.sensors)
    buffer = io.StringIO()
    columns.to_csv(buffer, index=False, lineterminator="\n")
    write_text(folder.root / "columns.csv", buffer.getvalue())
    write_text(folder.root / "README.md", card_text(rows, design, columns))


def _counts(rows: pd.DataFrame, column: str, order) -> str:
    ok = rows[rows["status"] == "ok"]
    counts = ok[column].astype(str).value_counts() if len(ok) else pd.Series(dtype=int)
    return ", ".join(f"{value} {int(counts.get(str(value), 0))}" for value in order)


def card_text(rows: pd.DataFrame, design, columns: pd.DataFrame) -> str:
    """The dataset card (Markdown)."""
    n_done = len(rows)
    status = rows["status"].value_counts() if n_done else pd.Series(dtype=int)
    factors = "\n".join(f"- `{f.name}`: {_spec(f)}" for f in design.factors)
    wall = rows["wall_s"].to_numpy(float) if n_done else np.array([])
    if wall.size:
        q = np.percentile(wall, [0, 10, 50, 90, 100])
        simulated = np.nansum(rows["simulate_s"].to_numpy(float)) \
            if "simulate_s" in rows else np.nan
        wall_text = (f"min {q[0]:.2f} s, p10 {q[1]:.2f}, median {q[2]:.2f}, p90 {q[3]:.2f}, "
                     f"max {q[4]:.2f} s; total {wall.sum() / 60:.1f} min of worker time, "
                     f"{simulated / wall.sum():.0%} of it simulating")
    else:
        wall_text = "no run yet"
    groups = columns.groupby("group", sort=False)["column"].count()
    described = columns[columns["group"].isin(("factor", "run", "measure", "label"))]
    units_text = "\n".join(f"| `{r.column}` | {r.group} | {r.unit or '–'} |"
                           for r in described.itertuples())
    channels = "\n".join(f"| `{s.name}` | {s.quantity} of {s.point} {s.direction} | {s.unit} "
                         f"| {design.noise.floor(s.quantity):g} |" for s in design.sensors)
    return f"""# rubdiag dataset

Made with rubdiag {__version__} (run-id schema {SCHEMA_VERSION}) on
{datetime.date.today().isoformat()}. `design.toml` is the resolved design: the same design
makes the same runs, bit for bit, on any machine and any number of workers.

## Design

Sampling: {design.method}, {design.n} design points × {design.replicates} replicate(s) =
{design.n_runs} runs (seed {design.seed}); {_timing(design)}; model: {_model(design)};
{_steps(design)}.
Factors:

{factors}
{_ramp(design)}
Labels (rubdiag.dataset._labels): severity threshold {design.labels.severity_threshold:g}
(interference ratio; calibrated on the study's four cells), full rub from a contact-time
share of {design.labels.full_contact_share:g}.

## Counts

Stored: {n_done} of {design.n_runs} runs; status: {_status(status)}.
Among the ok runs: rub {_counts(rows, 'rub', (True, False)) if n_done else '-'};
rub_state {_counts(rows, 'rub_state', RUB_STATES) if n_done else '-'};
severity {_counts(rows, 'severity', SEVERITIES) if n_done else '-'}.{_fault_counts(rows)}

Wall time per run: {wall_text}.

## Columns

| column | group | unit |
|---|---|---|
{units_text}

Sensor channels (features `CHANNEL__FEATURE`; amplitudes in the channel's unit; noise floor
= standard deviation of the added white noise, same unit):

| channel | measures | unit | noise floor |
|---|---|---|---|
{channels}

{len(columns)} columns ({', '.join(f'{g} {n}' for g, n in groups.items())}); `columns.csv`
gives each one's group, channel, feature and unit. Read the rows with
`rubdiag.dataset.load(DIR)` (one row per run) or `pandas.read_parquet(DIR / "features")`.
Group splits by `point_id`: replicates of a design point are near-copies.
"""


def _timing(design) -> str:
    if design.ramp is None:
        return (f"{design.duration_s:g} s simulated per run, the first {design.discard_s:g} s "
                "discarded")
    return (f"each run holds its start speed for {design.discard_s:g} s (discarded), then "
            "sweeps (see Speed ramp)")


def _ramp(design) -> str:
    """The card's paragraph on a design's speed ramp (empty without one)."""
    ramp = design.ramp
    if ramp is None:
        return ""
    kind = "run-up" if ramp.direction == "up" else "coast-down"
    sweep = ("speed·(1 − span) to speed·(1 + span)" if ramp.direction == "up"
             else "speed·(1 + span) to speed·(1 − span)")
    return f"""
Speed ramp: every run is a {kind} at {ramp.rate_rpm_s:g} rpm/s through its design point's
speed, from {sweep} with span {ramp.span:g}
(`ramp_from_rpm`, `ramp_to_rpm`, `ramp_rate_rpm_s`). The analysis window is the whole
ramp: a run lasts {design.discard_s:g} s + 2·span·speed / rate. `speed_rpm` is the design
point's speed (the sweep's middle). The features are those of the window's channels
order-tracked on the exact shaft angle (32 samples per revolution, whole revolutions) and
read as a constant-speed record at its mean speed `ramp_mean_rpm`: every order is a steady
line, frequencies are in Hz at that speed, `rms` covers the orders up to 12.5.
`interference_ratio` is the largest linear approach over the sweep, over g0; `…_per_rev`
counts the window's revolutions.
"""


def _steps(design) -> str:
    if not design.step_error:
        return "steps: 10 µs or shorter (`step_error = 0`)"
    return (f"steps: 10 µs or shorter while a contact is closed, up to 40 µs where the "
            f"Newmark local error estimate stays below {design.step_error:g} of the largest "
            f"recorded displacement (`step_error`)")


def _model(design) -> str:
    if design.reduction is None:
        return "the full finite-element model"
    return (f"the reduced-order model (Craig–Bampton, fixed-interface modes below "
            f"{design.reduction.cutoff_hz:g} Hz)")


def _fault_counts(rows: pd.DataFrame) -> str:
    """The fault labels' counts (rubdiag.dataset._faults), for a design with a fault factor."""
    if "faults" not in rows:
        return ""
    ok = rows[rows["status"] == "ok"]
    acted = ", ".join(f"{k} {int(v)}" for k, v in ok["faults"].value_counts().items())
    return (f"\nFaults that acted (`faults`): {acted}; fault_crack "
            f"{_counts(rows, 'fault_crack', (True, False))}; fault_misalignment "
            f"{_counts(rows, 'fault_misalignment', (True, False))} (thresholds: "
            "rubdiag.dataset._faults).")


def _status(counts: pd.Series) -> str:
    if counts.empty:
        return "none"
    return ", ".join(f"{k} {int(v)}" for k, v in counts.items())


def _spec(factor) -> str:
    if factor.levels is not None:
        return "levels " + ", ".join(v if isinstance(v, str) else f"{v:g}"
                                     for v in factor.levels)
    n = f", {factor.n} grid levels" if factor.n is not None else ""
    if factor.bands is not None:
        return " and ".join(f"{low:g} … {high:g}" for low, high in factor.bands) + n
    return f"{factor.low:g} … {factor.high:g}{n}"
