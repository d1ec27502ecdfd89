"""``rubdiag features`` and ``rubdiag compare``: spectral rub features of measured signals."""

from __future__ import annotations

import argparse
import json
import math
import sys

from rubdiag.cli._defaults import FromLibrary
from rubdiag.cli._signal_files import (
    ACROSS_SPEED_ORDERS,
    channels_and_features,
    check_across_speed,
    pair_row,
    pandas_display,
    unit_of,
    unit_words,
)

_INPUT_HELP = (
    "signal file: .csv/.txt (header row, one column per channel), .npz (one 1-D array per "
    "channel, optional scalar 'fs') or .parquet; a column t/time/time_s (seconds) gives fs; "
    "or a simulation result (.npz from `rubdiag simulate --out`): `features` gives one row "
    "for the run (shaft_/blade_/casing_ spectra over the analysis window and contact "
    "statistics), `compare` compares its shaft, blade and casing channels"
)


def register(subparsers) -> None:
    """Add the ``features`` and ``compare`` commands."""
    p = subparsers.add_parser(
        "features",
        help="spectral rub-impact features of a signal file, one row per channel",
        description=(
            "Order lines (0.5x ... 8x, peak amplitude in the signal's unit: --unit, m for a "
            "simulation result; frequency in Hz, phase in degrees), 1/3-order lines, "
            "sidebands n x +/- delta (Hz), broadband RMS around n x and the strongest "
            "combination pair fa + fb = m x. Absent lines have amplitude 0 and NaN "
            "frequency; features above Nyquist are NaN. Without --speed-rpm or a tacho the "
            "channels' strongest lines vote on the speed (a noise-only channel does not "
            "spoil it). Prints a summary in words per channel (per run for a simulation "
            "result), then every feature; --csv and --json write the features only. With "
            "--revs-per-bin N: "
            "features across speed, one row per bin of N revolutions in the angle domain "
            "(from --tacho or --angle) with its mean rpm; frequencies then in orders, phases "
            "against the shaft angle."
        ),
    )
    p.add_argument("input", metavar="INPUT", help=_INPUT_HELP)
    _common(p)
    _pair_options(p, "adds their full spectrum (forward and reverse amplitude at each "
                     "order) and orbit measures as a row 'Y+iZ'")
    out = p.add_mutually_exclusive_group()
    out.add_argument(
        "--json", action="store_true", help="print a JSON list, one object per channel"
    )
    out.add_argument("--csv", metavar="FILE", help="write the table to a CSV file")
    out.add_argument(
        "--summary", action="store_true",
        help="print only the summary in words, not the table of every feature after it",
    )
    p.set_defaults(func=_features)

    p = subparsers.add_parser(
        "compare",
        help="compare the spectra and features of two signal files (B - A)",
        description=(
            "For every channel A and B share (--column to choose): print the features of A "
            "and B and their difference B - A (amplitudes in the signals' unit: --unit, m "
            "for simulation results; frequencies in Hz), and with --out plot both amplitude "
            "spectra over orders of the running speed (log scale, one panel per channel) "
            "with the detected features marked. Each file's speed is its own (--speed-rpm, "
            "a tacho, or the vote of its channels' strongest lines). With --revs-per-bin N: "
            "compare across speed: the main order amplitudes of A's bins and B - A at the "
            "same speeds (B interpolated in rpm), over the speeds both cover; --out plots "
            "them against rpm."
        ),
    )
    p.add_argument("a", metavar="A", help="reference signal file (" + _INPUT_HELP + ")")
    p.add_argument("b", metavar="B", help="signal file compared with A (same formats)")
    _common(p)
    p.add_argument("--out", metavar="FIG.png",
                   help="write the spectra figure (with --revs-per-bin: amplitudes against "
                        "rpm) to this file")
    _pair_options(p, "compares their full spectrum (forward and reverse amplitude at each "
                     "order) and orbit measures in A and B, as a channel 'Y+iZ'")
    p.set_defaults(func=_compare)


def _pair_options(p: argparse.ArgumentParser, what: str) -> None:
    p.add_argument(
        "--pair", metavar="Y,Z",
        help=f"two channels of orthogonal probes in one plane: {what} (the shaft turning "
             "from Y towards Z; --rotation -1 for the other way)")
    p.add_argument("--rotation", type=int, metavar="SIGN", action=FromLibrary,
                   default_of="rubdiag.signal._fullspectrum:orbit_features.rotation",
                   choices_of="rubdiag.signal._fullspectrum:ROTATIONS",
                   help="with --pair, one of {choices}: 1 when the shaft turns from Y towards "
                   "Z, -1 the other way (default {default})")


def _compare(args) -> int:
    from rubdiag.cli.compare import compare

    return compare(args)


