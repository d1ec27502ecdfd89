"""The ``faults`` command: the faults that look like rub, beside rub, in one figure."""

from __future__ import annotations

import io
import json
from pathlib import Path


def register(sub) -> None:
    p = sub.add_parser(
        "faults", help="rub beside a breathing crack and a misaligned coupling: one figure",
        description="Simulates case 1 of the paper rig at one speed, under gravity: rubbing "
        "(g0 = --gap-mm), with a breathing crack (no rub), with a misaligned coupling (no "
        "rub), and healthy; draws for each the shaft's waveform, orbit and spectrum with the "
        "lines its model predicts marked (faults.png), and prints the lines' amplitudes.")
    p.add_argument("--speed-rpm", type=float, default=1500.0,
                   help="speed (rpm, default 1500: case 1's critical speed)")
    p.add_argument("--gap-mm", type=float, default=1.9, help="the rub run's gap (mm)")
    p.add_argument("--crack-depth", type=float, default=0.4, help="crack depth ratio a/D")
    p.add_argument("--misalignment-offset-mm", type=float, default=0.5,
                   help="the coupling's parallel offset (mm)")
    p.add_argument("--duration-s", type=float, default=1.0,
                   help="simulated time per run (s, default 1; the last half is analysed)")
    p.add_argument("--out", type=Path, required=True, help="output folder (created)")
    p.add_argument("--json", action="store_true", help="print the lines as JSON (m)")
    p.set_defaults(func=_faults)


def runs(args) -> dict:
    """The four runs of the figure, by name."""
    from rubdiag.simulate import Run
    from rubdiag.simulate.faults import Crack, Faults
    from rubdiag.simulate.misalignment import Misalignment
    from rubdiag.simulate.static_load import StaticLoad

    common = dict(speed_rpm=args.speed_rpm, duration_s=args.duration_s,
                  discard_s=0.5 * args.duration_s,
                  static_load=StaticLoad(direction="y", gravity_m_s2=-9.81))
    coupling = Misalignment(node=3, drive_torque_n_m=20.0, spacer_length_m=0.05,
                            offset_m=args.misalignment_offset_mm * 1e-3)
    return {
        "rub": Run.paper_case(1, args.gap_mm, gap_ramp_s=0.25 * args.duration_s, **common),
        "crack": Run.paper_case(1, None, faults=Faults(
            crack=Crack(element=10, depth_ratio=args.crack_depth)), **common),
        "misalignment": Run.paper_case(1, None, faults=Faults(misalignment=coupling),
                                       **common),
        "none": Run.paper_case(1, None, **common),
    }


def line_amplitudes(result, point: str, orders) -> dict[str, float]:
    """The amplitude (m) of each order's line of ``point`` over the window: a lock-in over
    the whole revolutions of the window."""
    import math

    import numpy as np

    t = result.t[result.window]
    x = result.displacement(point, True)
    omega = result.run.speed_rad_s
    revs = math.floor((t[-1] - t[0]) * omega / (2 * math.pi))
    keep = t <= t[0] + revs * 2 * math.pi / omega
    x = x[keep] - x[keep].mean()
    return {f"{k:g}x": float(2 * abs(np.mean(x * np.exp(-1j * k * omega * t[keep]))))
            for k in orders}


def _faults(args) -> int:
    from rubdiag._atomic import write_bytes
    from rubdiag.cli._paths import output_folder
    from rubdiag.plotting.faults import PREDICTED, faults_figure
    from rubdiag.simulate import simulate

    out = output_folder(args.out)
    results = {name: simulate(run) for name, run in runs(args).items()}
    orders = sorted({k for name in results for k in PREDICTED[name]})
    table = {name: line_amplitudes(r, "shaft 11 y", orders) for name, r in results.items()}
    fig = faults_figure(results)
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=90)
    write_bytes(out / "faults.png", buf.getvalue())
    if args.json:
        print(json.dumps(table))
        return 0
    print("shaft 11 y, line amplitudes (um) over the window")
    for name, row in table.items():
        print(f"  {name:13s} " + "  ".join(f"{k} {v * 1e6:8.3f}" for k, v in row.items()))
    print(f"wrote {out / 'faults.png'}")
    return 0
