"""``rubdiag compare A B``: features of two signal files and B - A, channel by channel.

Every channel both files hold is compared (``--column`` chooses): a simulation result's
shaft, blade and casing, a measurement's probes; a channel flat in both (a casing neither
run touched) is left out. Each file is analysed at its own speed
(given, from a tacho, or the vote of its channels' strongest lines), and amplitudes are
labelled with the files' unit (``--unit``; m for simulation results).

``--pair Y,Z`` (``--rotation -1`` when the shaft turns from Z towards Y) adds the probe
pair as one more channel ``Y+iZ``: its full spectrum (forward and reverse amplitude at each
order) and orbit measures in A and in B, each file at its own speed, and B - A
(:func:`rubdiag.cli._signal_files.pair_row`). Both files must hold both channels; a simulation
result, whose channels are y only, is refused.
"""

from __future__ import annotations

from rubdiag.cli._signal_files import (
    ACROSS_SPEED_ORDERS,
    check_across_speed,
    load,
    pair_row,
    pandas_display,
    unit_words,
)


def compare(args) -> int:
    """Run ``rubdiag compare`` (module docstring); 0 on success."""
    from rubdiag.cli._paths import output_file

    check_across_speed(args)
    if args.pair is not None:
        _check_pair_inputs(args)
    if args.out:
        output_file(args.out)
    # a channel that moves in one file only (a casing touched in B alone) is compared
    loaded = {"A": load(args.a, args, keep_flat=True), "B": load(args.b, args, keep_flat=True)}
    ta, tb = loaded["A"][2], loaded["B"][2]
    channels = list(dict.fromkeys(c for c in ta["channel"] if c in set(tb["channel"])))
    if args.column is None:
        channels = [c for c in channels
                    if not all(loaded[k][0][c].std() == 0 for k in ("A", "B"))] or channels
    if not channels:
        raise ValueError(f"{args.a} and {args.b} have no channel in common")
    units = list(dict.fromkeys(unit_words(loaded[k][3]) for k in ("A", "B")))
    unit = " (A) and ".join(units) + (" (B)" if len(units) > 1 else "")
    if args.revs_per_bin is not None:
        return _across_speed(args, channels, ta, tb, unit)
    pair = None if args.pair is None else _pair_rows(args, loaded)   # refused before output
    rows = {}
    for i, channel in enumerate(channels):
        ra = ta.set_index("channel").loc[channel]
        rb = tb.set_index("channel").loc[channel]
        rows[channel] = (ra, rb)
        if i:
            print()
        _print_difference(channel, ra, rb, args, unit)
    if pair is not None:
        print()
        _print_difference(*pair, args, unit)
    if args.out:
        _spectra_figure(args, loaded, rows, unit)
    return 0


def _pair_rows(args, loaded):
    """``(name, A's row, B's row)`` of ``--pair`` (rows as float Series)."""
    import pandas as pd

    found = [pair_row(loaded[k][2], loaded[k][0], loaded[k][1], args, path)
             for k, path in (("A", args.a), ("B", args.b))]
    key = loaded["A"][2].columns[0]                    # "channel"
    name = found[0].pop(key)
    found[1].pop(key)
    return name, pd.Series(found[0], dtype=float), pd.Series(found[1], dtype=float)


def _check_pair_inputs(args) -> None:
    """``--pair`` reads two channels of two signal files at one speed each: refused with
    ``--revs-per-bin`` or a simulation result, before anything is computed."""
    from rubdiag.runs import is_result

    if args.revs_per_bin is not None:
        raise ValueError("--pair works at one speed, not with --revs-per-bin")
    for path in (args.a, args.b):
        if is_result(path):
            raise ValueError(f"--pair reads two channels of a signal file (CSV, NPZ, "
                             f"parquet); {path} is a simulation result, whose channels "
                             "are y only")


def _print_difference(channel, ra, rb, args, unit: str) -> None:
    """A, B and B - A of every feature either has (absent in both: left out)."""
    import pandas as pd

    diff = pd.DataFrame({"A": ra, "B": rb, "B - A": rb - ra})
    diff = diff[~(diff["A"].isna() & diff["B"].isna()) & ~((diff["A"] == 0) & (diff["B"] == 0))]
    print(f"channel {channel!r}: A = {args.a}, B = {args.b} (amplitudes in {unit}, "
          "frequencies in Hz)")
    with pandas_display():
        print(diff.to_string())


