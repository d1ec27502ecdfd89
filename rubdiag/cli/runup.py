"""The ``runup`` command: a run-up and/or coast-down through the critical speeds with rub."""

from __future__ import annotations

import json
import math
import sys
from pathlib import Path

from rubdiag._atomic import write_text
from rubdiag.cli._defaults import FromLibrary
from rubdiag.cli._faults import add_fault_options, run_options
from rubdiag.cli._model import add_model_options, reduction
from rubdiag.cli._paths import add_rig_option
from rubdiag.cli._quiet import add_quiet_option

#: the function whose keywords the order-tracking options stand for
_ORDERS = "rubdiag.runs._runup:runup_orders."


def register(sub) -> None:
    p = sub.add_parser(
        "runup", help="simulate a run-up or coast-down through the criticals, with rub",
        description="Time integration of the rig along a linear speed ramp (a coast-down "
        "when --from-rpm > --to-rpm), from the linear steady state at the start speed. "
        "Writes to --out the result file of each direction (reused when the same run is "
        "already there), the order tracks of the chosen point (CSV), summary.json, and the "
        "figures: Bode and polar plots of the 1x vector with the linear response dashed, "
        "and a waterfall and order map of each direction.")
    p.add_argument("--case", type=int, choices=(1, 2), required=True,
                   help="unbalance pattern: 1 in phase (1st critical, ~1500 rpm), 2 out of "
                   "phase (2nd, ~5700 rpm)")
    p.add_argument("--from-rpm", type=float, required=True, help="start speed (rpm)")
    p.add_argument("--to-rpm", type=float, required=True, help="end speed (rpm)")
    p.add_argument("--rate-rpm-s", type=float, required=True,
                   help="ramp rate (rpm/s, > 0), e.g. 300")
    p.add_argument("--gap-mm", type=float,
                   help="initial blade-casing gap g0 (mm), e.g. 2.3; without it the run has "
                   "no blade-casing contact (faults only)")
    p.add_argument("--both", action="store_true",
                   help="run up (from -> to) and coast down (to -> from), overlaid")
    p.add_argument("--hold-s", type=float, action=FromLibrary,
                   default_of="rubdiag.runs._runup:ramp_run.hold_s",
                   help="time at the start speed before the ramp (s, default {default})")
    p.add_argument("--point", action=FromLibrary, default_of=_ORDERS + "point",
                   help="recorded point whose orders are tracked (default '{default}')")
    p.add_argument("--revs-per-bin", type=int, action=FromLibrary,
                   default_of=_ORDERS + "revs_per_bin",
                   help="revolutions per order-tracking bin (even; default {default})")
    p.add_argument("--dt-s", type=float, action=FromLibrary,
                   default_of="rubdiag.simulation._run:Run.dt_s",
                   help="largest time step (s, default {default})")
    p.add_argument("--mu", type=float,
                   help="friction coefficient (default: the rig's contact law's)")
    add_rig_option(p)
    p.add_argument("--out", type=Path, required=True, help="output folder (created)")
    add_model_options(p)
    add_fault_options(p)
    p.add_argument("--json", action="store_true",
                   help="print the summaries as one JSON list (SI units, speeds in rpm)")
    add_quiet_option(p)
    p.set_defaults(func=_runup)


def _runup(args) -> int:
    import dataclasses

    from rubdiag.cli._paths import load_rig
    from rubdiag.runs import linear_response, ramp_run, runup_orders, runup_summary
    from rubdiag.simulation import SimulationDiverged

    if args.gap_mm is not None and not 0.0 < args.gap_mm <= 100.0:
        raise ValueError(f"--gap-mm = {args.gap_mm:g} is out of range (allowed: > 0 and "
                         "<= 100)")
    if args.revs_per_bin < 2 or args.revs_per_bin % 2:
        raise ValueError(f"--revs-per-bin = {args.revs_per_bin} (allowed: an even number >= 2, "
                         "so that the half orders fall on a bin)")
    rig = load_rig(args.rig)
    options = dict(rig=rig, dt_s=args.dt_s, reduction=reduction(args), hold_s=args.hold_s,
                   **run_options(args))
    if args.gap_mm is None and "faults" not in options:
        raise ValueError("--gap-mm is missing (allowed: a gap for rub, or a fault option such "
                         "as --crack-element or --misalignment-offset-mm for a run without rub)")
    if args.mu is not None:
        if rig.contact is None or args.gap_mm is None:
            raise ValueError("--mu needs a rig with blade-casing contacts")
        options["contact"] = dataclasses.replace(rig.contact, friction_coefficient=args.mu)
    legs = [(args.from_rpm, args.to_rpm)]
    if args.both:
        legs.append((args.to_rpm, args.from_rpm))
    runs = {_name(a, b): ramp_run(args.case, a, b, args.rate_rpm_s, args.gap_mm, **options)
            for a, b in legs}
    args.out.mkdir(parents=True, exist_ok=True)
    tracks, summaries = {}, []
    for name, run in runs.items():
        try:
            result = _simulated(run, args.out / f"{name}.npz", name, not args.quiet)
        except SimulationDiverged as exc:
            raise ValueError(f"{name}: {exc} (partial result in {args.out / name}.npz)") from None
        table = runup_orders(result, args.point, revs_per_bin=args.revs_per_bin)
        _write_csv(table, args.out / f"{name}_orders.csv")
        summary = runup_summary(result, args.point, orders=table)
        tracks[name] = (result, table, summary)
        summaries.append(summary)
        if not args.json:
            print(_line(name, summary))
    write_text(args.out / "summary.json", json.dumps(summaries, indent=2))
    any_run = next(iter(runs.values()))
    lo, hi = sorted((args.from_rpm, args.to_rpm))
    linear = linear_response(any_run, args.point, _rpm_grid(lo, hi))
    figures = _figures(tracks, (_rpm_grid(lo, hi), linear), args)
    if args.json:
        print(json.dumps(summaries))
    else:
        print(f"wrote {args.out}: " + ", ".join(p.name for p in figures))
    return 0


