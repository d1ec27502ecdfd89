"""Benchmark of ``rubdiag predict`` over a folder of short records, each with its own speed.

Usage::

    .venv/bin/python benchmarks/bench_predict_files.py [--files 120] [--repeat 3]

Timed, ``--repeat`` times (median printed, min–max beside it), as a subprocess — the whole
command, interpreter start-up and imports included::

    rubdiag predict MODEL DIR --speeds speeds.csv --out table.csv

``DIR`` holds ``--files`` records of 1 s at 10 kHz as CSV (a time column and the two disc
probes ``shaft11_y_disp``, ``shaft11_z_disp``, written with ``%.7g``), drawn at speeds from
1500 to 6500 rpm, every other one rubbing; ``speeds.csv`` gives each file's speed
(``file``, ``speed_rpm``). The model: the default classifier (``make_pipeline("rf")`` on the
two disc probes, default feature families, 1-s windows) fitted on a synthetic dataset of 40
design points × 2 replicates made here (``bench_learn.py``'s signals: rub is a ½× line, 2×
and 3× harmonics, 1× modulation and a burst of broadband noise once per revolution), so
nothing is simulated. The script checks the table: one row per window and per file, every
speed from the CSV, and how many records are predicted as their class.

:func:`predict_files_seconds` runs the same measurement for another script (it makes the
model and the files in a temporary folder) and returns the median.
"""

from __future__ import annotations

import argparse
import datetime
import os
import platform
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
import pandas as pd
from _threads import cpu_model  # benchmarks/ is on sys.path as a script
from bench_learn import FS, record, training_rows

RECORD_S = 1.0
CHANNELS = ["shaft11_y_disp", "shaft11_z_disp"]


def make_model(out: Path) -> Path:
    """The default random forest on the disc probes, fitted on 80 synthetic 1-s runs;
    saved as a model folder ``out``."""
    from rubdiag.learn import make_pipeline
    from rubdiag.learn._features import DEFAULT_FAMILIES
    from rubdiag.learn._persist import save_model
    from rubdiag.learn._train import model_meta

    data = training_rows(window_s=RECORD_S)
    pipeline = make_pipeline("rf", channels=CHANNELS).fit(data, data["rub"].astype(str))
    meta = model_meta(pipeline, data, target="rub", estimator="rf", split="group",
                      families=DEFAULT_FAMILIES, seed=0)
    return save_model(pipeline, out, meta)


def make_files(folder: Path, n: int, seed: int = 2) -> tuple[Path, Path, list[bool]]:
    """``n`` records of 1 s in ``folder/records`` and their speeds in
    ``folder/speeds.csv``; (records folder, speeds file, rub flags)."""
    rng = np.random.default_rng(seed)
    records = folder / "records"
    records.mkdir()
    speeds, rubs = [], []
    t = np.arange(round(RECORD_S * FS)) / FS
    for i in range(n):
        rpm, rub = float(rng.uniform(1500.0, 6500.0)), i % 2 == 0
        signals = record(rng, rpm, rub, RECORD_S)
        name = f"record{i:03d}.csv"
        pd.DataFrame({"t": t, **{c: signals[c] for c in CHANNELS}}).to_csv(
            records / name, index=False, float_format="%.7g")
        speeds.append({"file": name, "speed_rpm": rpm})
        rubs.append(rub)
    pd.DataFrame(speeds).to_csv(folder / "speeds.csv", index=False)
    return records, folder / "speeds.csv", rubs


def command(model: Path, records: Path, speeds: Path, out: Path) -> list[str]:
    """``rubdiag predict MODEL DIR --speeds speeds.csv --out table.csv`` as argv."""
    script = Path(sys.executable).with_name("rubdiag")
    head = [str(script)] if script.exists() else [sys.executable, "-m", "rubdiag"]
    return [*head, "predict", str(model), str(records), "--speeds", str(speeds), "--out",
            str(out)]


def timed_runs(argv: list[str], repeat: int) -> list[float]:
    """Wall seconds of ``repeat`` runs of ``argv`` (each must succeed)."""
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        done = subprocess.run(argv, capture_output=True, text=True)
        times.append(time.perf_counter() - t0)
        if done.returncode != 0:
            raise SystemExit(f"{' '.join(argv)} failed: {done.stderr.strip()}")
    return times


def measure(folder: Path, n_files: int = 120, repeat: int = 3) -> dict:
    """Make the model and the files in ``folder`` and time the command; its times and what
    the table says."""
    model = make_model(folder / "model")
    records, speeds, rubs = make_files(folder, n_files)
    out = folder / "table.csv"
    times = timed_runs(command(model, records, speeds, out), repeat)
    table = pd.read_csv(out)
    whole = table[table["window"] == "all"]
    given = pd.read_csv(speeds).set_index("file")["speed_rpm"]
    windows = table[table["window"] != "all"]
    return {"times": times, "rows": len(table), "windows": len(windows),
            "right": int((whole["predicted"].astype(str).to_numpy()
                          == np.asarray([str(r) for r in rubs])).sum()),
            "speeds_used": bool((windows["speed_source"] == "speeds").all() and np.allclose(
                windows["speed_rpm"], given[[Path(p).name for p in windows["input"]]])),
            "files": n_files}


def predict_files_seconds(n_files: int = 120, repeat: int = 3) -> float:
    """Median wall seconds of ``rubdiag predict MODEL DIR --speeds speeds.csv --out
    table.csv`` on ``n_files`` one-second records (module docstring), over ``repeat`` runs
    of a fresh process each; the model and the files are made in a temporary folder."""
    with tempfile.TemporaryDirectory(prefix="bench_predict_files_") as tmp:
        return statistics.median(measure(Path(tmp), n_files, repeat)["times"])


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--files", type=int, default=120, help="1-s records (default 120)")
    ap.add_argument("--repeat", type=int, default=3, help="timed runs (default 3)")
    args = ap.parse_args()
    load_before = os.getloadavg()[0]
    started = datetime.datetime.now(datetime.UTC)
    with tempfile.TemporaryDirectory(prefix="bench_predict_files_") as tmp:
        found = measure(Path(tmp), args.files, args.repeat)
    load_after = os.getloadavg()[0]
    times = found["times"]
    print(f"bench_predict_files: {started:%Y-%m-%d %H:%M} UTC; {os.cpu_count()} CPUs "
          f"({cpu_model()}); Python {platform.python_version()}; load average (1 min) "
          f"{load_before:.1f} before, {load_after:.1f} after")
    print(f"rubdiag predict MODEL DIR --speeds speeds.csv --out table.csv, {found['files']} "
          f"files of 1 s: median {statistics.median(times):.2f} s over {len(times)} runs "
          f"({min(times):.2f}–{max(times):.2f} s), "
          f"{1e3 * statistics.median(times) / found['files']:.0f} ms per file")
    print(f"sanity: {found['rows']} rows ({found['windows']} windows); speeds from the CSV: "
          f"{found['speeds_used']}; {found['right']} of {found['files']} records predicted "
          "as their class")


if __name__ == "__main__":
    main()
