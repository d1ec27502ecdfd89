#!/usr/bin/env python
"""The transfer table: rub models trained on one design's dataset, scored on runs and
records they were not trained on — data/transfer.csv (and data/transfer_predictions.csv,
every prediction it counts).

    python scripts/transfer.py faults-data --name faults_journal \\
        --hold-out bearing_clearance_scale=1.05:1.05 --hold-out casing_stiffness_scale=2:2 \\
        --other faults-small-data --ross data/ross_records/records.csv

Models (the default of ``rubdiag train``: target rub, a random forest, the shaft channels
above their noise floor, the default feature families): ``rub, default`` on every run of
DATASET, ``rub, one probe (<channel>)`` on its first channel alone, and one default model
per ``--hold-out`` band trained without that band's runs (``train(..., leave_out=)``).
Each is scored (``evaluate``: evaluation only, nothing here is ever trained on) on:

* its held-out band (a level of a model-uncertainty factor, a speed band, a case);
* ``--other`` datasets (another rig preset, another design) with the same channels;
* textbook records (:mod:`rubdiag.learn._textbook`, made here with the model's channels, its
  window and sampling rate): every kind, strength and precession, at the speeds of the
  10th, 50th and 90th percentiles of the training runs, on the bin grid and midway between
  two bins; the 1× at the median 1× amplitude of the first channel over the training runs
  without rub, white noise at the dataset's displacement floor. The pair records go to the
  default model, the single-probe ones to the one-probe model;
* another simulator's records (``--ross``, a labelled record list: data/ross_records, made
  by scripts/ross_records.py), stored without noise: white noise at the dataset's
  displacement floor is added here, seeded by each file's name.

The table has one row per kind of run or record (textbook kinds split on and between the
bins) and an ``all`` row per block: ``model``, ``trained_on``, ``scored_on``, ``kind``,
``n``, ``n_called_rub``, the false rub alarm rate of the records without rub and the rub
recall of those with rub, each with Wilson's 95 % interval (``…_lo``, ``…_hi``; records
are independent, and 0 of n still has an upper bound), and on the ``all`` row the macro-F1
of rub against no rub with its bootstrap interval over design points (records: each its
own). tests/learn/test_transfer.py runs :func:`transfer` on a small case and checks the
stored table against the stored predictions and the goals.
"""

from __future__ import annotations

import argparse
import tempfile
import zlib
from pathlib import Path

import numpy as np
import pandas as pd

from rubdiag.learn import read_dataset, train
from rubdiag.learn._confusers import calls_rub
from rubdiag.learn._metrics import wilson_interval
from rubdiag.learn._records import read_records
from rubdiag.learn._textbook import KINDS, textbook_records, write_records
from rubdiag.learn._train import evaluate

DATA = Path(__file__).resolve().parents[1] / "data"
CSV, PREDICTIONS = DATA / "transfer.csv", DATA / "transfer_predictions.csv"
COLUMNS = ["model", "trained_on", "scored_on", "kind", "n", "n_called_rub",
           "false_rub_alarm", "false_rub_alarm_lo", "false_rub_alarm_hi",
           "rub_recall", "rub_recall_lo", "rub_recall_hi",
           "macro_f1", "macro_f1_lo", "macro_f1_hi"]
DEFAULT, ONE_PROBE = "rub, default", "rub, one probe ({})"
SPEED_QUANTILES = (0.1, 0.5, 0.9)
BIN_OFFSETS = (0.0, 0.5)
# the evaluation inside train() is not what this table measures: its cheapest form
TRAIN_OPTIONS = {"importances": False, "baselines": False, "audit": False, "n_shuffles": 1}


