"""Settings of the feature engine, and their defaults, written once.

:class:`Options` is the one place the defaults live: :func:`rubdiag.signal.signal_features`,
:func:`rubdiag.signal.combination_pairs`, :func:`rubdiag.signal.spectral_lines` and
:class:`rubdiag.signal.RubFeatures` read their keyword defaults from its fields
(``band: float = Options.band``), so that their signatures still show the values.
"""

from __future__ import annotations

from dataclasses import dataclass

from rubdiag import _check
from rubdiag.signal._records import MIN_SAMPLES


@dataclass(frozen=True)
class Options:
    """Settings of the feature engine (their meaning: :func:`rubdiag.signal.signal_features`).

    Attributes
    ----------
    band : float
        Half-width of the order search band, in orders (0.03: ±3 % of 1×).
    threshold : float
        A line is significant above ``threshold`` × the local median level.
    window, nperseg, detrend
        As for :func:`rubdiag.signal.amplitude_spectrum` (None: the whole record).
    min_revolutions : float
        Fewest revolutions a record (segment) must hold.
    combo_tol_hz : float or None
        Tolerance of f_a + f_b = m× in Hz (None: the resolution ``fs / nperseg``).
    """

    band: float = 0.03
    threshold: float = 5.0
    window: object = "hann"
    nperseg: int | None = None
    detrend: object = "constant"
    min_revolutions: float = 10.0
    combo_tol_hz: float | None = None

    def __post_init__(self):
        checked = {
            "band": _check.number("band", self.band, lo=0.0, hi=0.25, lo_open=True,
                                  hi_open=True, unit="orders"),
            "threshold": _check.number("threshold", self.threshold, lo=1.0),
            "min_revolutions": _check.non_negative("min_revolutions", self.min_revolutions),
        }
        if self.nperseg is not None:
            checked["nperseg"] = _check.integer("nperseg", self.nperseg, lo=MIN_SAMPLES)
        if self.combo_tol_hz is not None:
            checked["combo_tol_hz"] = _check.positive("combo_tol_hz", self.combo_tol_hz, "Hz")
        for name, value in checked.items():     # numpy scalars become Python numbers
            object.__setattr__(self, name, value)
