"""How a classifier's scores fall as measurement noise grows: a noise curve.

:func:`noise_curve` takes a dataset stored with ``--waveforms``, adds white Gaussian noise
to every input channel of the model at given signal-to-noise ratios, extracts the features
again from the noisy waveforms and scores the classifier on the same split, level by level.

* **Window** — the features are taken over the analysis window exactly as the dataset's
  were: samples ``t >= discard_s`` (the rule of ``SimulationResult.window``), from the
  stored float32 waveforms. With no noise added ("as stored", the first row) the features
  equal the dataset's up to the float32 rounding of the stored samples.
* **Reference power** of a channel — the median, over the *rubbing* runs (``rub`` True),
  of the channel's mean square about its mean in the window: "SNR 10 dB" means noise of
  a tenth of the power a typical rubbing run shows on that channel, whatever the run.
* **Noise** — σ = sqrt(P_ref / 10^(SNR/10)) per channel, added to every run (on top of
  the dataset's own noise floor, which the stored waveforms already hold). A run draws
  one standard-normal array (seeded by ``seed`` and its ``run_id``), scaled by σ at every
  level: levels differ by their σ alone, not by a new draw (common random numbers), and a
  level's noise does not depend on which other levels are asked for. Same call, same curve.
* **Training** — ``train_on="noisy"`` (default) trains and tests each fold at the level:
  what a model made for a machine that noisy can do. ``train_on="stored"`` trains on the
  dataset's features as stored and tests on the noisy ones: how a model made from
  simulation meets a machine noisier than the simulation's floor (the usual case).
* **Features** are extracted once per level (they do not depend on the model) with the
  dataset's options (:func:`rubdiag.signal._table.feature_matrix` defaults, as
  ``prefixed_features`` in :mod:`rubdiag.dataset._rows`), and replace the stored
  ``CHANNEL__FEATURE`` columns of the model's channels.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pandas as pd
from threadpoolctl import threadpool_limits

from rubdiag import _check
from rubdiag.dataset._schema import SEPARATOR
from rubdiag.learn._columns import read_dataset
from rubdiag.learn._controls import fold_of_rows
from rubdiag.learn._cross_predict import cross_predict
from rubdiag.learn._evaluate import cross_validate, resolve_channels, target_values
from rubdiag.learn._features import DEFAULT_FAMILIES
from rubdiag.learn._metrics import METRICS, null_interval, score
from rubdiag.learn._pipelines import make_pipeline
from rubdiag.learn._splits import folds

__all__ = ["Windows", "analysis_windows", "noise_curve", "noise_std", "noisy_windows",
           "reference_power", "standard_noise", "window_features"]

# evaluate's parts a curve does not report: always off (each costs cross-predictions)
_OFF = ("importances", "baselines", "audit")
_TRAIN_ON = ("noisy", "stored")
# the rule of SimulationResult.window: sample times k/fs and k*dt differ in the last bit
_WINDOW_TOLERANCE_S = 1e-12


@dataclass(frozen=True)
class Windows:
    """The analysis windows of a dataset's runs: ``x[run, channel, sample]`` (float32, as
    stored), with ``run_ids``, ``channels`` and the sampling rate ``fs`` (Hz)."""

    x: np.ndarray
    run_ids: list
    channels: list
    fs: float


def analysis_windows(root: str | Path, run_ids, channels) -> Windows:
    """The stored waveforms of ``channels`` over each run's analysis window.

    Raises
    ------
    ValueError
        The dataset was made without ``--waveforms``, a run's waveforms are missing, or
        runs differ in sampling rate or window length.
    """
    from rubdiag.dataset import load_waveforms

    root = Path(root)
    if not (root / "waveforms").is_dir():
        raise ValueError(f"{root}: the dataset holds no waveforms, and a noise curve adds "
                         "noise to them: generate it again with --waveforms")
    run_ids, channels = [str(r) for r in run_ids], list(channels)
    out, fs = None, None
    for i, run_id in enumerate(run_ids):
        waves = load_waveforms(root, run_id)
        missing = [c for c in channels if c not in waves.columns]
        if missing:
            raise ValueError(f"run {run_id}: no stored waveform of channel {missing[0]!r}")
        t = waves.index.to_numpy()
        window = waves[channels].to_numpy()[t >= waves.attrs["discard_s"]
                                            - _WINDOW_TOLERANCE_S].T
        if out is None:
            fs = float(waves.attrs["fs_hz"])
            out = np.empty((len(run_ids), *window.shape), dtype=np.float32)
        elif window.shape != out.shape[1:] or float(waves.attrs["fs_hz"]) != fs:
            raise ValueError(f"run {run_id}: its window ({window.shape[1]} samples at "
                             f"{waves.attrs['fs_hz']} Hz) differs from the first run's "
                             f"({out.shape[2]} at {fs} Hz)")
        out[i] = window
    if out is None:
        raise ValueError("run_ids is empty: no run to take waveforms from")
    return Windows(out, run_ids, channels, fs)


def reference_power(windows: Windows, rubbing) -> np.ndarray:
    """Per channel: the median over the rubbing runs of the mean square about the mean in
    the window (the signal unit squared)."""
    rubbing = np.asarray(rubbing, dtype=bool)
    if rubbing.shape != (len(windows.run_ids),):
        raise ValueError(f"rubbing: one flag per run needed ({len(windows.run_ids)}), got "
                         f"shape {rubbing.shape}")
    if not rubbing.any():
        raise ValueError("no rubbing run (rub True) in the data: the reference power of the "
                         "SNR is taken over rubbing runs")
    power = windows.x[rubbing].astype(np.float64).var(axis=-1)        # (runs, channels)
    return np.median(power, axis=0)


def noise_std(p_ref, snr_db: float) -> np.ndarray:
    """σ of white noise at ``snr_db`` below the reference powers ``p_ref``: sqrt(P_ref /
    10^(SNR/10)); 0 at SNR = inf (no noise)."""
    if snr_db != np.inf:
        snr_db = _check.number("snr_db", snr_db,
                               allowed="a finite number of dB, or inf for no noise")
    return np.sqrt(np.asarray(p_ref, dtype=np.float64) / 10.0 ** (snr_db / 10.0))


def noisy_windows(windows: Windows, p_ref, snr_db: float, seed: int = 0) -> np.ndarray:
    """The windows (float64) plus white Gaussian noise of :func:`noise_std` per channel,
    each run's from :func:`standard_noise`."""
    sigma = noise_std(p_ref, snr_db)
    if sigma.shape != (len(windows.channels),):
        raise ValueError(f"p_ref: one power per channel needed ({len(windows.channels)}), "
                         f"got shape {sigma.shape}")
    x = windows.x.astype(np.float64)
    if np.isfinite(snr_db):
        for i, run_id in enumerate(windows.run_ids):
            x[i] += sigma[:, None] * standard_noise(run_id, x.shape[1:], seed)
    return x


