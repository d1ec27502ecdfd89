"""Noise-free records against noisy ones: where the noise floor of ``bb_<n>x_over_floor`` sits,
and how a model trained on noise reads records without it, for several least floors.

Two datasets of the same 60 runs (reduced model, 0.6-s windows, both cases, speeds 0.8–1.2 of
the critical, gaps 0.3–2.5 mm): with the default noise floors and with every floor 0. Prints

* the mid-span probe's floor (its quietest band) over its level, noisy and noise-free, the
  loudest band 2× … 8× over the level in the rubbing runs and in the others, and the loudest
  band over the quietest (what ``bb_<n>x_over_floor`` reached before the least floor);
* for least floors ``MIN_FLOOR_OF_LEVEL`` from 1e-12 (no rule, in effect) to 1e-2: over four
  random halves (train on one half's noisy rows, predict the other half), the share of
  held-out runs whose noise-free row is predicted as their noisy row, and the accuracy on
  the noisy rows — rub and severity, forest and logistic regression, the six shaft probes and
  the mid-span probe alone.

    python benchmarks/bench_noise_free.py [--out FOLDER]     # about 2 min of simulation
"""

from __future__ import annotations

import argparse
import tempfile
from pathlib import Path

import numpy as np
import pandas as pd

import rubdiag.signal._bandfloor as bandfloor
from rubdiag.dataset import Design, generate, load
from rubdiag.dataset._noise import NoiseFloors
from rubdiag.learn import make_pipeline, shaft_channels
from rubdiag.learn._features import _level
from rubdiag.signal._orders import HARMONICS

DESIGN = """
[base]
rig = "paper"
duration_s = 0.85
discard_s = 0.25
reduced = true

[sampling]
method = "lhs"
n = 60
seed = 3

[factors]
case = [1, 2]
speed_ratio = {low = 0.8, high = 1.2}
gap_mm = {low = 0.3, high = 2.5}
"""
#: Every noise floor 0 (the sensor records of the same runs without noise).
NO_NOISE = "\n[noise]\n" + "".join(f"{k} = 0.0\n" for k in NoiseFloors().to_dict())
PROBE = "shaft11_y_disp"
FRACTIONS = (1e-12, 1e-5, 1e-4, 1e-3, 1e-2)


def datasets(root: Path) -> tuple[pd.DataFrame, pd.DataFrame]:
    out = []
    for name, text in (("noisy", DESIGN), ("clean", DESIGN + NO_NOISE)):
        if not (root / name / "design.toml").is_file():
            generate(Design.from_toml(text), root / name, jobs=1, progress=False)
        out.append(load(root / name))
    return out[0], out[1]


def floors(noisy: pd.DataFrame, clean: pd.DataFrame) -> None:
    bands = [f"{PROBE}__bb_{n}x_rms" for n in HARMONICS if n > 1]
    rub = noisy["rub"].to_numpy(bool)
    for name, rows in (("noisy", noisy), ("noise-free", clean)):
        level = _level(rows, PROBE)
        old = rows[[f"{PROBE}__bb_{n}x_rms" for n in HARMONICS]].to_numpy()
        quietest = np.nanmin(np.where(old > 0, old, np.nan), axis=1)
        over_quietest = np.nanmax(old, axis=1) / quietest      # before the rule
        quietest = quietest / level
        loudest = np.nanmax(rows[bands].to_numpy(), axis=1) / level
        q = np.nanquantile(quietest, (0.1, 0.5, 0.9))
        print(f"{PROBE}, {name}: quietest band / level: 10 % {q[0]:.2g}, median {q[1]:.2g}, "
              f"90 % {q[2]:.2g}; loudest band 2x-8x / level: rubbing runs 10 % "
              f"{np.quantile(loudest[rub], 0.1):.2g}, median {np.median(loudest[rub]):.2g}; "
              f"others 90 % {np.quantile(loudest[~rub], 0.9):.2g}; loudest band over the "
              f"quietest (no rule): median {np.median(over_quietest):.3g}, largest "
              f"{over_quietest.max():.3g}")


def agreement(noisy: pd.DataFrame, clean: pd.DataFrame) -> pd.DataFrame:
    rng = np.random.default_rng(0)
    halves = [rng.permutation(len(noisy)) < len(noisy) // 2 for _ in range(4)]
    rows = []
    for fraction in FRACTIONS:
        bandfloor.MIN_FLOOR_OF_LEVEL = fraction       # read at every call
        for channels in ("shaft", PROBE):
            names = shaft_channels(noisy) if channels == "shaft" else [PROBE]
            for target in ("rub", "severity"):
                for estimator in ("rf", "logreg"):
                    same, right = [], []
                    for train in halves:
                        y = noisy[target].astype(str)
                        model = make_pipeline(estimator, channels=names).fit(noisy[train],
                                                                             y[train])
                        p_noisy, p_clean = model.predict(noisy[~train]), model.predict(
                            clean[~train])
                        same.append(np.mean(p_noisy == p_clean))
                        right.append(np.mean(p_noisy == y[~train]))
                    rows.append({"least floor": f"{fraction:g}", "channels": channels,
                                 "target": target, "estimator": estimator,
                                 "alike": np.mean(same), "accuracy": np.mean(right)})
    return pd.DataFrame(rows)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, help="keep the datasets in this folder (reused)")
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        noisy, clean = datasets(args.out or Path(tmp))
        assert list(noisy["run_id"]) == list(clean["run_id"])
        floors(noisy, clean)
        table = agreement(noisy, clean)
    for value in ("alike", "accuracy"):
        print(f"\n{value} (held-out runs, mean of 4 halves):")
        print(table.pivot_table(index=["channels", "target", "estimator"],
                                columns="least floor", values=value, sort=False).to_string(
                                    float_format="{:.2f}".format))


if __name__ == "__main__":
    main()
