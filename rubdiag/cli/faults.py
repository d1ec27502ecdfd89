"""The ``faults`` command: each fault that looks like rub beside rub, one figure per fault."""

from __future__ import annotations

import json
from pathlib import Path

from rubdiag.cli._defaults import FromLibrary
from rubdiag.cli._quiet import add_quiet_option

POINT = "shaft 11"
#: the function whose keywords the options stand for
_RUNS = "rubdiag.runs._faults:fault_runs."


def register(sub) -> None:
    p = sub.add_parser(
        "faults", help="rub beside a breathing crack, a misaligned coupling and a loose "
        "pedestal: one figure per fault",
        description="Simulates case 1 of the paper-pedestal rig (the study's rig with its "
        "drive-end bearing on a pedestal) under gravity: a breathing crack and a misaligned "
        "coupling at 750 rpm (half the first critical speed), a loose pedestal at 1450 rpm, "
        "each without rub, and at each of those speeds a rubbing and a healthy run; and on "
        "paper-journal (the same rig on plain journal bearings) case 2 whipping above its "
        "threshold of instability beside rub below it. For each fault it draws the fault's "
        "and the rub run's shaft waveform, orbit and spectrum, with the lines each model "
        "predicts marked (faults_<fault>.png), and prints the lines' amplitudes at shaft "
        "11.")
    p.add_argument("--speed-rpm", type=float,
                   help="one speed for every run (rpm; default: each fault's own, above)")
    p.add_argument("--interference", type=float, action=FromLibrary,
                   default_of=_RUNS + "interference",
                   help="the rub runs' gap: their linear blade-tip approach over this ratio "
                   "(default {default}: a rub that touches every revolution)")
    p.add_argument("--crack-depth", type=float, action=FromLibrary,
                   default_of=_RUNS + "crack_depth",
                   help="crack depth ratio a/D (default {default})")
    p.add_argument("--misalignment-angle-mrad", type=float, action=FromLibrary,
                   default_of=_RUNS + "misalignment_angle_mrad",
                   help="the coupling's angular misalignment (mrad, default {default})")
    p.add_argument("--loose-preload-n", type=float, action=FromLibrary,
                   default_of=_RUNS + "loose_preload_n",
                   help="the force left pressing the loose pedestal on its seat, across "
                   "gravity (N, default {default})")
    p.add_argument("--duration-s", type=float, action=FromLibrary,
                   default_of=_RUNS + "duration_s",
                   help="simulated time per run (s, default {default}; the last half is "
                   "analysed)")
    p.add_argument("--out", type=Path, required=True, help="output folder (created)")
    p.add_argument("--json", action="store_true",
                   help="print the lines as JSON (m): run -> direction -> order -> amplitude")
    add_quiet_option(p)
    p.set_defaults(func=_faults)


def _faults(args) -> int:
    from rubdiag.cli._paths import output_folder
    from rubdiag.plotting import save_figure
    from rubdiag.plotting._faults import PREDICTED, faults_figure
    from rubdiag.runs import FIGURE_FAULTS, fault_runs, line_amplitudes, whirl_runs

    runs = fault_runs(speed_rpm=args.speed_rpm, interference=args.interference,
                      crack_depth=args.crack_depth,
                      misalignment_angle_mrad=args.misalignment_angle_mrad,
                      loose_preload_n=args.loose_preload_n, duration_s=args.duration_s)
    journal, whip_order = whirl_runs(interference=args.interference)
    out = output_folder(args.out)
    results, journal = _simulated([runs, journal], not args.quiet)
    orders = sorted({k for name in results for k in PREDICTED[name.split()[0]]})
    table = {name: {d: line_amplitudes(r, f"{POINT} {d}", orders) for d in "yz"}
             for name, r in results.items()}
    written = []
    for fault, (_, direction) in FIGURE_FAULTS.items():
        rub = f"rub {results[fault].run.speed_rpm:g}"
        fig = faults_figure({fault: results[fault], "rub": results[rub]}, POINT,
                            direction=direction)
        written.append(save_figure(fig, out / f"faults_{fault}.png", dpi=90))
    fig = faults_figure(journal, POINT, direction="y",
                        predicted={"whirl": (whip_order, 1.0), "rub": PREDICTED["rub"]})
    written.append(save_figure(fig, out / "faults_whirl.png", dpi=90))
    whirl_orders = sorted({whip_order, 0.5, *PREDICTED["rub"]})
    for name, r in journal.items():
        table[f"{name} journal"] = {d: line_amplitudes(r, f"{POINT} {d}", whirl_orders)
                                    for d in "yz"}
        results[f"{name} journal"] = r
    if args.json:
        print(json.dumps(table))
        return 0
    print(f"{POINT}, line amplitudes (um) over the window")
    for name, by_direction in table.items():
        run = results[name].run
        rig = " (journal)" if name.endswith("journal") else ""
        what = f"{name.split()[0]}{rig} {run.speed_rpm:.0f} rpm" + (
            f" g0 {run.gap_m * 1e3:.3f} mm" if name.startswith("rub") else "")
        for d, row in by_direction.items():
            print(f"  {what:36s} {d} " + " ".join(f"{k} {v * 1e6:8.3f}" for k, v in row.items()))
    print("wrote " + ", ".join(str(p) for p in written))
    return 0


def _simulated(groups: list[dict], progress: bool) -> list[dict]:
    """Each group of runs (name -> Run) simulated one run after the other, as name ->
    result, under one bar over their simulated seconds."""
    from rubdiag import _progress
    from rubdiag.simulation import simulate

    total = sum(run.duration_s for runs in groups for run in runs.values())
    done, out = 0.0, []
    with _progress.simulated(total, "faults", enabled=progress) as bar:
        for runs in groups:
            out.append({})
            for name, run in runs.items():
                _progress.label(bar, name)
                out[-1][name] = simulate(run, progress=_progress.following(
                    bar, done, run.duration_s))
                done += run.duration_s
    return out