def standard_noise(run_id: str, shape, seed: int = 0) -> np.ndarray:
    """The standard-normal draw of one run, ``shape`` = (channels, samples): seeded by
    ``seed`` and the run's id (hexadecimal), so independent of the other runs."""
    seed = _check.integer("seed", seed, lo=0)
    try:
        key = int(str(run_id), 16)
    except ValueError:
        raise ValueError(f"run_id = {run_id!r} is not a dataset run id (hexadecimal)") from None
    return np.random.default_rng(np.random.SeedSequence([seed, key])).standard_normal(shape)


def window_features(x: np.ndarray, fs: float, speed_rpm, channels) -> pd.DataFrame:
    """``CHANNEL__FEATURE`` columns of windows ``x[run, channel, sample]``, one row per run,
    with the dataset's feature options; ``speed_rpm`` one per run. Every y/z probe pair
    among ``channels`` adds its ``PAIR__FEATURE`` columns, as a dataset row's
    (:func:`rubdiag.learn._predict.pair_columns`)."""
    from rubdiag.learn._predict import pair_columns
    from rubdiag.signal._table import FEATURE_NAMES, SPEED_NAMES, feature_matrix

    n_runs, n_channels, n_samples = x.shape
    speed = np.repeat(np.asarray(speed_rpm, dtype=np.float64), n_channels)
    values = feature_matrix(x.reshape(n_runs * n_channels, n_samples).astype(np.float64),
                            fs, speed)
    values = values.reshape(n_runs, n_channels, len(FEATURE_NAMES))
    keep = [j for j, n in enumerate(FEATURE_NAMES) if n not in SPEED_NAMES]
    columns = [f"{c}{SEPARATOR}{FEATURE_NAMES[j]}" for c in channels for j in keep]
    frame = pd.DataFrame(values[:, :, keep].reshape(n_runs, -1), columns=columns)
    per_run = np.asarray(speed_rpm, dtype=np.float64).reshape(-1)
    pairs = [pair_columns(dict(zip(channels, x[r].astype(np.float64), strict=True)), fs,
                          per_run[r]) for r in range(n_runs)]
    if n_runs and pairs[0]:
        frame = pd.concat([frame, pd.DataFrame(pairs)], axis=1)
    return frame


