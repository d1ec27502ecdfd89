"""Textbook records: probe records of the faults that look like rub, made in code.

Records of a machine rubdiag did not simulate, to score a classifier on the signatures the
literature describes — for evaluation only: a transfer score means something only on
records no model was fitted to. Each record is a 1× line plus the line (or lines) of one
*kind*, at a stated strength over 1×, with white noise, as an x-y probe pair (both probes
of every pair among the channels, :func:`rubdiag.dataset._schema.pair_channel`) and single
probes; at speeds on the frequency-bin grid of the record and between two bins, where a
line's leakage is largest.

Kinds (:data:`KINDS`; strengths as multiples of the 1× amplitude; the sources in our own
words):

``2x`` (``misalignment``; 0.25, 0.5, 1, 2; forward and reverse)
    A coupling misalignment preloads the rotor and adds a 2× line, from a fraction of 1× to
    above it in severe cases, and flattens the orbit into a banana or figure-eight (Bently &
    Hatch 2002, on radial preloads and misalignment; Vance 1988). A breathing crack gives
    the same line, small away from resonance but larger than 1× near half the first
    critical speed, where the 2× resonance amplifies it (Bently & Hatch 2002; Muszynska
    2005, on cracked shafts). The published models disagree on the precession of a
    parallel misalignment's 2× (forward in most textbooks' orbits, reverse in some
    simulators'), so both are made.
``3x`` (``crack``; 0.1, 0.25, 0.5)
    A crack's 3× near a third of the critical speed, and the 3× of misalignment and of
    loose parts (same sources).
``0.5x`` (``looseness``; 0.1, 0.25, 0.5)
    A loose pedestal or bearing bounces once every two turns: a ½× subharmonic, tens of
    per cent of 1× (Muszynska 2005, on looseness and rotor–stator contact; Bently & Hatch
    2002).
``0.33x`` (``looseness``; 0.1, 0.2, 0.3)
    The ⅓× that looseness gives at higher speeds (same sources).
``rub-like`` (``rub``; 0.5 and 1 times ½× 0.3, 1½× 0.15, 2× 0.1, 2½× 0.07, 3× 0.05)
    A partial rub that touches once every two turns: the ½× subharmonic with its multiples,
    and the harmonics of the truncated orbit (Muszynska 2005, on rotor-to-stator rub;
    Bently & Hatch 2002). A loose part gives the same lines, so a spectrum alone does not
    tell the two apart: these records measure what a model calls the textbook rub
    signature, not a goal of telling it from looseness.

Every line precesses forward unless the kind says otherwise; a pair's y probe reads
``a cos(2π k f t + φ)`` and its z probe ``e a sin(…)`` for forward precession (``−e a
sin(…)`` reverse), e = :data:`ELLIPTICITY` (an elliptical orbit, as anisotropic supports
make it); a single probe reads the y part. Each line's phase is drawn per record, each
channel's noise independently: white, Gaussian, standard deviation ``noise_m`` (default
1 µm, rubdiag's default displacement noise floor) beside a 1× of ``amp_1x_m`` (default
50 µm). A record is deterministic from ``seed`` and its position in the list.

Tested (``tests/learn/test_textbook.py``): rubdiag's own spectral features read every line
within :data:`AMPLITUDE_TOLERANCE` of its stated amplitude, or within
:data:`NOISE_TOLERANCE` times ``noise_m`` for a line so weak that the noise in its bins
counts more (measured: 0.8 % at most for lines of 5 µm and more, 0.04 µm at most for the
weaker ones, with 1 µm noise), on the bins and between them.
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import pandas as pd

from rubdiag import _check
from rubdiag.dataset._schema import pair_channel
from rubdiag.signal import order_label

__all__ = ["AMPLITUDE_TOLERANCE", "ELLIPTICITY", "KINDS", "NOISE_TOLERANCE", "Kind",
           "TextbookRecord",
           "on_bin_speed_rpm", "textbook_records", "write_records"]

#: z over y amplitude of every line of a probe pair's orbit.
ELLIPTICITY = 0.7
#: How far rubdiag's spectral features may read a line from its stated amplitude (share of
#: it), on and between the bins (measured: tests/learn/test_textbook.py) …
AMPLITUDE_TOLERANCE = 0.02
#: … or, for a weak line, in units of the noise's standard deviation.
NOISE_TOLERANCE = 0.1


@dataclass(frozen=True)
class Kind:
    """One kind of textbook record: ``lines`` (order, amplitude over 1×) at each of
    ``strengths`` (factors on those amplitudes), each precession in ``directions``, and
    the ``faults`` label of the fault whose signature it is."""

    faults: str
    lines: tuple[tuple[float, float], ...]
    strengths: tuple[float, ...]
    directions: tuple[str, ...] = ("forward",)


#: The kinds (module docstring).
KINDS = {
    "2x": Kind("misalignment", ((2.0, 1.0),), (0.25, 0.5, 1.0, 2.0), ("forward", "reverse")),
    "3x": Kind("crack", ((3.0, 1.0),), (0.1, 0.25, 0.5)),
    "0.5x": Kind("looseness", ((0.5, 1.0),), (0.1, 0.25, 0.5)),
    "0.33x": Kind("looseness", ((1.0 / 3.0, 1.0),), (0.1, 0.2, 0.3)),
    "rub-like": Kind("rub", ((0.5, 0.3), (1.5, 0.15), (2.0, 0.1), (2.5, 0.07), (3.0, 0.05)),
                     (0.5, 1.0)),
}


@dataclass(frozen=True)
class TextbookRecord:
    """One record: its ``signals`` (channel -> metres, one window) at ``fs_hz``, the 1×
    line and ``lines`` ((order, amplitude in m), 1× first) it holds, and what it is."""

    name: str
    kind: str
    faults: str
    speed_rpm: float
    bin_offset: float           # 1×'s frequency in bins past the grid (0: on a bin)
    direction: str
    lines: tuple[tuple[float, float], ...]
    fs_hz: float
    signals: dict = field(repr=False)

    def frame(self) -> pd.DataFrame:
        """The signals as a table, one column per channel."""
        return pd.DataFrame(self.signals)


def on_bin_speed_rpm(speed_rpm: float, window_s: float, bin_offset: float = 0.0) -> float:
    """The speed nearest ``speed_rpm`` whose 1× lies ``bin_offset`` bins past a bin of a
    ``window_s`` record (bins 1 / window_s apart): 0 on the grid, 0.5 midway between two
    bins."""
    df = 1.0 / window_s
    return 60.0 * (round(speed_rpm / 60.0 / df) + bin_offset) * df


def textbook_records(channels, fs_hz: float, window_s: float, speeds_rpm, *,
                     kinds=tuple(KINDS), bin_offsets=(0.0, 0.5), amp_1x_m: float = 50e-6,
                     noise_m: float = 1e-6, seed: int = 0) -> list[TextbookRecord]:
    """Textbook records of ``kinds`` at every strength, direction, speed and bin offset.

    Parameters
    ----------
    channels : sequence of str
        The probes to make (a model's channels): y/z pairs of one point are read as a
        pair, the others as single probes.
    fs_hz : float
        Sampling rate, Hz.
    window_s : float
        Length of each record, s (a model's window: one window per record).
    speeds_rpm : sequence of float
        Nominal speeds, rpm; each is moved to the nearest speed on the bin grid plus each
        of ``bin_offsets`` (:func:`on_bin_speed_rpm`).
    kinds : sequence of str
        Names in :data:`KINDS`.
    bin_offsets : sequence of float
        1×'s place between two bins, in bins (0 to 1).
    amp_1x_m, noise_m : float
        The 1× amplitude and the noise's standard deviation, m.
    seed : int
        Seeds the phases and the noise.

    Returns
    -------
    list of TextbookRecord
    """
    channels = list(channels)
    if not channels:
        raise ValueError("channels is empty (allowed: one or more probe names)")
    unknown = [k for k in kinds if k not in KINDS]
    if unknown:
        raise ValueError(f"kinds: {unknown[0]!r} is not a textbook kind (allowed: "
                         f"{', '.join(KINDS)})")
    fs_hz = _check.positive("fs_hz", fs_hz, "Hz")
    window_s = _check.positive("window_s", window_s, "s")
    amp_1x_m = _check.positive("amp_1x_m", amp_1x_m, "m")
    noise_m = _check.non_negative("noise_m", noise_m)
    for b in bin_offsets:
        _check.number("bin_offsets", b, lo=0.0, hi=1.0)
    speeds = [_check.positive("speeds_rpm", s, "rpm") for s in speeds_rpm]
    t = np.arange(round(window_s * fs_hz)) / fs_hz
    layout = _layout(channels)
    out = []
    cases = [(name, strength, direction, speed, offset)
             for name in kinds
             for strength, direction in itertools.product(KINDS[name].strengths,
                                                          KINDS[name].directions)
             for speed, offset in itertools.product(speeds, bin_offsets)]
    for index, (name, strength, direction, nominal, offset) in enumerate(cases):
        kind = KINDS[name]
        rpm = on_bin_speed_rpm(nominal, window_s, offset)
        top = max(k for k, _ in kind.lines)
        if (top + 0.25) * rpm / 60.0 >= fs_hz / 2.0:
            raise ValueError(f"fs_hz = {fs_hz:g} Hz is too low for the {name} lines at "
                             f"{rpm:.0f} rpm (allowed: above {2 * (top + 0.25) * rpm / 60:.0f}"
                             " Hz)")
        lines = ((1.0, amp_1x_m),
                 *((k, strength * a * amp_1x_m) for k, a in kind.lines))
        rng = np.random.default_rng(np.random.SeedSequence([seed, index]))
        signals = _probes(layout, lines, direction, rpm / 60.0, t, noise_m, rng)
        label = f"{name}_{strength:g}" + ("_reverse" if direction == "reverse" else "")
        out.append(TextbookRecord(
            name=f"{label}_{rpm:.2f}rpm", kind=name, faults=kind.faults, speed_rpm=rpm,
            bin_offset=float(offset), direction=direction, lines=lines, fs_hz=fs_hz,
            signals=signals))
    return out


def _layout(channels: list[str]) -> list[tuple[str, str | None]]:
    """(y probe or single probe, its z partner or None), every channel once."""
    paired = {}
    for y, z in itertools.permutations(channels, 2):
        if pair_channel(y, z) is not None:
            paired[y], paired[z] = z, None
    return [(c, paired.get(c)) for c in channels if c not in paired or paired[c] is not None]


def _probes(layout, lines, direction, f1_hz, t, noise_m, rng) -> dict[str, np.ndarray]:
    """Each probe's signal (the channels in their given order)."""
    phases = rng.uniform(0.0, 2.0 * np.pi, len(lines))
    turn = 2.0 * np.pi * f1_hz * t
    y = np.zeros_like(t)
    z = np.zeros_like(t)
    for i, ((k, a), phi) in enumerate(zip(lines, phases, strict=True)):
        sign = -1.0 if direction == "reverse" and i > 0 else 1.0
        y += a * np.cos(k * turn + phi)
        z += sign * ELLIPTICITY * a * np.sin(k * turn + phi)
    out = {}
    for first, partner in layout:
        out[first] = y + noise_m * rng.standard_normal(t.size)
        if partner is not None:
            out[partner] = z + noise_m * rng.standard_normal(t.size)
    return out


def write_records(records, folder) -> Path:
    """Each record as ``<name>.npz`` (its channels and ``fs``) in ``folder``, and
    ``records.csv`` listing them: ``file``, ``faults``, ``kind``, ``speed_rpm``,
    ``bin_offset``, ``direction`` and each line's amplitude over 1× (``line_<k>``), the
    labelled record list that ``rubdiag evaluate`` reads. Returns the CSV's path."""
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    rows = []
    for r in records:
        np.savez_compressed(folder / f"{r.name}.npz", fs=np.float64(r.fs_hz), **r.signals)
        one = r.lines[0][1]
        rows.append({"file": f"{r.name}.npz", "faults": r.faults, "kind": r.kind,
                     "speed_rpm": r.speed_rpm, "bin_offset": r.bin_offset,
                     "direction": r.direction,
                     **{f"line_{order_label(k)}": a / one for k, a in r.lines[1:]}})
    path = folder / "records.csv"
    pd.DataFrame(rows).to_csv(path, index=False)
    return path
