"""Benchmark of the classifier layer: feature extraction through RubFeatures, and predict()
on long measured records.

Usage::

    .venv/bin/python benchmarks/bench_learn.py [--n 500] [--records 6] [--repeat 5]
        [--estimators rf hgb] [--threads 1]

Measured, each ``--repeat`` times (medians reported, min–max beside them):

(a) ``RubFeatures(fs=10000, speed_col=-1).transform(X)`` on ``--n`` synthetic rub-like
    signals of 2 s at 10 kHz, the rows' speeds in X's last column (the signals of
    ``bench_features.py``: 1×, 2×, 3/2×, 4× ± 5 Hz sidebands, a combination pair and white
    noise at 1500 … 5700 rpm); ``fit`` (a shape check) is not timed. Throughput in signals/s
    and in features/s (the transformer's 106 output columns per signal, ``speed_rpm`` and
    ``speed_confidence`` included).
(b) ``rubdiag.learn._predict(model, paths)`` on ``--records`` records of 10 s at 10 kHz
    with the six shaft displacement channels of the paper rig's sensors (the default
    model's inputs), each record a file: CSV (a time column and six channels, written with
    ``%.7g``; 100,000 rows) and NPZ (one array per channel and ``fs``). Timed: the whole
    call — reading each file, cutting it into the model's 2-s windows (5 per record),
    estimating each window's speed from its dominant line (no speed given, the default),
    the features of the 6 channels per window, the model's probabilities, the training-range
    warnings and the majority row per record. Loading the model (skops) is not timed: it
    happens once per ``rubdiag predict``. A breakdown of one record (NPZ; rf) times the
    parts that have public entry points: reading (``read_signals``), features at the known
    speed (``prefixed_features`` per window) and the fitted pipeline on those rows
    (``predict_proba``).

The model: ``rubdiag.learn._train`` (defaults but for the evaluation's importances,
baselines and audit, which are off) on a synthetic dataset made here — 40 design points ×
2 replicates of a 2-s window at 10 kHz, half of the points rubbing, speeds 1200–6800 rpm —
so that the script needs no simulation and runs in about a minute. Rub in the synthetic
signals: a ½× line, 2× and 3× harmonics, 1× amplitude modulation (sidebands) and a burst
of broadband noise once per revolution; without rub: 1×, a weak 2× and the noise floor. The
prediction records are drawn the same way (new seeds), half of them rubbing; the script
checks that the model gets them right (a model that learnt nothing would still time the
same, but would not be worth timing).

``--threads N`` limits the BLAS and OpenMP pools (threadpoolctl) for the whole run (default
1: the forest predicts on one core anyway, ``n_jobs=1``; ``--threads 0`` leaves the pools
at their defaults, one thread per CPU, as ``rubdiag predict`` runs); the load average
(1 min) is read before and after. Prints a Markdown table ready to paste into benchmarks/README.md.
"""

from __future__ import annotations

import argparse
import datetime
import os
import platform
import statistics
import tempfile
import time
from pathlib import Path

import numpy as np
import pandas as pd
from _threads import cpu_model, limit_threads  # benchmarks/ is on sys.path as a script
from bench_features import make_signals

FS = 10_000.0
WINDOW_S = 2.0
RECORD_S = 10.0
# the paper rig's shaft displacement probes: the default model's channels
CHANNELS = [(f"shaft{node}_{axis}_disp", f"shaft {node}", axis)
            for node in (4, 11, 26) for axis in ("y", "z")]


def record(rng: np.random.Generator, rpm: float, rub: bool, seconds: float) -> dict:
    """Six channels (m) of a synthetic machine at ``rpm``, rubbing or not (module doc)."""
    t = np.arange(round(seconds * FS)) / FS
    f1 = rpm / 60.0
    turn = 2 * np.pi * f1 * t + rng.uniform(0, 2 * np.pi)
    bursts = np.zeros_like(t)
    if rub:   # a decaying burst of broadband noise at one point of every revolution
        since = (turn / (2 * np.pi)) % 1.0 / f1
        bursts = np.exp(-since / 2e-3) * rng.standard_normal(t.size)
    out = {}
    for name, point, axis in CHANNELS:
        scale = 300e-6 if point == "shaft 11" else 3e-6      # the disc moves, bearings less
        lag = 0.0 if axis == "y" else np.pi / 2
        level = scale * (0.8 if axis == "z" else 1.0)
        x = level * np.cos(turn - lag) + 0.02 * level * np.cos(2 * turn - lag + 0.4)
        if rub:
            x *= 1.0 + 0.05 * np.cos(2 * np.pi * 3.0 * t)                 # sidebands
            x += level * (0.08 * np.cos(0.5 * turn + 1.0) + 0.10 * np.cos(2 * turn + 0.7)
                          + 0.05 * np.cos(3 * turn + 0.2))
            x += 0.02 * level * bursts
        x += 0.002 * scale * rng.standard_normal(t.size)                 # noise floor
        out[name] = x
    return out


