"""The runs every shipped design expands into: ids, speeds and gaps, as reference data.

For each design of ``data/designs/*.toml``, one row per run of ``Design.runs()``: the design's
file name, the run's index, ``run_id``, ``point_id``, the design point's speed (rpm, ``repr``:
every digit) and the run's gap g0 (m, ``repr``; empty for a run whose gap is the design's
"none"). The run ids hash the whole run description (:mod:`rubdiag.dataset._ids`), speeds
and gaps included, so equal ids mean equal runs; the speed and gap columns say which number
moved when they are not.

``tests/dataset/test_design_expansion.py`` expands every shipped design again and asks for
exactly these rows.

    python scripts/design_run_ids.py                     # -> data/design_run_ids.csv
    python scripts/design_run_ids.py --check --jobs 2    # compare; exit 1 on a difference
"""

from __future__ import annotations

import argparse
import csv
import io
import sys
from pathlib import Path

import rubdiag

if __name__ == "__main__":     # a run starts here (imported, numpy is loaded already)
    rubdiag.pin_blas_kernels()  # first: before numpy loads OpenBLAS (the tests' kernels)

ROOT = Path(__file__).resolve().parents[1]
DESIGNS = ROOT / "data" / "designs"
OUT = ROOT / "data" / "design_run_ids.csv"
COLUMNS = ("design", "index", "run_id", "point_id", "speed_rpm", "gap_m")


def rows(path: Path, jobs: int = 1) -> list[dict]:
    """The rows of the design at ``path`` (module docstring), in the order of its runs,
    expanded on ``jobs`` worker processes."""
    from rubdiag.dataset import Design

    return [{"design": path.name, "index": str(index), "run_id": item.run_id,
             "point_id": item.point_id, "speed_rpm": repr(float(item.speed_rpm)),
             "gap_m": "" if item.run.gap_m is None else repr(float(item.run.gap_m))}
            for index, item in enumerate(Design.from_toml(path).runs(jobs=jobs))]


def table(paths, jobs: int = 1) -> str:
    """The CSV text of the rows of every design in ``paths``."""
    buffer = io.StringIO()
    writer = csv.DictWriter(buffer, COLUMNS, lineterminator="\n")
    writer.writeheader()
    for path in paths:
        writer.writerows(rows(path, jobs))
    return buffer.getvalue()


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--check", action="store_true",
                        help="compare with data/design_run_ids.csv instead of writing it")
    parser.add_argument("--jobs", type=int, default=1, help="worker processes (default 1)")
    args = parser.parse_args(argv)
    text = table(sorted(DESIGNS.glob("*.toml")), args.jobs)
    if not args.check:
        OUT.write_text(text, encoding="utf-8")
        print(f"{OUT}: {text.count(chr(10)) - 1} runs")
        return 0
    stored = OUT.read_text(encoding="utf-8").splitlines()
    for number, (old, new) in enumerate(zip(stored, text.splitlines(), strict=False), 1):
        if old != new:
            print(f"line {number}: stored {old!r}, now {new!r}")
            return 1
    if len(stored) != text.count("\n"):
        print(f"{len(stored)} lines stored, {text.count(chr(10))} now")
        return 1
    print("the same runs")
    return 0


if __name__ == "__main__":
    sys.exit(main())