def transfer(dataset, work, *, name=None, hold_out=(), other=(), ross=None,
             kinds=tuple(KINDS), seed: int = 0, n_bootstrap: int = 1000, n_splits: int = 5):
    """The table and the predictions it counts (module docstring).

    Parameters
    ----------
    dataset : path
        The training dataset's folder.
    work : path
        A folder for the models and the records made here.
    name : str, optional
        What the table calls the dataset (default: its folder's name).
    hold_out : sequence of (str, float, float)
        Bands (factor, lo, hi) to hold out of training, one model each.
    other : sequence of path
        Other datasets to score the default model on.
    ross : path, optional
        A labelled record list of another simulator's noise-free records.
    kinds : sequence of str
        The textbook kinds to make.
    seed, n_bootstrap : int
        Seed of models, records and noise; bootstrap draws of the macro-F1 intervals.
    n_splits : int
        Folds of the evaluation each ``train`` makes (not what the table reports).

    Returns
    -------
    (DataFrame, DataFrame)
        The table (:data:`COLUMNS`) and the predictions: ``model``, ``trained_on``,
        ``scored_on``, ``record``, ``kind``, ``rubbing``, ``predicted``, ``called_rub``.
    """
    work = Path(work)
    data = read_dataset(dataset)
    options = {**TRAIN_OPTIONS, "n_splits": n_splits, "seed": seed}
    name = name or Path(dataset).name
    blocks = []
    default = train(data, work / "default", **options)
    probe = default.channels[0]
    single = train(data, work / "one_probe", channels=[probe], **options)
    for band in hold_out:
        factor, lo, hi = band
        model = train(data, work / f"without_{factor}_{lo:g}_{hi:g}", leave_out=band,
                      **options)
        what = f"{factor} {lo:g}" if lo == hi else f"{factor} {lo:g} to {hi:g}"
        blocks.append((DEFAULT, f"{name} without {what}", f"{name}: {what}",
                       evaluate(model, data, n_bootstrap, seed, band=band)))
    for folder in other:
        blocks.append((DEFAULT, name, Path(folder).name,
                       evaluate(default, folder, n_bootstrap, seed)))
    floor = _displacement_floor(data)
    level = _median_1x(data, probe)
    for model, label, what, folder in (
            (default, DEFAULT, "textbook records, probe pairs", "textbook_pairs"),
            (single, ONE_PROBE.format(probe), "textbook records, one probe", "textbook_one")):
        records = textbook_records(model.channels, model.meta["fs_hz"], model.meta["window_s"],
                                   np.quantile(data["speed_rpm"], SPEED_QUANTILES),
                                   kinds=kinds, bin_offsets=BIN_OFFSETS, amp_1x_m=level,
                                   noise_m=floor, seed=seed)
        listed = read_records(write_records(records, work / folder))
        listed["kind"] = [f"{r.kind} ({'on' if r.bin_offset == 0 else 'between'} bins)"
                          for r in records]
        blocks.append((label, name, what,
                       evaluate(model, listed, n_bootstrap, seed)))
    if ross is not None:
        listed = _with_noise(read_records(ross), floor, work / "ross_noisy", seed)
        blocks.append((DEFAULT, name, "ROSS records, paper shaft",
                       evaluate(default, listed, n_bootstrap, seed)))
    tables, predictions = zip(*(_block(*b) for b in blocks), strict=True)
    return (pd.concat(tables, ignore_index=True)[COLUMNS],
            pd.concat(predictions, ignore_index=True))


def _block(model: str, trained_on: str, scored_on: str, scores):
    """The rows and the predictions of one scoring (``scores``: a ModelScores)."""
    keys = {"model": model, "trained_on": trained_on, "scored_on": scored_on}
    rows = []
    for r in scores.kinds.itertuples():
        prefix = "false_rub_alarm" if r.measure == "false rub alarm" else "rub_recall"
        rows.append({**keys, "kind": r.kind, "n": r.n, "n_called_rub": r.n_called_rub,
                     **_rate(prefix, r.n_called_rub, r.n)})
    p = scores.predictions
    called, rubbing = calls_rub(p["predicted"]), p["rubbing"].to_numpy(dtype=bool)
    f1 = scores.scores["macro_f1"]
    rows.append({**keys, "kind": "all", "n": len(p), "n_called_rub": int(called.sum()),
                 **_rate("false_rub_alarm", int((called & ~rubbing).sum()),
                         int((~rubbing).sum())),
                 **_rate("rub_recall", int((called & rubbing).sum()), int(rubbing.sum())),
                 "macro_f1": f1.value, "macro_f1_lo": f1.lo, "macro_f1_hi": f1.hi})
    # a record by its file's name (its path is a work folder's), a run by its id
    predictions = pd.DataFrame({**keys, "record": [Path(r).name for r in p["run_id"].astype(str)],
                                "kind": p["kind"],
                                "rubbing": rubbing, "predicted": p["predicted"],
                                "called_rub": called})
    return pd.DataFrame(rows), predictions