def _spectra_figure(args, loaded, rows, unit: str) -> None:
    """Both spectra over orders, one panel per channel, written to ``args.out``."""
    import numpy as np

    from rubdiag._figures import new_figure
    from rubdiag.plotting import order_spectra_figure, save_figure
    from rubdiag.signal import amplitude_spectrum

    fig = new_figure(figsize=(9.0, 4.2 * len(rows)), layout="constrained")
    axes = fig.subplots(len(rows), 1, squeeze=False)
    for ax, (channel, pair) in zip(axes[:, 0], rows.items(), strict=True):
        curves = []
        for label, path, row in zip(("A", "B"), (args.a, args.b), pair, strict=True):
            frame, fs = loaded[label][0], loaded[label][1]
            f, amp = amplitude_spectrum(frame[channel].to_numpy(dtype=np.float64), fs)
            curves.append((f"{label}: {path}", f, amp, row))
        order_spectra_figure(curves, title=f"channel {channel}", ax=ax, unit=unit)
    save_figure(fig, args.out, dpi=120)
    print(f"wrote {args.out}")


def _across_speed(args, channels, ta, tb, unit: str) -> int:
    """Per channel: A's main order amplitudes per bin and B - A at the same speeds (B's
    bins interpolated linearly in rpm) over the speeds both cover; plot them with
    ``--out`` (a row of panels per channel)."""
    import numpy as np
    import pandas as pd

    for i, channel in enumerate(channels):
        a, b = ta[ta.channel == channel], tb[tb.channel == channel]
        lo, hi = max(a.rpm.min(), b.rpm.min()), min(a.rpm.max(), b.rpm.max())
        shared = a[(a.rpm >= lo) & (a.rpm <= hi)]
        if shared.empty:
            raise ValueError(
                f"{args.a} ({a.rpm.min():.0f} to {a.rpm.max():.0f} rpm) and {args.b} "
                f"({b.rpm.min():.0f} to {b.rpm.max():.0f} rpm) share no speed range")
        b = b.sort_values("rpm")
        columns = {("", "rpm"): shared.rpm.to_numpy()}
        for k in ACROSS_SPEED_ORDERS:
            amp_a = shared[f"amp_{k}"].to_numpy()
            columns[(f"amp_{k}", "A")] = amp_a
            columns[(f"amp_{k}", "B - A")] = np.interp(shared.rpm, b.rpm, b[f"amp_{k}"]) - amp_a
        if i:
            print()
        print(f"channel {channel!r}: A = {args.a}, B = {args.b}; bins of "
              f"{args.revs_per_bin} revolutions, B at the speeds of A's bins, {lo:.0f} to "
              f"{hi:.0f} rpm (amplitudes in {unit})")
        with pandas_display():
            print(pd.DataFrame(columns).to_string(index=False))
    if args.out:
        _across_speed_figure(args, channels, ta, tb, unit)
    return 0


def _across_speed_figure(args, channels, ta, tb, unit: str) -> None:
    from rubdiag._figures import new_figure
    from rubdiag.plotting import save_figure

    orders = ACROSS_SPEED_ORDERS[:4]
    fig = new_figure(figsize=(12.0, 2.9 * len(channels) + 0.6), layout="constrained")
    axes = fig.subplots(len(channels), len(orders), sharex=True, squeeze=False)
    for row, channel in zip(axes, channels, strict=True):
        for ax, k in zip(row, orders, strict=True):
            for label, path, table in (("A", args.a, ta), ("B", args.b, tb)):
                rows = table[table.channel == channel]
                ax.plot(rows.rpm, rows[f"amp_{k}"], "o-", ms=3, label=f"{label}: {path}")
            ax.set_title(f"{channel}: {k.replace('p', '.').replace('x', '×')}")
            ax.set_ylim(bottom=0.0, top=1.15 * max(ax.get_ylim()[1], 1e-300))
        row[0].set_ylabel(f"amplitude ({unit})")
    for ax in axes[-1]:
        ax.set_xlabel("speed (rpm)")
    axes[0, 0].legend(fontsize="small")
    fig.suptitle("order amplitudes across speed")
    save_figure(fig, args.out, dpi=120)
    print(f"wrote {args.out}")
