"""Which channels a classifier learns from: named ones, or by default the shaft channels
that carry more than their noise floor.

A plant's probes at stiff bearings may see little but their own noise (in the paper rig
the bearing probes read their 1 µm floor and nothing else). A model that uses them learns
nothing from them, yet cannot run where they are missing. So the default set
(``channels="auto"``) leaves out every shaft channel whose **median power over the rubbing
runs** lies within :data:`NOISE_MARGIN_DB` of its **noise floor**:

* a run's power on a channel is the square of its ``rms`` feature (the standard deviation
  of the record over the analysis window, noise included);
* the floor's power is ``floor²``: the design adds white noise of standard deviation
  ``floor`` to every channel of a quantity (:mod:`rubdiag.dataset._noise`), and
  :func:`~rubdiag.learn._columns.read_dataset` gives it per channel (``noise_floors``).

Noise alone reads 0 dB; 6 dB is a signal of √3 × the floor's RMS beside it (power adds).
The rubbing runs set the bar because rub is what the model must see: a channel quiet
without rub but loud with it is kept. Casing channels are never in the default set (in
this model the casing moves only through contact, so it gives rub away by itself:
:func:`~rubdiag.learn._columns.shaft_channels`).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import pandas as pd

from rubdiag.dataset._schema import SEPARATOR
from rubdiag.learn._columns import channels_of, shaft_channels

__all__ = ["CHANNEL_SETS", "NOISE_MARGIN_DB", "ChannelChoice", "choose_channels", "decibels",
           "power_over_floor_db"]

#: A shaft channel whose median power over the rubbing runs is less than this many dB
#: above its noise floor's power is left out of the default channels.
NOISE_MARGIN_DB = 6.0
#: The named channel sets: ``auto`` (the default), ``shaft`` (every channel not on the
#: casing), ``all``.
CHANNEL_SETS = ("auto", "shaft", "all")


@dataclass(frozen=True)
class ChannelChoice:
    """The channels to learn from, and what the default set left out and why."""

    channels: list
    left_out: dict = field(default_factory=dict)   # channel -> dB over its floor
    n_rubbing: int = 0                             # runs the powers were taken over
    note: str = ""                                 # why nothing could be judged, if so

    def left_out_json(self) -> dict:
        """``left_out`` for strict JSON: a channel that read exactly 0 (−inf dB) as None."""
        return {c: float(v) if np.isfinite(v) else None for c, v in self.left_out.items()}

    def describe(self) -> str:
        """One sentence for a report ("" when nothing was left out or judged)."""
        if self.note:
            return self.note
        if not self.left_out:
            return ""
        shown = ", ".join(f"{c} ({decibels(db)})" for c, db in self.left_out.items())
        return (f"Left out of the default channels: {shown} — their median power over the "
                f"{self.n_rubbing} rubbing runs is within {NOISE_MARGIN_DB:g} dB of their "
                "noise floor, so they carry almost nothing but noise (name channels with "
                "--channels to use them).")


def decibels(db: float) -> str:
    """``+0.1 dB``: signed, one decimal, never ``-0.0``."""
    return f"{round(db, 1) + 0.0:+.1f} dB"


def power_over_floor_db(data: pd.DataFrame, channels) -> dict[str, float]:
    """Median power over the rubbing runs (``rub`` True) of each of ``channels`` over its
    noise floor's power, in dB (``inf`` for a floor of 0; channels without a known floor
    are left out of the result). Empty when the data has no rubbing run or no floors."""
    floors = data.attrs.get("noise_floors") or {}
    if "rub" not in data.columns:
        return {}
    rubbing = data["rub"].to_numpy(dtype=bool)
    if not rubbing.any():
        return {}
    out = {}
    for c in channels:
        if c not in floors:
            continue
        rms = data[f"{c}{SEPARATOR}rms"].to_numpy(dtype=np.float64)[rubbing]
        power = float(np.median(rms ** 2))
        floor = float(floors[c]) ** 2
        with np.errstate(divide="ignore"):
            out[c] = float(10.0 * np.log10(power / floor)) if floor > 0 else np.inf
    return out


def choose_channels(data: pd.DataFrame, channels="auto") -> ChannelChoice:
    """``channels`` of :func:`rubdiag.learn._evaluate` resolved on ``data``: ``"auto"`` (the
    default: the shaft channels with more than their floor, module docstring),
    ``"shaft"``, ``"all"``, or names (a string or a list).

    Parameters
    ----------
    data : pandas.DataFrame
        A dataset's rows (:func:`read_dataset`).
    channels : str or list of str
        ``"auto"``, ``"shaft"``, ``"all"`` or channel names.

    Returns
    -------
    ChannelChoice
        The channels, and what ``"auto"`` left out.
    """
    if channels is None or (isinstance(channels, str) and channels == "auto"):
        return _auto(data)
    if isinstance(channels, str) and channels == "shaft":
        return _checked(ChannelChoice(shaft_channels(data)))
    if isinstance(channels, str) and channels == "all":
        return _checked(ChannelChoice(channels_of(data)))
    names = [channels] if isinstance(channels, str) else list(channels)
    have = channels_of(data)
    missing = [c for c in names if c not in have]
    if missing:
        raise ValueError(f"channels: {missing[0]!r} is not a channel of the data (its "
                         f"channels: {', '.join(have)}; or one of {', '.join(CHANNEL_SETS)})")
    twice = [c for i, c in enumerate(names) if c in names[:i]]
    if twice:
        raise ValueError(f"channels: {twice[0]!r} is named twice (allowed: each channel once)")
    return _checked(ChannelChoice(names))


def _auto(data: pd.DataFrame) -> ChannelChoice:
    shaft = shaft_channels(data)
    if not data.attrs.get("noise_floors"):
        return _checked(ChannelChoice(shaft, note="The noise floors of the channels are "
                                      "unknown (rows not read by read_dataset): every "
                                      "shaft channel is used."))
    n_rubbing = int(data["rub"].astype(bool).sum()) if "rub" in data.columns else 0
    if n_rubbing == 0:
        return _checked(ChannelChoice(shaft, note="No rubbing run to compare the channels' "
                                      "power with their noise floors: every shaft channel "
                                      "is used."))
    db = power_over_floor_db(data, shaft)
    left_out = {c: v for c, v in db.items() if v < NOISE_MARGIN_DB}
    kept = [c for c in shaft if c not in left_out]
    if not kept:
        shown = ", ".join(f"{c} {decibels(v)}" for c, v in left_out.items())
        raise ValueError(f"channels = 'auto': every shaft channel is within "
                         f"{NOISE_MARGIN_DB:g} dB of its noise floor over the rubbing runs "
                         f"({shown}): nothing to learn from (name channels to use them "
                         "anyway: --channels shaft, or their names)")
    return ChannelChoice(kept, left_out, n_rubbing)


def _checked(choice: ChannelChoice) -> ChannelChoice:
    if not choice.channels:
        raise ValueError("no channel left to learn from (channels)")
    return choice