def _common(p: argparse.ArgumentParser) -> None:
    p.add_argument("--fs", type=float, metavar="HZ", help="sampling frequency in Hz")
    p.add_argument(
        "--speed-rpm",
        type=float,
        metavar="N",
        help="running speed in rpm (default: from the tacho channel, else the vote of the "
             "channels' strongest lines)",
    )
    p.add_argument(
        "--unit", metavar="UNIT",
        help="unit of the file's values, named in the output (default: m for a simulation "
             "result, else 'signal unit')",
    )
    p.add_argument(
        "--column", metavar="NAME", action="append", help="channel to analyse (repeatable)"
    )
    p.add_argument(
        "--tacho",
        metavar="NAME",
        help="once-per-revolution pulse channel giving the speed (default: a column 'tacho'); "
             "with --revs-per-bin the shaft angle",
    )
    p.add_argument(
        "--angle", metavar="NAME",
        help="channel holding the shaft angle in rad, instead of a tacho (with --revs-per-bin)",
    )
    p.add_argument(
        "--revs-per-bin", type=int, metavar="N",
        help="features across speed: one row per bin of N whole revolutions (at least 10) and "
             "channel, with its mean rpm; the angle from --tacho or --angle (a simulation "
             "result: its shaft angle)",
    )


def _features(args) -> int:
    from rubdiag.cli._paths import load_result, output_file
    from rubdiag.runs import is_result, run_features

    check_across_speed(args)
    unit = unit_of(args.input, args)
    if args.csv:
        output_file(args.csv, "--csv")
    if args.pair is not None and is_result(args.input):
        raise ValueError("--pair reads two channels of a signal file (CSV, NPZ, parquet); a "
                         "simulation result's channels are y only (allowed: a file of "
                         "measured or exported y and z channels)")
    if is_result(args.input) and args.revs_per_bin is None:
        # a simulation result: one row for the run, as rubdiag.run_features(result) gives it
        # (shaft_/blade_/casing_ spectra and the contact statistics)
        table = run_features(load_result(args.input))
        table.insert(0, "source", [args.input])
    else:
        frame, fs, table = channels_and_features(args.input, args, keep_flat=args.pair is not None)
        if args.pair is not None:
            table = _with_pair(table, frame, fs, args)
    if args.json:
        rows = [
            {k: (None if isinstance(v, float) and math.isnan(v) else v) for k, v in row.items()}
            for row in table.to_dict(orient="records")
        ]
        json.dump(rows, sys.stdout, indent=1, default=_plain)
        print()
    elif args.csv:
        table.to_csv(args.csv, index=False)
        print(f"wrote {len(table)} row(s) to {args.csv}")
    elif args.revs_per_bin is not None:
        print("\n".join(across_speed_lines(table, args.revs_per_bin, args.summary, unit)))
    else:
        print("\n".join(summary_lines(table)))
        if not args.summary:
            what = "run" if "source" in table.columns else "channel"
            print(f"\nall {table.shape[1] - 1} features per {what} (amplitudes in "
                  f"{unit_words(unit)}, frequencies in Hz, phases in degrees; absent line: "
                  "amplitude 0; NaN: not measurable):")
            with pandas_display():
                print(table.set_index(table.columns[0]).T.to_string())   # channel or source
    return 0


def _with_pair(table, frame, fs, args):
    """``table`` with the row of ``--pair Y,Z`` (its speed the pair's channels' own)."""
    import pandas as pd

    row = pair_row(table, frame, fs, args, args.input)
    return pd.concat([table, pd.DataFrame([row])], ignore_index=True)



def across_speed_lines(table, revs_per_bin: int, summary_only: bool = False,
                       unit: str | None = None) -> list[str]:
    """Per channel of a table across speed: one line (bins, speeds, 1× range), then the
    main order amplitudes bin by bin unless ``summary_only``; ``unit`` of the amplitudes
    (None: unknown)."""
    from rubdiag.signal import REVOLUTION_FEATURE_NAMES

    lines = []
    shown = ["rev_start", "t_s", "rpm", "rms", *(f"amp_{k}" for k in ACROSS_SPEED_ORDERS),
             "n_half_orders", "n_third_orders"]
    for channel, rows in table.groupby("channel", sort=False):
        lines.append(f"{channel}: {len(rows)} bins of {revs_per_bin} revolutions, "
                     f"{rows.rpm.min():.0f} to {rows.rpm.max():.0f} rpm, 1× "
                     f"{rows.amp_1x.min():.4g} to {rows.amp_1x.max():.4g}")
        if not summary_only:
            with pandas_display():
                lines.extend(rows[["bin", *shown]].to_string(index=False).splitlines())
            lines.append("")
    if not summary_only:
        lines.append(f"all {len(REVOLUTION_FEATURE_NAMES)} features per bin with --csv or --json "
                     f"(amplitudes in {unit_words(unit)}, frequencies in orders, phases in "
                     "degrees against the shaft angle)")
    return lines