def _name(a: float, b: float) -> str:
    return "runup" if b > a else "coastdown"


def _simulated(run, path: Path, name: str, progress: bool = True):
    """The result of ``run``: read back from ``path`` when a finished result of the same run
    is there (a rerun after a crash or with other figures resumes), else simulated (with a
    progress bar) and saved (atomically)."""
    from rubdiag import _progress
    from rubdiag.simulation import load_result, simulate

    if path.exists():
        try:
            old = load_result(path)
        except (OSError, ValueError):
            old = None
        if old is not None and old.run == run and old.status == 0:
            print(f"{name}: reusing {path}", file=sys.stderr)
            return old
    try:
        with _progress.simulated(run.duration_s, name, enabled=progress) as bar:
            result = simulate(run, progress=_progress.following(bar, 0.0, run.duration_s))
    except Exception as exc:
        partial = getattr(exc, "result", None)
        if partial is not None:
            partial.save(path)
        raise
    result.save(path)
    return result


def _rpm_grid(lo: float, hi: float):
    import numpy as np

    return np.linspace(lo, hi, 401)


def _line(name: str, s: dict) -> str:
    words = {"runup": "run-up", "coastdown": "coast-down"}[name]
    head = (f"{words} {s['from_rpm']:.0f} -> {s['to_rpm']:.0f} rpm at {s['rate_rpm_s']:g} "
            f"rpm/s: peak 1x {s['peak_1x_m'] * 1e3:.3f} mm at {s['peak_rpm']:.0f} rpm; ")
    if s["n_episodes"] == 0:
        return head + f"no contact ({s['wall_s']:.1f} s wall)"
    return head + (f"{s['n_episodes']} contact episodes from {s['first_contact_rpm']:.0f} to "
                   f"{s['last_contact_rpm']:.0f} rpm, peak force "
                   f"{s['max_contact_force_n']:.0f} N ({s['wall_s']:.1f} s wall)")


def _write_csv(table, path: Path) -> None:
    write_text(path, table.to_csv(index=False))


def _figures(tracks: dict, linear, args) -> list[Path]:
    """Bode, polar and rub-order figures of every direction together, and a waterfall and
    order map of each (:mod:`rubdiag.plotting._runup`), written into ``args.out``."""
    import numpy as np

    from rubdiag.assembly import assemble
    from rubdiag.modal import critical_speeds
    from rubdiag.plotting import save_runup_figures
    from rubdiag.signal import rpm_order_map, waterfall

    words = {"runup": "run-up", "coastdown": "coast-down"}
    orders, contact, waterfalls, maps = {}, {}, {}, {}
    for name, (result, table, summary) in tracks.items():
        label = words[name]
        orders[label] = table
        if summary["n_episodes"]:
            contact[label] = (summary["first_contact_rpm"], summary["last_contact_rpm"])
        x, fs = result.displacement(args.point), result.fs
        f, _, rpm, amp = waterfall(x, fs, nperseg=_segment(fs), angle=result.angle_rad)
        waterfalls[label] = (f, rpm, amp)
        maps[label] = rpm_order_map(x, fs, result.angle_rad, revs_per_bin=8, revs_step=2)
    run = next(iter(tracks.values()))[0].run
    lo, hi = sorted((args.from_rpm, args.to_rpm))
    criticals = critical_speeds(assemble(run.rig), n=4) * 30 / math.pi
    criticals = [c for c in np.atleast_1d(criticals) if lo <= c <= hi]
    return save_runup_figures(orders, args.out, linear=linear, critical_rpm=criticals or None,
                              contact_rpm=contact, waterfalls=waterfalls, order_maps=maps)


def _segment(fs: float) -> int:
    """Waterfall segments of about 0.2 s (5 Hz resolution), a power of two."""
    return 1 << max(6, round(math.log2(0.2 * fs)))