def _rate(prefix: str, hits: int, n: int) -> dict:
    """``prefix``, its ``_lo`` and ``_hi``: hits / n and Wilson's interval (none if n = 0)."""
    if n == 0:
        return {}
    lo, hi = wilson_interval(hits, n)
    return {prefix: hits / n, f"{prefix}_lo": lo, f"{prefix}_hi": hi}


def _displacement_floor(data: pd.DataFrame) -> float:
    """The dataset's noise floor of its displacement probes (m)."""
    floors = data.attrs.get("noise_floors") or {}
    sensors = data.attrs["acquisition"]["sensors"]
    values = {floors[s["name"]] for s in sensors
              if s["quantity"] == "displacement" and s["name"] in floors}
    if len(values) != 1:
        raise ValueError(f"the dataset's displacement floors are {sorted(values)} (one needed)")
    return values.pop()


def _median_1x(data: pd.DataFrame, channel: str) -> float:
    """Median 1× amplitude of ``channel`` over the runs without rub (m)."""
    quiet = ~data["rub"].astype(str).str.lower().eq("true")
    return float(np.median(data.loc[quiet, f"{channel}__amp_1x"]))


def _with_noise(records: pd.DataFrame, floor: float, folder: Path, seed: int) -> pd.DataFrame:
    """Copies of noise-free records with white noise of ``floor`` on every channel (seeded
    by the seed and each file's name), listed as ``records`` lists them."""
    folder.mkdir(parents=True, exist_ok=True)
    out = records.copy()
    files = []
    for path in records["file"]:
        path = Path(path)
        rng = np.random.default_rng([seed, zlib.crc32(path.name.encode())])
        with np.load(path) as saved:
            arrays = {k: saved[k] for k in saved.files}
        noisy = {k: (v if k == "fs" else v + floor * rng.standard_normal(v.shape))
                 for k, v in arrays.items()}
        np.savez_compressed(folder / path.name, **noisy)
        files.append(str(folder / path.name))
    out["file"] = files
    return out


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("dataset", type=Path, help="the training dataset's folder")
    parser.add_argument("--name", help="what the table calls it (default: the folder's name)")
    parser.add_argument("--hold-out", action="append", default=[], metavar="FACTOR=LO:HI")
    parser.add_argument("--other", action="append", default=[], type=Path, metavar="DIR")
    parser.add_argument("--ross", type=Path, metavar="RECORDS.csv")
    parser.add_argument("--work", type=Path, help="keep the models and records here")
    parser.add_argument("--n-splits", type=int, default=5,
                        help="folds of the evaluation inside each train (default: 5)")
    parser.add_argument("--out", type=Path, default=CSV)
    parser.add_argument("--predictions", type=Path, default=PREDICTIONS)
    args = parser.parse_args(argv)
    from rubdiag.cli.learn import _band

    bands = [_band(text, "--hold-out") for text in args.hold_out]
    with tempfile.TemporaryDirectory() as tmp:
        table, predictions = transfer(args.dataset, args.work or tmp, name=args.name,
                                      hold_out=bands, other=args.other, ross=args.ross,
                                      n_splits=args.n_splits)
    table.to_csv(args.out, index=False, float_format="%.6g")
    predictions.to_csv(args.predictions, index=False)
    with pd.option_context("display.width", 200, "display.max_rows", None,
                           "display.max_columns", None, "display.float_format", "{:.3f}".format):
        print(table.drop(columns=["trained_on"]).to_string(index=False))
    print(f"wrote {args.out} and {args.predictions}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
