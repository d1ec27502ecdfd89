"""The ``faults`` command: each fault that looks like rub beside rub, one figure per fault."""

from __future__ import annotations

import io
import json
import math
from pathlib import Path

#: the faults drawn beside rub: the speed where each reference puts its signature (rpm: a
#: crack's 2× resonates at half the first critical speed, 1500 rpm; so does a coupling's
#: 2× force; a loose pedestal lifts most near the critical, where the bearing force peaks)
#: and the shaft direction its figure shows (the pedestal is loose across gravity, along z)
FAULTS = {"crack": (750.0, "y"), "misalignment": (750.0, "y"), "looseness": (1450.0, "z")}
POINT = "shaft 11"


def register(sub) -> None:
    p = sub.add_parser(
        "faults", help="rub beside a breathing crack, a misaligned coupling and a loose "
        "pedestal: one figure per fault",
        description="Simulates case 1 of the paper-pedestal rig (the study's rig with its "
        "drive-end bearing on a pedestal) under gravity: a breathing crack and a misaligned "
        "coupling at 750 rpm (half the first critical speed), a loose pedestal at 1450 rpm, "
        "each without rub, and at each of those speeds a rubbing and a healthy run. For "
        "each fault it draws the fault's and the rub run's shaft waveform, orbit and "
        "spectrum, with the lines each model predicts marked (faults_<fault>.png), and "
        "prints the lines' amplitudes at shaft 11.")
    p.add_argument("--speed-rpm", type=float,
                   help="one speed for every run (rpm; default: each fault's own, above)")
    p.add_argument("--interference", type=float, default=1.3,
                   help="the rub runs' gap: their linear blade-tip approach over this ratio "
                   "(default 1.3: a rub that touches every revolution)")
    p.add_argument("--crack-depth", type=float, default=0.4,
                   help="crack depth ratio a/D (default 0.4)")
    p.add_argument("--misalignment-angle-mrad", type=float, default=10.0,
                   help="the coupling's angular misalignment (mrad, default 10)")
    p.add_argument("--loose-preload-n", type=float, default=5.0,
                   help="the force left pressing the loose pedestal on its seat, across "
                   "gravity (N, default 5)")
    p.add_argument("--duration-s", type=float, default=2.0,
                   help="simulated time per run (s, default 2; the last half is analysed)")
    p.add_argument("--out", type=Path, required=True, help="output folder (created)")
    p.add_argument("--json", action="store_true",
                   help="print the lines as JSON (m): run -> direction -> order -> amplitude")
    p.set_defaults(func=_faults)


def runs(args) -> dict:
    """The runs of the figures, by name: each fault of :data:`FAULTS` (``"crack"`` …), and
    ``"rub <rpm>"`` and ``"none <rpm>"`` at each speed the faults run at."""
    from rubdiag import _check
    from rubdiag.dataset.approach import sweep_linear_approach_m
    from rubdiag.model import preset_rig
    from rubdiag.simulate import Run
    from rubdiag.simulate.faults import Crack, Faults, Looseness
    from rubdiag.simulate.misalignment import Misalignment
    from rubdiag.simulate.static_load import StaticLoad

    interference = _check.number("--interference", args.interference, lo=0.0, hi=100.0,
                                 lo_open=True)

    def run(rpm, gap_mm=None, **options):
        return Run.paper_case(1, gap_mm, speed_rpm=rpm, duration_s=args.duration_s,
                              discard_s=0.5 * args.duration_s,
                              rig=preset_rig("paper-pedestal"),
                              static_load=StaticLoad(direction="y", gravity_m_s2=-9.81),
                              **options)

    faults = {
        "crack": Crack(element=10, depth_ratio=args.crack_depth, law="gasch"),
        "misalignment": Misalignment(node=3, drive_torque_n_m=20.0, spacer_length_m=0.05,
                                     angle_rad=args.misalignment_angle_mrad * 1e-3),
        "looseness": Looseness(bearing=0, preload_n=args.loose_preload_n, direction="z"),
    }
    out = {name: run(fault_speed(args, name), faults=Faults(**{name: fault}))
           for name, fault in faults.items()}
    for rpm in sorted({fault_speed(args, name) for name in FAULTS}):
        probe = run(rpm, 50.0)              # the casing out of reach: the linear approach
        gap_mm = 1e3 * sweep_linear_approach_m(probe) / interference
        out[f"rub {rpm:g}"] = run(rpm, gap_mm, gap_ramp_s=0.25 * args.duration_s)
        out[f"none {rpm:g}"] = run(rpm)
    return out


def fault_speed(args, name: str) -> float:
    """The speed (rpm) of fault ``name``'s figure."""
    return FAULTS[name][0] if args.speed_rpm is None else args.speed_rpm


def line_amplitudes(result, point: str, orders) -> dict[str, float]:
    """The amplitude (m) of each order's line of ``point`` over the window: a lock-in over
    the window's whole multiple of 6 revolutions (⅓× and ½× fit in it whole)."""
    import numpy as np

    t = result.t[result.window]
    x = result.displacement(point, True)
    omega = result.run.speed_rad_s
    revs = math.floor((t[-1] - t[0]) * omega / (2 * math.pi))
    revs = revs - revs % 6 if revs >= 6 else revs
    keep = t <= t[0] + revs * 2 * math.pi / omega
    x = x[keep] - x[keep].mean()
    return {f"{k:.3g}x": float(2 * abs(np.mean(x * np.exp(-1j * k * omega * t[keep]))))
            for k in orders}


def _faults(args) -> int:
    from rubdiag._atomic import write_bytes
    from rubdiag.cli._paths import output_folder
    from rubdiag.plotting.faults import PREDICTED, faults_figure
    from rubdiag.simulate import simulate

    out = output_folder(args.out)
    results = {name: simulate(run) for name, run in runs(args).items()}
    orders = sorted({k for name in results for k in PREDICTED[name.split()[0]]})
    table = {name: {d: line_amplitudes(r, f"{POINT} {d}", orders) for d in "yz"}
             for name, r in results.items()}
    written = []
    for fault, (_, direction) in FAULTS.items():
        rub = f"rub {fault_speed(args, fault):g}"
        fig = faults_figure({fault: results[fault], "rub": results[rub]}, POINT,
                            direction=direction)
        buf = io.BytesIO()
        fig.savefig(buf, format="png", dpi=90)
        path = out / f"faults_{fault}.png"
        write_bytes(path, buf.getvalue())
        written.append(path)
    if args.json:
        print(json.dumps(table))
        return 0
    print(f"{POINT}, line amplitudes (um) over the window")
    for name, by_direction in table.items():
        rpm, gap = results[name].run.speed_rpm, results[name].run.gap_m
        what = f"{name.split()[0]} {rpm:.0f} rpm" + (f" g0 {gap * 1e3:.3f} mm"
                                                     if name.startswith("rub") else "")
        for d, row in by_direction.items():
            print(f"  {what:26s} {d} " + " ".join(f"{k} {v * 1e6:8.3f}" for k, v in row.items()))
    print("wrote " + ", ".join(str(p) for p in written))
    return 0
