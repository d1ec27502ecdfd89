"""Commands of the linear analysis: ``modal``, ``campbell``, ``unbalance``, ``calibrate``."""

from __future__ import annotations

import json
import sys
from pathlib import Path

from rubdiag.cli._defaults import FromLibrary
from rubdiag.cli._paths import add_rig_option
from rubdiag.cli._quiet import add_quiet_option

RPM = 3.141592653589793 / 30.0   # rad/s per rpm
#: relative miss of a target critical speed from which calibrate warns: far above the fit's
#: tolerance (1e-6), so only a fit that could not reach its targets
_MISSED = 1e-3


def register(sub) -> None:
    p = sub.add_parser("modal", help="critical speeds, natural frequencies, Rayleigh damping",
                       description="Print the forward critical speeds (rpm), the natural "
                       "frequencies at rest (Hz), Rayleigh alpha (1/s) and beta (s) and the "
                       "number of DOFs of a rig. On journal bearings: the critical speed map's "
                       "speeds, the natural frequencies at the first of them and the threshold "
                       "of instability.")
    add_rig_option(p)
    p.add_argument("--n-modes", type=int, default=8,
                   help="natural frequencies to list (default 8)")
    p.add_argument("--json", action="store_true", help="print one JSON object (SI units)")
    p.set_defaults(func=_modal)

    p = sub.add_parser("campbell", help="Campbell diagram (PNG and CSV)",
                       description="Write campbell.png and campbell.csv: damped natural "
                       "frequencies (Hz) and whirl of the lowest modes against speed (rpm).")
    add_rig_option(p)
    p.add_argument("--max-speed-rpm", type=float, default=8000.0,
                   help="highest speed (rpm, default 8000)")
    p.add_argument("--n-speeds", type=int, default=41, help="speeds (default 41)")
    p.add_argument("--n-modes", type=int, action=FromLibrary,
                   default_of="rubdiag.modal._campbell:campbell.n_modes",
                   help="modes per speed (default {default})")
    p.add_argument("--out", type=Path, default=Path("out"), help="output folder (default out)")
    add_quiet_option(p)
    p.set_defaults(func=_campbell)

    p = sub.add_parser("unbalance", help="linear unbalance response (the study's Figs. 5-6)",
                       description="Write unbalance_caseN.png/.csv: amplitude (mm) of shaft "
                       "node 11 in y against speed (rpm) for the study's case 1 (unbalances "
                       "in phase) or case 2 (out of phase), and deflection_caseN.png: the "
                       "deflected shaft at the first (case 1) or second (case 2) critical "
                       "speed.")
    p.add_argument("--case", type=int, choices=(1, 2), required=True, help="loading case")
    add_rig_option(p)
    p.add_argument("--max-speed-rpm", type=float, default=8000.0,
                   help="highest speed (rpm, default 8000)")
    p.add_argument("--n-speeds", type=int, default=400, help="speeds (default 400)")
    p.add_argument("--out", type=Path, default=Path("out"), help="output folder (default out)")
    p.set_defaults(func=_unbalance)

    p = sub.add_parser("calibrate", help="fit geometry to target critical speeds",
                       description="Scale geometry knobs of a rig so that its first forward "
                       "critical speeds hit the targets (rpm); write the calibrated rig TOML.")
    add_rig_option(p)
    p.add_argument("--targets-rpm", type=float, nargs="+", default=[1500.0, 5700.0],
                   help="target forward critical speeds (rpm, default 1500 5700)")
    p.add_argument("--knobs", nargs="+", metavar="KNOB", action=FromLibrary,
                   default_of="rubdiag.modal._calibrate:calibrate.knobs",
                   shows={"knobs": "rubdiag.modal:KNOBS"},
                   help="geometry knobs to scale: {knobs} (default {default})")
    p.add_argument("--out", type=Path, default=Path("calibrated_rig.toml"),
                   help="rig TOML to write (default calibrated_rig.toml)")
    p.set_defaults(func=_calibrate)


