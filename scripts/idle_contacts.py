#!/usr/bin/env python
"""What leaving out-of-reach blade contacts to the modes changes in a dataset's rows.

The journal ensemble of ``scripts/step_study.py`` (``data/designs/faults_journal.toml``,
20 design points, two per fault level, three start histories, the default long steps and
measurement noise) is made twice: as rubdiag makes it — a run whose casing is out of reach
simulated on the reduction without its blade contacts
(:mod:`rubdiag.simulation._idle_contacts`) — and with ``Reduction(keep_idle_contacts=True)``.
The rubbing runs are the same runs in both; the others (30 runs) differ only by the
reduced basis. Both are measured with the same noise draw
(:func:`rubdiag.dataset._ids.noise_id`).

Per family of quantities, over the runs without rub, as the step study: the change
(median over runs of |left out − kept|) against max(scatter between start histories,
0.1 % of the quantity's size), the share below a quarter of it, the 95th percentile and
the largest ratio; the labels' agreement and the simulate time.

    python scripts/idle_contacts.py --out idle-study          # both ensembles, the table
    python scripts/idle_contacts.py --table                   # the table, from the CSV

``data/idle_contacts.csv`` holds the table; ``tests/dataset/test_idle_contacts_study.py``
checks it against the goal.
"""

from __future__ import annotations

import argparse
import dataclasses
import sys
import time
from pathlib import Path

import pandas as pd

sys.path.insert(0, str(Path(__file__).resolve().parent))
import step_study  # the ensemble, the comparison and the table's format

ROOT = Path(__file__).resolve().parents[1]
CSV = ROOT / "data" / "idle_contacts.csv"


def generate(out: Path, keep: bool, jobs: int) -> pd.DataFrame:
    """The journal ensemble into ``out``, with its idle contacts kept or left out."""
    from rubdiag.dataset import generate as make
    from rubdiag.dataset import load
    from rubdiag.reduce import Reduction

    design = step_study.designs(1e-5, ("journal",))["journal"]
    design = dataclasses.replace(design, reduction=Reduction(keep_idle_contacts=keep))
    folder = out / ("kept" if keep else "left-out")
    start = time.perf_counter()
    make(design, folder, jobs=jobs, progress=False)
    print(f"{folder}: {time.perf_counter() - start:.1f} s", file=sys.stderr)
    return load(folder)


def table(kept: pd.DataFrame, left: pd.DataFrame) -> pd.DataFrame:
    """The CSV: the step study's table of ``left`` against ``kept`` (one row per family),
    over the runs without rub (the rubbing runs are the same runs in both). Runs are matched
    by their factors without ``interference_ratio``, which a run without rub reports as its
    linear approach over its gap (so from its reduced model)."""
    kept, left = (rows[~rows["fault"].str.contains("rub")].drop(columns="interference_ratio")
                  for rows in (kept, left))
    return step_study.table({"journal": kept}, {"journal": left}, 1e-5)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", type=Path, default=Path("idle-study"))
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--table", action="store_true", help="print the table from the CSV")
    args = ap.parse_args(argv)
    if not args.table:
        kept = generate(args.out, True, args.jobs)
        left = generate(args.out, False, args.jobs)
        table(kept, left).to_csv(CSV, index=False)
    print(step_study.markdown(pd.read_csv(CSV)))
    return 0


if __name__ == "__main__":
    sys.exit(main())