def summary_lines(table) -> list[str]:
    """A few lines per row of a feature table, in words: the rub signatures found
    (:func:`rubdiag.paper._describe.describe_spectrum`), the 1× line and the RMS; for a
    simulation result also its contact statistics."""
    from rubdiag.paper import describe_spectrum

    lines = []
    for row in table.to_dict(orient="records"):
        if _is_pair(row):                             # --pair Y,Z
            lines.extend(pair_summary_lines(row))
            continue
        if "source" not in row:                       # a measured channel
            one = _amplitude(row, "")
            if one != "absent":
                one += f" at {row['freq_1x_hz']:.2f} Hz"
            lines.append(f"{row['channel']}: {row['speed_rpm']:.0f} rpm, RMS {row['rms']:.4g}, "
                         f"1× {one}")
            lines.append(f"  {describe_spectrum(row, prefixes=('',))}")
            continue
        reduced = ", reduced model" if row.get("model") == "reduced" else ""
        lines.append(f"{row['source']}: {row['label'] or 'run'}{reduced}, "
                     f"{row['speed_rpm']:.0f} rpm, {row['window_s']:.3g} s analysed, "
                     f"dt = {row['dt_s']:g} s")
        signals = [(p, name) for p, name in (("shaft", "shaft"), ("blade", "blade tip"),
                                             ("casing", "casing")) if f"{p}_rms" in row]
        lines.append("  1× (RMS): " + ", ".join(
            f"{name} {_amplitude(row, p, 1e6, ' um')} ({row[f'{p}_rms'] * 1e6:.4g} um)"
            for p, name in signals))
        rotor = [(p, name) for p, name in signals if p != "casing"]
        if rotor:   # as Table 2 describes a run: the lines of shaft and blade together
            lines.append(f"  {' and '.join(name for _, name in rotor)}: "
                         f"{describe_spectrum(row, prefixes=tuple(p for p, _ in rotor))}")
        if ("casing", "casing") in signals:
            lines.append(f"  casing: {describe_spectrum(row, prefixes=('casing',))}")
        if "contact1_max_force_n" in row:
            lines.append(
                f"  contact 1: max force {row['contact1_max_force_n']:.1f} N, min "
                f"{row['contact1_min_force_n']:.1f} N; entries sliding "
                f"{row['contact1_sliding_entries']:.0f} / sticking "
                f"{row['contact1_sticking_entries']:.0f}; sticking share "
                f"{row['contact1_sticking_share']:.2f}")
        if "contacts_max_force_n" in row:
            lines.append(f"  all contacts: max force {row['contacts_max_force_n']:.1f} N, "
                         f"{row['contacts_n_episodes']:.0f} episodes")
    return lines


#: A probe pair's line is named in its summary when it stands this many times above the
#: median of the pair's forward and reverse amplitudes (most orders hold no line: their
#: median is the record's floor).
PAIR_LINE_OVER_FLOOR = 10.0


def _is_pair(row) -> bool:
    value = row.get("forward_1x")
    return value is not None and not math.isnan(value)


def pair_summary_lines(row) -> list[str]:
    """The summary in words of a probe pair's row (``--pair Y,Z``): its 1× forward and
    reverse amplitudes and precession, then the other lines standing
    :data:`PAIR_LINE_OVER_FLOOR` times above the pair's floor, strongest first."""
    amplitudes = {key: row[key] for key in row
                  if key.startswith(("fwd_", "rev_")) and math.isfinite(row[key])}
    floor = sorted(amplitudes.values())[len(amplitudes) // 2] if amplitudes else 0.0
    others = sorted(((value, key) for key, value in amplitudes.items()
                     if value > PAIR_LINE_OVER_FLOOR * floor and key[4:] != "1x"), reverse=True)
    turning = "forward" if row["precession_1x"] > 0 else "reverse"
    named = [f"{'forward' if key.startswith('fwd') else 'reverse'} "
             f"{key[4:].replace('p', '.').replace('x', '×')} {value:.4g}"
             for value, key in others]
    detail = "; ".join(named) if named else "no other significant line"
    if named and math.isfinite(row.get("reverse_share", math.nan)):
        detail += f"; reverse share of the other lines {row['reverse_share']:.2f}"
    return [f"{row['channel']}: {row['speed_rpm']:.0f} rpm, 1× forward "
            f"{row['forward_1x']:.4g}, reverse {row['reverse_1x']:.4g} ({turning} precession)",
            f"  {detail}"]


def _amplitude(row, prefix: str, scale: float = 1.0, unit: str = "") -> str:
    key = f"{prefix}_amp_1x" if prefix else "amp_1x"
    return f"{row[key] * scale:.4g}{unit}" if row.get(key, 0) > 0 else "absent"


def _plain(value):
    try:
        return value.item()
    except AttributeError:
        return str(value)
