"""What each feature column means: a dictionary of the feature columns, by name pattern.

Two kinds of rows carry features: a channel's row (:func:`~rubdiag.signal.signal_features`,
:data:`~rubdiag.signal._table.FEATURE_NAMES`) and a probe pair's row
(:func:`~rubdiag.signal._fullspectrum.orbit_features`). A dataset stores them per channel as
``<channel>__<feature>`` (``shaft11_y_disp__amp_2x``, ``shaft11_yz_disp__rev_1x``).

In a pattern, ``<k>`` is an order label — ``1x``, ``2x``, ``1p5x`` (1.5×), ``0p33x`` (⅓×):
:func:`~rubdiag.signal.order_label` — and ``<n>`` a harmonic, 1 to 8. "signal" as a unit
means the unit of the signal (m for a simulation's displacements; the probe's unit for a
measurement). Every column a row can hold matches exactly one entry
(``tests/signal/test_glossary.py``), so :func:`describe` answers for any of them.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from functools import cached_property

import pandas as pd

__all__ = ["GLOSSARY", "Entry", "describe", "glossary_frame"]

_ORDER = r"\d+(?:p\d+)?x"
_HARMONIC = r"[1-8]"


@dataclass(frozen=True)
class Entry:
    """One pattern of feature names: what it measures and in which unit."""

    pattern: str
    meaning: str
    unit: str
    row: str            # "channel" or "pair"

    @cached_property
    def regex(self) -> re.Pattern:
        text = re.escape(self.pattern).replace(re.escape("<k>"), _ORDER)
        return re.compile("^" + text.replace(re.escape("<n>"), _HARMONIC) + "$")


def _channel(pattern, meaning, unit="signal") -> Entry:
    return Entry(pattern, meaning, unit, "channel")


def _pair(pattern, meaning, unit="signal") -> Entry:
    return Entry(pattern, meaning, unit, "pair")


#: Every feature pattern, in the order of the columns.
GLOSSARY: tuple[Entry, ...] = (
    _channel("speed_rpm", "Running speed the row was analysed at: given, from a tacho, or "
             "voted from the channels' strongest lines.", "rpm"),
    _channel("speed_confidence", "How far the line taken as 1× stands above the noise when "
             "the speed was guessed (noise alone reaches about 5; NaN when the speed was "
             "given).", "1"),
    _channel("rms", "RMS of the detrended signal.", "signal"),
    _channel("amp_<k>", "Peak amplitude of the strongest significant line within k× ± the "
             "search band (half orders 0.5× … 8×, third orders ⅓× … 23/3×); 0 when absent. "
             "Read with every other line's leakage taken out."),
    _channel("freq_<k>_hz", "Exact frequency of that line; NaN when absent.", "Hz"),
    _channel("phase_<k>_deg", "Phase of that line, of cos(2πft + φ) with t = 0 at the "
             "record's first sample; NaN when absent.", "deg"),
    _channel("n_half_orders", "How many of the fractional half orders 0.5×, 1.5× … 7.5× hold "
             "a line.", "1"),
    _channel("n_third_orders", "How many of the third orders k/3× (k not a multiple of 3) "
             "hold a line.", "1"),
    _channel("sb_<n>x_delta_hz", "Sideband spacing Δ around n×: the spacing (below 0.25×) "
             "at which both n× − Δ and n× + Δ hold a line, the one whose weaker line is "
             "strongest; NaN when there is none.", "Hz"),
    _channel("sb_<n>x_lower", "Amplitude of the lower sideband n× − Δ; 0 when absent."),
    _channel("sb_<n>x_upper", "Amplitude of the upper sideband n× + Δ; 0 when absent."),
    _channel("bb_<n>x_rms", "Broadband RMS over n× ± 0.25×, without the n× line's main lobe "
             "and with every line's leakage taken out: what is not a line there."),
    _channel("combo_fa_hz", "Lower frequency f_a of the strongest combination pair f_a + f_b "
             "= m× (m = 1, 2, 3; lines that are neither orders nor sidebands, at least 0.5× "
             "apart; the pair whose weaker line is strongest); NaN when there is none.", "Hz"),
    _channel("combo_fb_hz", "Higher frequency f_b of that pair.", "Hz"),
    _channel("combo_order", "The order m× the pair sums to.", "1"),
    _channel("combo_amp_a", "Amplitude of the line at f_a; 0 when there is no pair."),
    _channel("combo_amp_b", "Amplitude of the line at f_b; 0 when there is no pair."),
    _pair("fwd_<k>", "Forward (with the shaft) amplitude of the orbit at k×: the full "
          "spectrum's positive-frequency line."),
    _pair("rev_<k>", "Reverse (against the shaft) amplitude of the orbit at k×: the full "
          "spectrum's negative-frequency line."),
    _pair("forward_1x", "1× forward amplitude."),
    _pair("reverse_1x", "1× reverse amplitude."),
    _pair("ellipticity_1x", "reverse_1x / forward_1x: 0 for a forward circle, 1 for a line, "
          "above 1 for a reverse orbit.", "1"),
    _pair("precession_1x", "+1 when the 1× orbit turns with the shaft, −1 against it.", "1"),
    _pair("reverse_share", "Reverse share of the motion other than 1×: Σ rev² / Σ (fwd² + "
          "rev²) over the other orders.", "1"),
    _pair("flattening", "1 − r_min / r_max of the orbit's radius about its mean: 0 for a "
          "circle, 1 for a line through the centre.", "1"),
    _pair("limit_radius", "The orbit's clearance-limited radius: the 99th percentile of its "
          "radius."),
    _pair("near_limit_share", "Share of the samples whose radius lies within 5 % of "
          "limit_radius: high for an orbit held by a clearance.", "1"),
)


def describe(name: str) -> Entry:
    """The glossary entry of a feature column ``name`` (with or without its
    ``<channel>__`` prefix).

    Examples
    --------
    >>> describe("shaft11_y_disp__freq_1p5x_hz").meaning
    'Exact frequency of that line; NaN when absent.'
    """
    feature = name.split("__", 1)[-1]
    found = [entry for entry in GLOSSARY if entry.regex.match(feature)]
    if len(found) != 1:
        raise ValueError(f"{name!r} is not a feature column (allowed: names matching a "
                         "pattern of rubdiag.signal._glossary.GLOSSARY, e.g. 'amp_2x')")
    return found[0]


def glossary_frame() -> pd.DataFrame:
    """The glossary as a table: ``row`` (channel or pair), ``pattern``, ``unit``,
    ``meaning``."""
    return pd.DataFrame([{"row": e.row, "pattern": e.pattern, "unit": e.unit,
                          "meaning": e.meaning} for e in GLOSSARY])
