#!/usr/bin/env python
"""The documentation's "Model uncertainty" table: what each model-uncertainty factor of the shipped
multi-fault design does to the rig, one factor at a time.

For the design ``data/designs/faults_journal.toml`` (rig ``paper-journal``), each factor of
:data:`rubdiag.dataset._rig_factors.RIG_FACTORS` is set to each of its levels in the design,
the others at their nominal value (1, or the rig's ξ = 0.04), and the linear rig is
measured: the case's critical speeds (the critical speed map with the films), the
threshold of instability (where whirl begins) and the blades' largest linear approach in
each case at the design's middle speed ratio (0.75 of the case's own critical speed: what
sets a rub run's gap through ``interference_ratio``). Linear answers only — a few seconds
in all, no simulation.

    python scripts/uncertainty.py            # -> data/uncertainty.csv
    python scripts/uncertainty.py --table    # the documentation's table, from the CSV

``tests/dataset/test_uncertainty_table.py`` recomputes two rows and compares them with
the CSV, and that the documentation shows the table the CSV gives.
"""

from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path

import pandas as pd

ROOT = Path(__file__).resolve().parents[1]
CSV = ROOT / "data" / "uncertainty.csv"
DESIGN = ROOT / "data" / "designs" / "faults_journal.toml"
SPEED_RATIO = 0.75
RPM = 30.0 / math.pi
COLUMNS = ("crit1_rpm", "crit2_rpm", "threshold_rpm", "approach1_um", "approach2_um")


def design():
    from rubdiag.dataset import Design

    return Design.from_toml(DESIGN)


def variants(d) -> list[tuple[str, float]]:
    """(factor, value) for every level of every rig factor of the design, nominal first."""
    from rubdiag.dataset._rig_factors import RIG_FACTORS

    out = [("nominal", math.nan)]
    for f in d.factors:
        if f.name in RIG_FACTORS:
            out += [(f.name, v) for v in f.grid_levels()]
    return out


def measure(d, factor: str, value: float) -> dict:
    """The row of one variant (module docstring)."""
    from rubdiag.dataset._approach import sweep_linear_approach_m

    base = {} if factor == "nominal" else {factor: value}
    row = {"factor": factor, "value": value}
    for case in (1, 2):
        point = {"case": case, **base}
        row[f"crit{case}_rpm"] = d.critical_speed_rad_s(point) * RPM
        run = d.run_for({**point, "speed_ratio": SPEED_RATIO, "fault": "rub",
                         "interference_ratio": 1.0})
        row[f"approach{case}_um"] = sweep_linear_approach_m(run) * 1e6
    row["threshold_rpm"] = d.whirl_threshold_rad_s(base) * RPM
    return row


def table(rows: pd.DataFrame) -> str:
    """The documentation's table: each variant's values and its change from the nominal rig (%)."""
    nominal = rows[rows.factor == "nominal"].iloc[0]
    heads = ["1st critical (rpm)", "2nd critical (rpm)", "threshold (rpm)",
             "approach case 1 (µm)", "approach case 2 (µm)"]
    lines = ["| factor | value | " + " | ".join(heads) + " |",
             "|---|---:|" + "---:|" * len(heads)]
    for _, r in rows.iterrows():
        cells = []
        for c in COLUMNS:
            digits = 1 if c.endswith("_um") else 0
            text = f"{r[c]:.{digits}f}"
            if r.factor != "nominal":
                text += f" ({100 * (r[c] / nominal[c] - 1):+.1f} %)"
            cells.append(text)
        value = "" if r.factor == "nominal" else f"{r.value:g}"
        lines.append(f"| {r.factor} | {value} | " + " | ".join(cells) + " |")
    return "\n".join(lines)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--table", action="store_true", help="print the documentation's table")
    args = parser.parse_args(argv)
    if args.table:
        print(table(pd.read_csv(CSV)))
        return 0
    d = design()
    rows = pd.DataFrame([measure(d, f, v) for f, v in variants(d)])
    rows.to_csv(CSV, index=False, float_format="%.6g")
    print(table(rows))
    return 0


if __name__ == "__main__":
    sys.exit(main())
