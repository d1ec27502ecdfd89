#!/usr/bin/env python
"""The documentation's noise-robustness table: the default rub model's held-out macro-F1
against the SNR of white noise added to its channels, trained at each noise level and
trained on the stored features (a machine noisier than the simulation).

On a dataset made with ``--waveforms`` (the classifier design):

    rubdiag dataset data/designs/rub_classifier_lhs300.toml --out clf --waveforms --jobs 2
    python scripts/noise_table.py clf          # -> data/noise_curve.csv
    python scripts/noise_table.py --table      # the documentation's table, from the CSV

Both curves are :func:`rubdiag.learn.noise_curve` (rub, the default forest, design points
held out) at :data:`SNR_DB`. The CSV keeps each level's macro-F1 with its 95 % interval,
the chance interval, and the noise σ added at each channel (m for the displacement
probes). ``tests/learn/test_noise_table.py`` checks the documented table against the CSV
and the σ of each level against the SNR it was made for.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np
import pandas as pd

ROOT = Path(__file__).resolve().parents[1]
CSV = ROOT / "data" / "noise_curve.csv"
SNR_DB = (40, 30, 20, 10, 5, 0)
TRAIN_ON = {"noisy": "trained at each level", "stored": "trained as stored"}
#: the probes whose added σ the table shows (the disc's pair)
DISC = ("shaft11_y_disp", "shaft11_z_disp")


def measure(dataset) -> pd.DataFrame:
    """Both curves, one row per (train_on, level)."""
    from rubdiag.learn import noise_curve

    curves = [noise_curve(dataset, snr_db=SNR_DB, train_on=how).assign(train_on=how)
              for how in TRAIN_ON]
    return pd.concat(curves, ignore_index=True)


def _level(snr_db: float) -> str:
    return "as stored" if np.isinf(snr_db) else f"{snr_db:g} dB"


def table(rows: pd.DataFrame) -> str:
    """The documentation's table: macro-F1 [95 %] per level and way of training, then the
    σ added at the disc probes."""
    levels = list(dict.fromkeys(rows["snr_db"]))
    lines = ["| added noise | " + " | ".join(_level(s) for s in levels) + " |",
             "|---|" + "---|" * len(levels)]
    for how, name in TRAIN_ON.items():
        part = rows[rows["train_on"] == how].set_index("snr_db")
        cells = [f"{part.loc[s, 'macro_f1']:.2f} [{part.loc[s, 'macro_f1_lo']:.2f}, "
                 f"{part.loc[s, 'macro_f1_hi']:.2f}]" for s in levels]
        lines.append(f"| {name} | " + " | ".join(cells) + " |")
    noisy = rows[rows["train_on"] == "noisy"].set_index("snr_db")
    sigma = noisy[[f"{p}__noise_std" for p in DISC]].max(axis=1)
    lines.append("| σ at the disc probes | " + " | ".join(
        "–" if np.isinf(s) else _length(sigma.loc[s]) for s in levels) + " |")
    return "\n".join(lines)


def _length(metres: float) -> str:
    return f"{metres * 1e6:.2g} µm" if metres < 1e-4 else f"{metres * 1e3:.2g} mm"


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("dataset", nargs="?", help="a dataset folder made with --waveforms")
    parser.add_argument("--table", action="store_true", help="print the documentation's table")
    args = parser.parse_args(argv)
    if args.table:
        print(table(pd.read_csv(CSV)))
        return 0
    if args.dataset is None:
        parser.error("give the dataset folder, or --table")
    rows = measure(args.dataset)
    rows.to_csv(CSV, index=False, float_format="%.6g")
    print(table(rows))
    return 0


if __name__ == "__main__":
    sys.exit(main())
