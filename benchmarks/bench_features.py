"""Benchmark of the feature table's batch path: features() on many signals at once.

Builds ``--n`` synthetic rub-like signals (1×, 2×, 3×/2, 4× ± 5 Hz sidebands, a combination
pair and white noise; speeds spread over 1500 … 5700 rpm) of ``--duration`` seconds at
``--fs`` Hz, then times :func:`rubdiag.signal_features` on the whole 2-D array (rows are signals).

Usage::

    PYTHONPATH=. .venv/bin/python benchmarks/bench_features.py [--n 1000] [--fs 10000]
        [--duration 2] [--repeat 5]

Prints the median wall time of ``--repeat`` runs and the time per signal.
"""

from __future__ import annotations

import argparse
import statistics
import time

import numpy as np

import rubdiag


def make_signals(n: int, fs: float, duration: float, seed: int = 0):
    rng = np.random.default_rng(seed)
    m = round(fs * duration)
    t = np.arange(m) / fs
    rpm = rng.choice([1500.0, 2400.0, 3600.0, 5700.0], size=n)
    f1 = (rpm / 60.0)[:, None]
    X = np.cos(2 * np.pi * f1 * t) + 0.2 * np.cos(2 * np.pi * 2 * f1 * t + 1.0)
    X += 0.02 * np.cos(2 * np.pi * 1.5 * f1 * t)
    X += 0.01 * (np.cos(2 * np.pi * (4 * f1 - 5) * t) + np.cos(2 * np.pi * (4 * f1 + 5) * t))
    X += 0.01 * (np.cos(2 * np.pi * 0.45 * f1 * t) + np.cos(2 * np.pi * 1.55 * f1 * t))
    X += 1e-3 * rng.standard_normal(X.shape)
    return X, rpm


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, default=1000, help="number of signals")
    ap.add_argument("--fs", type=float, default=10_000.0, help="sampling frequency (Hz)")
    ap.add_argument("--duration", type=float, default=2.0, help="record length (s)")
    ap.add_argument("--repeat", type=int, default=5)
    args = ap.parse_args()

    X, rpm = make_signals(args.n, args.fs, args.duration)
    table = rubdiag.signal_features(X[:2], args.fs, rpm[:2])  # warm-up (window tables)
    times = []
    for _ in range(args.repeat):
        t0 = time.perf_counter()
        table = rubdiag.signal_features(X, args.fs, rpm)
        times.append(time.perf_counter() - t0)
    median = statistics.median(times)
    found = float(np.isfinite(table["sb_4x_delta_hz"]).mean())
    print(
        f"features(): {args.n} signals x {X.shape[1]} samples ({args.duration:g} s at "
        f"{args.fs:g} Hz), {table.shape[1] - 1} features"
    )
    print(
        f"median of {args.repeat} runs: {median:.3f} s  ({1e3 * median / args.n:.2f} ms per "
        f"signal; min {min(times):.3f} s, max {max(times):.3f} s)"
    )
    print(f"sanity: 4x sidebands found in {100 * found:.0f} % of the signals")


if __name__ == "__main__":
    main()
