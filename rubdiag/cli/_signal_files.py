"""What ``rubdiag features`` and ``rubdiag compare`` share: reading a signal file (or a
simulation result) into channels, its sampling rate, feature table and unit; the probe pair's
row of ``--pair``; the options of features across speed."""

from __future__ import annotations

import contextlib
import warnings

#: The unit of a simulation result's responses.
RESULT_UNIT = "m"


def unit_of(path, args) -> str | None:
    """The unit of a file's values: ``--unit``; m for a simulation result; a dataset's stored
    waveforms' own unit when all the analysed channels (``--column``, else all) share one;
    else None (unknown). ``--unit`` other than the file's own is refused (one line)."""
    from rubdiag.runs import is_result
    from rubdiag.signal._io import stored_units

    if args.unit is not None and not args.unit.strip():
        raise ValueError(f"--unit {args.unit!r} names no unit (allowed: the unit of the "
                         "file's values, e.g. um)")
    if is_result(path):
        own, what = RESULT_UNIT, "a simulation result"
    else:
        stored = stored_units(path)
        units = {stored[c] for c in getattr(args, "column", None) or stored if c in stored}
        if len(units) > 1 and args.unit is not None:     # no one unit names them all
            raise ValueError(f"--unit {args.unit}: {path} is a dataset's stored waveforms, "
                             f"in {' and '.join(sorted(units))} (allowed: --column to choose "
                             "channels of one unit, or leave --unit out)")
        if len(units) != 1:
            return args.unit
        own, what = units.pop(), "a dataset's stored waveforms"
    if args.unit not in (None, own):
        raise ValueError(f"--unit {args.unit}: {path} is {what}, in {own} (allowed: "
                         f"--unit {own}, or leave it out)")
    return own


def unit_words(unit: str | None) -> str:
    """What amplitudes are in, for a heading: the unit, or "the signal's unit"."""
    return "the signal's unit" if unit is None else unit


def load(path, args, keep_flat: bool = False):
    """Channels (DataFrame), fs (Hz), the feature table (with ``--revs-per-bin``: the
    table across speed, :func:`rubdiag.signal.revolution_features`) and the unit
    (:func:`unit_of`) of one signal file (``keep_flat``: :func:`channels_and_features`)."""
    unit = unit_of(path, args)      # a wrong --unit is refused before any analysis
    frame, fs, table = channels_and_features(path, args, keep_flat)
    return frame, fs, table, unit


def channels_and_features(path, args, keep_flat: bool = False):
    """Channels (DataFrame), fs (Hz) and the feature table of one signal file. A result's
    channel that does not move (a casing never touched) is left out unless ``keep_flat``
    or ``--column`` names it."""
    from rubdiag.runs import is_result, run_signals
    from rubdiag.signal import read_signals, revolution_features, signal_features

    speed, angle = args.speed_rpm, args.angle
    if is_result(path):
        # a simulation result: its shaft, blade and casing responses over the analysis
        # window, at the run's speed unless --speed-rpm says otherwise
        import pandas as pd

        from rubdiag.cli._paths import load_result

        result = load_result(path)
        frame, fs = pd.DataFrame(run_signals(result)), result.fs
        if args.column is None and not keep_flat:   # a casing never touched: skip it
            frame = frame.loc[:, frame.std() > 0]
        speed = result.run.speed_rpm if speed is None else speed
        if args.revs_per_bin is not None and args.tacho is None and angle is None:
            angle = result.angle_rad[result.window]       # the run's exact shaft angle
    else:
        frame, fs = read_signals(path, args.fs)
    if args.revs_per_bin is not None:
        table = revolution_features(frame, fs, angle, tacho=args.tacho,
                                       revs_per_bin=args.revs_per_bin, columns=args.column)
    else:
        with _named(path):
            table = signal_features(frame, fs, speed, tacho=args.tacho, columns=args.column)
    return frame, fs, table


@contextlib.contextmanager
def _named(path):
    """A guessed speed's refusal and ambiguity warning name the file ``path`` (``compare``
    reads two)."""
    from rubdiag.signal import SpeedAmbiguous, SpeedNotFound

    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        try:
            yield
        except SpeedNotFound as exc:
            raise SpeedNotFound(f"{path}: {exc}") from None
    for w in caught:
        named = issubclass(w.category, SpeedAmbiguous)
        warnings.warn_explicit(f"{path}: {w.message}" if named else w.message, w.category,
                               w.filename, w.lineno)


def check_across_speed(args) -> None:
    """The options of features across speed go together (one line each when not)."""
    if args.revs_per_bin is None:
        if args.angle is not None:
            raise ValueError("--angle gives the shaft angle for --revs-per-bin: give "
                             "--revs-per-bin N too")
        return
    if args.speed_rpm is not None:
        raise ValueError("--revs-per-bin takes the speed from the shaft angle (--tacho or "
                         "--angle), not --speed-rpm")
    if args.tacho is not None and args.angle is not None:
        raise ValueError("give --tacho or --angle, not both")


def pair_row(table, frame, fs, args, path) -> dict:
    """The feature row of ``--pair Y,Z`` of one loaded file (``frame``, ``fs``, its feature
    ``table``): named ``Y+iZ``, at the speed of Y's row of the table, with ``--rotation``.
    Refused in one line: no speed, a name that is not a channel of ``path``, with
    ``--revs-per-bin``."""
    from rubdiag.signal import orbit_features

    if args.revs_per_bin is not None:
        raise ValueError("--pair works at one speed, not with --revs-per-bin")
    names = [name.strip() for name in args.pair.split(",")]
    if len(names) != 2 or not all(names):
        raise ValueError(f"--pair {args.pair!r} (allowed: two channel names, Y,Z)")
    missing = [name for name in names if name not in frame.columns]
    if missing:
        raise ValueError(f"--pair: no channel {missing[0]!r} in {path} (channels: "
                         f"{', '.join(map(str, frame.columns))})")
    rows = table.set_index(table.columns[0])
    speed = args.speed_rpm
    if "speed_rpm" in rows and len(rows):       # Y's own, else the record's (--column)
        speed = float(rows["speed_rpm"].get(names[0], rows["speed_rpm"].iloc[0]))
    if speed is None or not speed > 0.0:
        raise ValueError("--pair needs the running speed (--speed-rpm, or a channel whose "
                         "lines give it)")
    row = orbit_features(frame[names[0]].to_numpy(), frame[names[1]].to_numpy(), fs, speed,
                        rotation=args.rotation)
    return {table.columns[0]: f"{names[0]}+i{names[1]}", "speed_rpm": speed, **row}


#: Order amplitudes that the printed tables across speed show.
ACROSS_SPEED_ORDERS = ("0p5x", "1x", "1p5x", "2x", "4x")


def pandas_display():
    import pandas as pd

    return pd.option_context("display.max_rows", None, "display.float_format", "{:.6g}".format)
