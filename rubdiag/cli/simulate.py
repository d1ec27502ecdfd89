"""The ``simulate`` command: one rub-impact run of a rig."""

from __future__ import annotations

import json
import sys
from pathlib import Path

from rubdiag.cli._defaults import FromLibrary
from rubdiag.cli._faults import add_fault_options, run_options
from rubdiag.cli._model import add_model_options, reduction
from rubdiag.cli._paths import add_rig_option
from rubdiag.cli._quiet import add_quiet_option

#: the Run fields the options stand for
_RUN = "rubdiag.simulation._run:Run."


def register(sub) -> None:
    p = sub.add_parser(
        "simulate", help="simulate blade-casing rub-impact at constant speed",
        description="Time integration of the rig with blade-casing contact, starting from "
        "the linear steady state. Prints headline numbers over the analysis window "
        "[discard, duration] (SI units with --json) and optionally saves the result file.")
    p.add_argument("--case", type=int, choices=(1, 2), required=True,
                   help="unbalance pattern: 1 in phase, 2 out of phase (the study's cases)")
    p.add_argument("--gap-mm", type=float,
                   help="initial blade-casing gap g0 (mm), e.g. 2.3 (light) or 1.9 (serious); "
                   "without it the run has no blade-casing contact (faults only)")
    p.add_argument("--speed-rpm", type=float,
                   help="speed (rpm); default the rig's 1st (case 1) or 2nd (case 2) forward "
                   "critical speed")
    p.add_argument("--duration-s", type=float, action=FromLibrary, default_of=_RUN + "duration_s",
                   help="total simulated time (s, default {default})")
    p.add_argument("--discard-s", type=float, action=FromLibrary, default_of=_RUN + "discard_s",
                   help="start left out of the statistics (s, default {default})")
    p.add_argument("--dt-s", type=float, action=FromLibrary, default_of=_RUN + "dt_s",
                   help="base time step (s, default {default}; halved down to dt/64 as "
                   "needed)")
    p.add_argument("--step-error", type=float, action=FromLibrary,
                   shows={"datasets": "rubdiag.dataset._design:DEFAULT_STEP_ERROR"},
                   help="take steps up to 4 dt where nothing is in contact, with this local "
                   "error tolerance relative to the largest displacement (datasets: "
                   "{datasets}; default: none, every step <= dt)")
    p.add_argument("--output-rate-hz", type=float,
                   help="waveform sampling rate (Hz, default 10000; 1/dt divided by an "
                   "integer); contact events are logged at every step whatever the rate")
    p.add_argument("--mu", type=float,
                   help="friction coefficient (default: the rig's contact law's)")
    add_rig_option(p)
    p.add_argument("--out", type=Path, metavar="FILE.npz",
                   help="save the result to this file (.npz is added to a name without it); "
                        "its folder must exist")
    add_model_options(p)
    add_fault_options(p)
    p.add_argument("--json", action="store_true", help="print one JSON object (SI units)")
    add_quiet_option(p)
    p.set_defaults(func=_simulate)


def _simulate(args) -> int:
    import dataclasses

    from rubdiag import _progress
    from rubdiag.cli._paths import load_rig, output_file
    from rubdiag.simulation import Run, SimulationDiverged, response_points, simulate

    out = None
    if args.out is not None:   # before any work: a long run must not end in "no such folder"
        output_file(args.out)           # a folder is refused, not written beside
        out = output_file(args.out if args.out.suffix == ".npz"
                          else args.out.with_name(f"{args.out.name}.npz"))
    if args.gap_mm is not None and not 0.0 < args.gap_mm <= 100.0:
        raise ValueError(f"--gap-mm = {args.gap_mm:g} is out of range (allowed: > 0 and "
                         "<= 100)")
    model = reduction(args)
    rig = load_rig(args.rig)
    options = dict(duration_s=args.duration_s, discard_s=args.discard_s, dt_s=args.dt_s,
                   output_rate_hz=args.output_rate_hz, reduction=model,
                   step_error=args.step_error, **run_options(args))
    if args.gap_mm is None and "faults" not in options:
        raise ValueError("--gap-mm is missing (allowed: a gap for rub, or a fault option such "
                         "as --crack-element or --misalignment-offset-mm for a run without rub)")
    if args.mu is not None:
        if rig.contact is None or args.gap_mm is None:
            raise ValueError("--mu needs a rig with blade-casing contacts")
        options["contact"] = dataclasses.replace(rig.contact, friction_coefficient=args.mu)
    run = Run.paper_case(args.case, args.gap_mm, speed_rpm=args.speed_rpm, rig=rig, **options)
    _check_output_size(run, len(response_points(rig)))
    try:
        with _progress.simulated(run.duration_s, f"case {args.case}",
                                 enabled=not args.quiet) as bar:
            result = simulate(run, progress=_progress.following(bar, 0.0, run.duration_s))
    except SimulationDiverged as exc:
        if out is not None:
            path = exc.result.save(out)
            print(f"partial result saved to {path}", file=sys.stderr)
        raise ValueError(str(exc)) from None
    if out is not None:
        result.save(out)
    summary = result.summary()
    if args.json:
        print(json.dumps(summary))
        return 0
    w0, w1 = summary["window_s"]
    print(f"{run.label} at {run.speed_rpm:.0f} rpm: {summary['message']} "
          f"({summary['wall_s']:.1f} s wall)")
    if model is not None:
        print(f"model: reduced (Craig-Bampton, modes below {model.cutoff_hz:g} Hz)")
    if run.faults is not None:
        print(f"faults: {', '.join(run.faults.names)}")
    if run.contact_law is not None:
        print(f"window {w0:g}-{w1:g} s: contact-1 max force "
              f"{summary['contact1_max_force_n']:.1f} N, all elements "
              f"{summary['max_contact_force_n']:.1f} N")
        print(f"contact 1 entries: sliding {summary['contact1_sliding_entries']}, sticking "
              f"{summary['contact1_sticking_entries']}")
    else:
        print(f"window {w0:g}-{w1:g} s: no blade-casing contact")
    if "casing_max_y_m" in summary:
        print(f"casing max y {summary['casing_max_y_m'] * 1e6:.1f} um, shaft max y "
              f"{summary['shaft_max_y_m'] * 1e3:.3f} mm")
    if out is not None:
        print(f"saved {out}")
    return 0


#: Most recorded values (samples x channels) a run may hold: simulate_system's own limit,
#: checked here too so that the advice names the command's options.
MAX_OUTPUT_VALUES = 5e8


def _check_output_size(run, n_channels: int) -> None:
    n_samples = int(run.duration_s / run.output_dt_s) + 1
    if n_samples * max(n_channels, 1) > MAX_OUTPUT_VALUES:
        raise ValueError(
            f"--duration-s {run.duration_s:g} at --output-rate-hz {run.output_rate_hz:g} gives "
            f"{n_samples} samples x {n_channels} channels, too large an output (at most "
            f"{MAX_OUTPUT_VALUES:g} values): lower --output-rate-hz or shorten --duration-s")