def training_rows(points: int = 40, replicates: int = 2, seed: int = 1,
                  window_s: float = WINDOW_S) -> pd.DataFrame:
    """A synthetic dataset frame as rubdiag.learn.read_dataset returns one (runs of
    ``window_s`` seconds)."""
    from rubdiag.learn._robustness import window_features

    rng = np.random.default_rng(seed)
    names = [c[0] for c in CHANNELS]
    rows, windows = [], []
    for p in range(points):
        rpm = float(rng.uniform(1200.0, 6800.0))
        rub = p % 2 == 1
        for r in range(replicates):
            signals = record(rng, rpm, rub, window_s)
            windows.append(np.vstack([signals[n] for n in names]))
            rows.append({"run_id": f"{p:04x}{r:04x}", "point_id": f"p{p:03d}",
                         "replicate": r, "speed_rpm": rpm, "rub": rub})
    data = pd.DataFrame(rows)
    features = window_features(np.stack(windows), FS, data["speed_rpm"], names)
    data = pd.concat([data, features], axis=1)
    data.attrs.update(
        acquisition={"fs_hz": FS, "window_s": window_s, "discard_s": 0.0,
                     "sensors": [{"name": n, "point": p, "direction": a,
                                  "quantity": "displacement", "unit": "m"}
                                 for n, p, a in CHANNELS]},
        factors=[], failed=0)
    return data


def write_records(folder: Path, n: int, seed: int = 2):
    """``n`` records of 10 s as CSV and as NPZ; (csv paths, npz paths, rub flags)."""
    rng = np.random.default_rng(seed)
    csvs, npzs, rubs = [], [], []
    for i in range(n):
        rub = i % 2 == 0
        signals = record(rng, float(rng.uniform(1500.0, 6500.0)), rub, RECORD_S)
        frame = pd.DataFrame({"t": np.arange(round(RECORD_S * FS)) / FS, **signals})
        csvs.append(folder / f"record{i}.csv")
        frame.to_csv(csvs[-1], index=False, float_format="%.7g")
        npzs.append(folder / f"record{i}.npz")
        np.savez(npzs[-1], fs=FS, **signals)
        rubs.append(rub)
    return csvs, npzs, rubs


def timed(fn, repeat: int):
    """(median, min, max) wall time of ``repeat`` calls and the last result."""
    times, result = [], None
    for _ in range(repeat):
        t0 = time.perf_counter()
        result = fn()
        times.append(time.perf_counter() - t0)
    return statistics.median(times), min(times), max(times), result