def _rig(path):
    from rubdiag.cli._paths import load_rig

    return load_rig(path)


def _positive(name: str, value):
    from rubdiag import _check

    return _check.positive(name, value)


def _modal(args) -> int:
    import numpy as np

    from rubdiag.assembly import assemble
    from rubdiag.modal import critical_speeds, modes, stability_threshold, with_rayleigh

    _positive("--n-modes", args.n_modes)
    model = with_rayleigh(assemble(_rig(args.rig)))
    crit = critical_speeds(model, n=4)
    films = len(model.journal_bearings)
    # a film has no stiffness at rest: a rig on journal bearings is shown at its first
    # critical speed, and its threshold of instability is searched up to 4x the last one
    speed = float(crit[0]) if films else 0.0
    natural = modes(model, speed, n_modes=args.n_modes, damped=False)
    threshold = (stability_threshold(model, 0.05 * crit[0], 4.0 * crit[-1]) if films
                 else None)
    alpha, beta = model.rayleigh
    f_hz = natural.damped_frequencies / (2 * np.pi)
    if args.json:
        out = {
            "rig": model.rig.name,
            "critical_speeds_rpm": [float(c / RPM) for c in crit],
            "critical_speeds_rad_s": [float(c) for c in crit],
            "rayleigh_alpha": float(alpha),
            "rayleigh_beta": float(beta),
            "n_dof": model.n_dof,
            "journal_bearings": films,
        }
        if not films:
            out["natural_frequencies_at_rest_hz"] = [float(f) for f in f_hz]
        else:
            out["natural_frequencies_hz"] = [float(f) for f in f_hz]
            out["natural_frequencies_at_rpm"] = speed / RPM
            out["stability_threshold_rpm"] = (None if threshold is None
                                              else threshold.speed_rad_s / RPM)
            out["whirl_ratio_at_threshold"] = (None if threshold is None
                                               else threshold.whirl_ratio)
        print(json.dumps(out))
        return 0
    print(f"rig: {model.rig.name}")
    print(f"DOFs: {model.n_dof}")
    if films:
        print(f"bearings: {films} plain journal bearing(s), speed-dependent and cross-coupled; "
              "critical speeds of the undamped critical speed map (the films' direct "
              "stiffness at each critical speed)")
    print("forward critical speeds (rpm): " + ", ".join(f"{c / RPM:.1f}" for c in crit))
    where = f"at {speed / RPM:.1f} rpm" if films else "at rest"
    print(f"natural frequencies {where} (Hz): " + ", ".join(f"{f:.2f}" for f in f_hz))
    print(f"Rayleigh damping: alpha = {alpha:.4f} 1/s, beta = {beta:.4e} s")
    if films:
        if threshold is None:
            print(f"threshold of instability: none up to {4.0 * crit[-1] / RPM:.0f} rpm")
        else:
            print(f"threshold of instability: {threshold.speed_rad_s / RPM:.1f} rpm, whirl at "
                  f"{threshold.frequency_rad_s / (2 * np.pi):.2f} Hz "
                  f"({threshold.whirl_ratio:.3f} x)")
    return 0


def _campbell(args) -> int:
    import numpy as np

    from rubdiag.assembly import assemble
    from rubdiag.cli._paths import output_folder
    from rubdiag.modal import campbell
    from rubdiag.plotting import campbell_figure, save_figure

    _positive("--max-speed-rpm", args.max_speed_rpm)
    _positive("--n-speeds", args.n_speeds)
    _positive("--n-modes", args.n_modes)
    model = assemble(_rig(args.rig))
    output_folder(args.out)
    top = args.max_speed_rpm * RPM
    # a journal bearing's film has no stiffness at rest: its diagram starts above 0
    low = top / args.n_speeds if model.journal_bearings else 0.0
    result = campbell(model, np.linspace(low, top, args.n_speeds), n_modes=args.n_modes,
                      progress=not args.quiet)
    result.to_frame().to_csv(args.out / "campbell.csv", index=False)
    films = (", journal bearings: coefficients at each speed" if model.journal_bearings
             else "")
    save_figure(campbell_figure(result, title=f"Campbell diagram: {model.rig.name}{films}"),
                args.out / "campbell.png", dpi=150)
    if films:
        print(f"{len(model.journal_bearings)} plain journal bearing(s): the films' speed-"
              "dependent, cross-coupled coefficients at each speed; the diagram starts at "
              f"{low / RPM:.0f} rpm (a film has no stiffness at rest)", file=sys.stderr)
    print(f"wrote {args.out / 'campbell.png'} and {args.out / 'campbell.csv'}", file=sys.stderr)
    return 0