def noise_curve(dataset, target: str = "rub", split: str = "group", estimator: str = "rf",
                snr_db=(30, 20, 10, 5), channels="shaft", seed: int = 0,
                train_on: str = "noisy", **evaluate_options) -> pd.DataFrame:
    """Held-out scores of a classifier against the SNR of noise added to its channels.

    Parameters
    ----------
    dataset : str, Path or DataFrame
        A dataset folder made with ``--waveforms``, or its rows from
        :func:`~rubdiag.learn._columns.read_dataset` (which know their folder).
    target, split, estimator, channels
        As :func:`~rubdiag.learn._evaluate.evaluate`; noise goes into ``channels`` (the
        model's inputs) only.
    snr_db : sequence of float
        Signal-to-noise ratios (dB) of the added noise, relative to each channel's
        reference power (module docstring); finite, any sign.
    seed : int
        Seeds the noise and the evaluation.
    train_on : {"noisy", "stored"}
        Train each fold at the level's noise, or on the stored features (module
        docstring).
    **evaluate_options
        Further options of :func:`~rubdiag.learn._evaluate.evaluate` (``n_splits``,
        ``n_bootstrap``, ``families`` …); importances, baselines and the audit are not
        computed.

    Returns
    -------
    pandas.DataFrame
        One row per level, first "as stored" (``snr_db`` inf: no noise added, features
        extracted again from the stored waveforms): ``snr_db``, ``macro_f1`` and
        ``balanced_accuracy`` with ``_lo``/``_hi`` (95 % bootstrap interval), ``chance_lo``/
        ``chance_hi`` (the permutation-null interval of the shuffled-label model; with
        ``train_on="stored"``, of the predictions themselves), then
        ``<channel>__noise_std`` (σ added, in the channel's unit) per channel. ``attrs``:
        ``target``, ``split``, ``estimator``, ``channels``, ``train_on``,
        ``reference_power`` (channel → P_ref), ``n_rubbing``.
    """
    if train_on not in _TRAIN_ON:
        raise ValueError(f"train_on = {train_on!r} is not allowed (allowed: "
                         f"{', '.join(map(repr, _TRAIN_ON))})")
    for name in _OFF:
        if name in evaluate_options:
            raise ValueError(f"{name} is not an option of noise_curve (allowed: evaluate's "
                             f"options but {', '.join(_OFF)}: a curve holds scores only)")
    levels = _levels(snr_db)
    seed = _check.integer("seed", seed, lo=0)
    data = dataset if isinstance(dataset, pd.DataFrame) else read_dataset(dataset)
    root = data.attrs.get("source")
    if root is None:
        raise ValueError("dataset: a folder, or rows from read_dataset (which know their "
                         "folder), is needed: the waveforms are read from it")
    if "rub" not in data.columns:
        raise ValueError("the data has no 'rub' column: the reference power is taken over "
                         "rubbing runs")
    channels = resolve_channels(data, channels)
    windows = analysis_windows(root, data["run_id"], channels)
    p_ref = reference_power(windows, data["rub"].to_numpy(dtype=bool))
    speed = data["speed_rpm"].to_numpy(dtype=np.float64)
    # the chance band needs one shuffle per level, not the report's several
    options = {"n_shuffles": 1, **evaluate_options, **dict.fromkeys(_OFF, False)}

    rows = []
    for snr in [np.inf, *levels]:
        x = noisy_windows(windows, p_ref, snr, seed)
        features = window_features(x, windows.fs, speed, channels)
        noisy = data.copy()
        noisy[features.columns] = features.to_numpy()
        if train_on == "noisy":
            ev = cross_validate(noisy, target, split, estimator, channels=channels, seed=seed,
                          **options)
            scores, chance = ev.scores, (ev.shuffled["null_lo"], ev.shuffled["null_hi"])
        else:
            scores, chance = _trained_on_stored(data, noisy, target, split, estimator,
                                                channels, seed, options)
        row = {"snr_db": float(snr)}
        for metric in METRICS:
            s = scores[metric]
            row.update({metric: s.value, f"{metric}_lo": s.lo, f"{metric}_hi": s.hi})
        row.update(chance_lo=chance[0], chance_hi=chance[1])
        row.update({f"{c}{SEPARATOR}noise_std": float(v)
                    for c, v in zip(channels, noise_std(p_ref, snr), strict=True)})
        rows.append(row)
    curve = pd.DataFrame(rows)
    curve.attrs.update(target=target, split=split, estimator=estimator, channels=channels,
                       train_on=train_on,
                       reference_power=dict(zip(channels, map(float, p_ref), strict=True)),
                       n_rubbing=int(data["rub"].astype(bool).sum()))
    return curve


@threadpool_limits.wrap(limits=1)
def _trained_on_stored(data, noisy, target, split, estimator, channels, seed, options):
    """Scores (and chance interval) of folds trained on ``data``, tested on ``noisy``."""
    pipeline = options.get("pipeline")
    if pipeline is None:
        pipeline = make_pipeline(estimator, channels=channels,
                                 families=options.get("families", DEFAULT_FAMILIES),
                                 random_state=seed)
    y = target_values(data, target)
    splits = folds(data, split, y, n_splits=options.get("n_splits", 5),
                   bands=options.get("bands", 5), seed=seed)
    cp = cross_predict(pipeline, data, y, splits, test_data=noisy)
    s, groups, classes = cp.scored, data["point_id"].to_numpy(), sorted(set(y))
    scores = score(y[s], cp.predicted[s], groups[s], classes,
                   options.get("n_bootstrap", 1000), seed)
    chance = null_interval(y[s], cp.predicted[s], classes, options.get("n_null", 1000), seed,
                           groups=groups[s], strata=fold_of_rows(splits, groups, s))
    return scores, chance


def _levels(snr_db) -> list[float]:
    values = [snr_db] if np.ndim(snr_db) == 0 else snr_db
    return list(_check.numbers("snr_db", values, check=_check.number))