def breakdown(model, path: Path, csv: Path, repeat: int) -> dict:
    """Median seconds of one record's parts that have public entry points: reading it (NPZ
    and CSV), its windows' features at the speed predict estimated, the pipeline's feature
    step and the whole pipeline on those rows."""
    from rubdiag.learn import predict
    from rubdiag.signal import read_signals
    from rubdiag.signal._table import prefixed_features

    frame, fs = read_signals(path)
    n = round(model.meta["window_s"] * fs)
    x = {c: frame[c].to_numpy() for c in model.channels}
    speed = float(predict(model, path)["speed_rpm"].iloc[0])   # as predict estimated it
    options = {k: tuple(v) if isinstance(v, list) else v
               for k, v in model.meta["feature_options"].items()}

    def features():
        return pd.concat([prefixed_features({c: v[i * n:(i + 1) * n] for c, v in x.items()},
                                            fs, speed, separator="__", **options)
                          for i in range(len(frame) // n)], ignore_index=True)

    rows = features()
    return {"read NPZ": timed(lambda: read_signals(path), repeat)[0],
            "read CSV": timed(lambda: read_signals(csv), repeat)[0],
            "features": timed(features, repeat)[0],
            "feature step": timed(
                lambda: model.pipeline.named_steps["features"].transform(rows), repeat)[0],
            "pipeline": timed(lambda: model.pipeline.predict_proba(rows), repeat)[0],
            "windows": len(rows)}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, default=500, help="signals of (a)")
    ap.add_argument("--records", type=int, default=6, help="10-s records of (b)")
    ap.add_argument("--repeat", type=int, default=5, help="timed runs of each measurement")
    ap.add_argument("--estimators", nargs="+", default=["rf", "hgb"],
                    choices=["rf", "hgb", "svm", "logreg"])
    ap.add_argument("--threads", type=int, default=1,
                    help="BLAS/OpenMP threads (default 1; 0: leave the pools alone)")
    args = ap.parse_args()
    # imported first, so that the pools they load (OpenMP with scikit-learn) are limited too
    from rubdiag.learn import load_model, predict, train
    from rubdiag.signal import RubFeatures

    pools = limit_threads(args.threads or None)
    load_before = os.getloadavg()[0]
    started = datetime.datetime.now(datetime.UTC)

    # (a) RubFeatures
    X, rpm = make_signals(args.n, FS, 2.0)
    Xs = np.column_stack([X, rpm])
    transformer = RubFeatures(fs=FS, speed_col=-1).fit(Xs)
    transformer.transform(Xs[:2])                                     # warm-up
    med, lo, hi, Z = timed(lambda: transformer.transform(Xs), args.repeat)
    n_out = Z.shape[1]
    rows_a = [("(a) `RubFeatures.transform`, " f"{args.n} signals × 2 s at 10 kHz",
               f"{med:.2f} s", f"{lo:.2f}–{hi:.2f} s",
               f"**{args.n / med:,.0f} signals/s**, {args.n * n_out / med:,.0f} features/s "
               f"({1e3 * med / args.n:.2f} ms per signal)")]

    # (b) predict
    rows_b, sanity, parts = [], [], None
    with tempfile.TemporaryDirectory(prefix="bench_learn_") as tmp:
        tmp = Path(tmp)
        t0 = time.perf_counter()
        data = training_rows()
        made = time.perf_counter() - t0
        csvs, npzs, rubs = write_records(tmp, args.records)
        for estimator in args.estimators:
            t0 = time.perf_counter()
            train(data, tmp / estimator, estimator=estimator, importances=False,
                  baselines=False, audit=False)
            trained = time.perf_counter() - t0
            model = load_model(tmp / estimator)
            f1 = model.meta["scores"]["macro_f1"]
            sanity.append(f"{estimator}: trained in {trained:.1f} s (dataset made in "
                          f"{made:.1f} s), held-out macro-F1 {f1['value']:.3f}")
            predict(model, npzs[:1])                                  # warm-up
            for kind, paths in (("CSV", csvs), ("NPZ", npzs)):
                med, lo, hi, table = timed(lambda m=model, p=paths: predict(m, p), args.repeat)
                majority = table[table["window"] == "all"]
                windows = int((table["window"] != "all").sum())
                right = int((majority["predicted"] == [str(r) for r in rubs]).sum())
                warned = int((majority["warnings"] != "").sum())
                sanity.append(f"{estimator} {kind}: {right} of {len(rubs)} records predicted "
                              f"as their class; {warned} with range warnings")
                rows_b.append((f"(b) `predict`, {estimator}, {kind}",
                               f"{1e3 * med / len(paths):.0f} ms per record",
                               f"{1e3 * lo / len(paths):.0f}–{1e3 * hi / len(paths):.0f} ms",
                               f"**{len(paths) / med:.2f} records/s**, "
                               f"{windows / med:.1f} windows/s"))
            if estimator == "rf":
                parts = breakdown(model, npzs[0], csvs[0], args.repeat)
    load_after = os.getloadavg()[0]

    print(f"bench_learn: {started:%Y-%m-%d %H:%M} UTC; {os.cpu_count()} CPUs ({cpu_model()}); "
          f"Python {platform.python_version()}, numpy {np.__version__}; thread pools: "
          f"{pools}; load average (1 min) {load_before:.1f} before, {load_after:.1f} after; "
          f"median of {args.repeat}")
    print()
    print("| measurement | median | min–max | throughput |")
    print("|---|---:|---:|---|")
    for row in rows_a + rows_b:
        print("| " + " | ".join(row) + " |")
    print()
    if parts is not None:
        ms = {k: f"{1e3 * v:.0f} ms" for k, v in parts.items() if k != "windows"}
        print(f"one record (rf), {parts['windows']} windows of 6 channels, medians: reading "
              f"it {ms['read NPZ']} (NPZ) or {ms['read CSV']} (CSV); prefixed_features of "
              f"its windows at a known speed {ms['features']}; on those rows, the pipeline's "
              f"feature step (OrderFeatures.transform) {ms['feature step']} and the whole "
              f"pipeline's predict_proba {ms['pipeline']}; the rest of a predict call is "
              "the speed estimate, the checks, the training-range warnings (the feature "
              "step again) and the tables")
    print(f"(a): {n_out} output columns per signal")
    for line in sanity:
        print("sanity:", line)


if __name__ == "__main__":
    main()
