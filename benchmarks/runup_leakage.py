"""How much of the run-up rub-orders figure is the order tracking's own leakage.

The README's run-up (case 1, g0 = 2.3 mm, 600 -> 2400 rpm at 300 rpm/s, both directions,
mid-span ``shaft 11 y``, 4-revolution bins one revolution apart) and the same run-up without
contact (g0 = 50 mm), on the reduced model. For each rub order it prints, away from contact
(more than 50 rpm outside the first-to-last contact speeds) and in contact, the median (and
90th percentile) of the order over 1× and the median of the order over its leakage level
(:func:`rubdiag.signal._leakage.tracking_leakage`: what tracking the 1× track alone puts
there). An order over its leakage near 1 is leakage.

    python benchmarks/runup_leakage.py
"""

from __future__ import annotations

import dataclasses

import numpy as np

from rubdiag.reduce import Reduction
from rubdiag.runs import ramp_run, runup_orders, runup_summary
from rubdiag.signal._leakage import tracking_leakage
from rubdiag.signal._orders import order_label
from rubdiag.simulation import simulate

ORDERS = (0.5, 1.5, 2.0, 3.0)
MARGIN_RPM = 50.0


def main() -> None:
    print("run, direction, where, bins: per order: median (and 90th percentile) of order / 1x, "
          "median of order / leakage")
    for gap_mm in (2.3, 50.0):
        for start, end in ((600, 2400), (2400, 600)):
            run = dataclasses.replace(ramp_run(1, start, end, 300, gap_mm=gap_mm),
                                      reduction=Reduction())
            result = simulate(run)
            track = runup_orders(result)
            leak = tracking_leakage(track, track.attrs["revs_per_bin"], ORDERS)
            summary = runup_summary(result, orders=track)
            lo, hi = sorted((summary["first_contact_rpm"], summary["last_contact_rpm"]))
            rpm = track["rpm"].to_numpy()
            contact = ((rpm > lo - MARGIN_RPM) & (rpm < hi + MARGIN_RPM)
                       if np.isfinite(lo) else np.zeros(rpm.size, bool))
            direction = "run-up" if end > start else "coast-down"
            for where, rows in (("away from contact", ~contact), ("in contact", contact)):
                if not rows.any():
                    continue
                cells = []
                for k in ORDERS:
                    amp = track[f"amp_{order_label(k)}"].to_numpy()[rows]
                    over_1x = 100 * np.quantile(amp / track["amp_1x"].to_numpy()[rows],
                                                (0.5, 0.9))
                    over_leak = np.median(amp / leak[f"amp_{order_label(k)}"].to_numpy()[rows])
                    cells.append(f"{k:g}x {over_1x[0]:.2g} % of 1x (90 %: {over_1x[1]:.2g} %), "
                                 f"{over_leak:.2f} x leakage")
                print(f"g0 = {gap_mm:g} mm, {direction}, {where}, {rows.sum()} bins: "
                      + "; ".join(cells))


if __name__ == "__main__":
    main()