def _unbalance(args) -> int:
    import numpy as np

    from rubdiag.assembly import assemble
    from rubdiag.cli._paths import output_folder
    from rubdiag.modal import critical_speeds, harmonic_response, unbalance_response
    from rubdiag.plotting import deflection_figure, save_figure, unbalance_figure

    _positive("--max-speed-rpm", args.max_speed_rpm)
    _positive("--n-speeds", args.n_speeds)
    rig = _rig(args.rig)
    output_folder(args.out)
    model = assemble(rig)
    unbalance = rig.unbalance(args.case)
    speeds = np.linspace(args.max_speed_rpm * RPM / args.n_speeds, args.max_speed_rpm * RPM,
                         args.n_speeds)
    response = unbalance_response(model, speeds, unbalance, points=((11, "y"),))
    crit = critical_speeds(model, n=2)
    stem = f"case{args.case}"
    response.to_frame().to_csv(args.out / f"unbalance_{stem}.csv", index=False)
    save_figure(unbalance_figure({f"case {args.case}": response}, critical_rpm=crit / RPM,
                                 title="Unbalance response of disc 1 (node 11, y), case "
                                       f"{args.case}"),
                args.out / f"unbalance_{stem}.png", dpi=150)
    speed = crit[min(args.case, len(crit)) - 1]
    shape = harmonic_response(model, speed, unbalance)
    save_figure(deflection_figure(model, {f"case {args.case} at {speed / RPM:.0f} rpm": shape},
                                  title=f"Deflected shaft at {speed / RPM:.0f} rpm, case "
                                        f"{args.case}"),
                args.out / f"deflection_{stem}.png", dpi=150)
    peak = response.peak_speed() / RPM
    print(f"case {args.case}: peak at {peak:.0f} rpm, disc 1 amplitude at "
          f"{speed / RPM:.0f} rpm = {abs(shape.amplitude(11, 'y')) * 1e3:.3f} mm (y); wrote "
          f"{args.out}/unbalance_{stem}.png, .csv and deflection_{stem}.png", file=sys.stderr)
    return 0


def _calibrate(args) -> int:
    import math

    from rubdiag.cli._paths import output_file
    from rubdiag.modal import calibrate
    from rubdiag.model import save_rig

    targets = args.targets_rpm
    for t in targets:
        if not (t > 0 and math.isfinite(t)):
            raise ValueError(f"--targets-rpm {t:g} is out of range (allowed: finite, > 0)")
    if targets != sorted(set(targets)):   # strictly ascending
        raise ValueError(f"--targets-rpm {' '.join(f'{t:g}' for t in targets)} must be "
                         "strictly ascending (rpm)")
    output_file(args.out)
    result = calibrate(_rig(args.rig), [t * RPM for t in args.targets_rpm], knobs=args.knobs)
    save_rig(result.rig, args.out)
    for name, scale in zip(result.knobs, result.scales, strict=True):
        print(f"{name}: x {scale:.6f}", file=sys.stderr)
    reached = ", ".join(f"{s / RPM:.2f}" for s in result.speeds)
    print(f"critical speeds (rpm): {reached}; wrote {args.out}", file=sys.stderr)
    worst = max(abs(e) for e in result.relative_errors)
    if worst > _MISSED:
        print(f"warning: targets missed by up to {worst:.2%} (add knobs or widen them)",
              file=sys.stderr)
    return 0
