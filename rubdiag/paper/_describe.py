"""Words for a spectrum: the detected rub signatures of a run, written from its features.

Nothing here is typed by hand per case: the text lists what the feature layer found in the
shaft and blade spectra (a feature counts when either response shows it).
"""

from __future__ import annotations

import math

__all__ = ["describe_spectrum"]

#: A broadband peak around n× stands this many times above the level around (n ± 1)×.
BROADBAND_FACTOR = 5.0
_HALF_ORDERS = ("0p5x", "1p5x", "2p5x", "3p5x", "4p5x", "5p5x", "6p5x", "7p5x")


def _fraction(label: str) -> str:
    """'3p5x' -> '7×/2'."""
    value = float(label[:-1].replace("p", "."))
    return f"{round(2 * value)}×/2"


def _get(row, key: str) -> float:
    value = row.get(key, math.nan)
    return float(value) if value is not None else math.nan


def _key(prefix: str, key: str) -> str:
    """Column ``key`` of a signal: ``shaft_amp_1x``, or ``amp_1x`` for the prefix ''."""
    return f"{prefix}_{key}" if prefix else key


def describe_spectrum(row, prefixes=("shaft", "blade")) -> str:
    """A short text of the rub signatures in a run's feature row.

    ``prefixes`` name the signals whose columns count (``shaft_amp_1x`` …); ``("",)``
    describes a row of :func:`rubdiag.signal.signal_features`, whose columns have no prefix.

    Lists the dominant order, present harmonics 2×…8×, broadband peaks around n× (the RMS
    level around n× at least :data:`BROADBAND_FACTOR` times that around (n − 1)× and
    (n + 1)×: the study's "wide continuous spectrum peak near 4×"), sideband pairs n× ± Δ,
    half-order lines and the strongest combination pair f_a + f_b = m×, e.g.
    ``"1× dominant; broadband peak around 4×; 4× ± 2.8 Hz sidebands; 3×/2, 7×/2"`` or
    ``"1× dominant; 7×; combination 43.8 Hz + 145.8 Hz = 2×"``.

    Parameters
    ----------
    row : pandas.Series or dict
        One row of a feature table.
    prefixes : sequence of str
        The signals whose columns count.

    Returns
    -------
    str
        The description.

    Examples
    --------
    A measured 25-Hz line at 1500 rpm with a tenth of it at 3× and half that at 1.5×:

    >>> import numpy as np
    >>> from rubdiag.signal import signal_features
    >>> fs = 2000.0
    >>> t = np.arange(8000) / fs
    >>> x = (np.cos(2 * np.pi * 25 * t) + 0.1 * np.cos(2 * np.pi * 75 * t)
    ...      + 0.05 * np.cos(2 * np.pi * 37.5 * t))
    >>> row = signal_features(x, fs, speed_rpm=1500).iloc[0]
    >>> describe_spectrum(row, prefixes=("",))
    '1× dominant; 3×; 3×/2'
    """
    parts = []
    orders = ["1x", "2x", "3x", "4x", "5x", "6x", "7x", "8x", *_HALF_ORDERS]

    def present(key):
        return any(_get(row, _key(p, key)) > 0 for p in prefixes)

    def largest(key):
        values = [v for v in (_get(row, _key(p, key)) for p in prefixes) if math.isfinite(v)]
        return max(values, default=0.0)

    strongest = max(orders, key=lambda k: largest(f"amp_{k}"))
    if largest(f"amp_{strongest}") > 0:
        parts.append(f"{strongest.replace('p', '.').replace('x', '×')} dominant")
    harmonics = [k for k in ("2x", "3x", "4x", "5x", "6x", "7x", "8x")
                 if k != strongest and present(f"amp_{k}")]
    if harmonics:
        parts.append(", ".join(k.replace("x", "×") for k in harmonics))
    for n in range(2, 8):
        if any(_get(row, _key(p, f"bb_{n}x_rms")) > BROADBAND_FACTOR * max(
                _get(row, _key(p, f"bb_{n - 1}x_rms")), _get(row, _key(p, f"bb_{n + 1}x_rms")))
               for p in prefixes):
            parts.append(f"broadband peak around {n}×")
    for n in range(1, 9):
        deltas = [_get(row, _key(p, f"sb_{n}x_delta_hz")) for p in prefixes]
        deltas = [d for d in deltas if math.isfinite(d)]
        if deltas:
            parts.append(f"{n}× ± {deltas[0]:.1f} Hz sidebands")
    halves = [k for k in _HALF_ORDERS if present(f"amp_{k}")]
    if halves:
        parts.append(", ".join(_fraction(k) for k in halves))
    for p in prefixes:
        fa, fb = _get(row, _key(p, "combo_fa_hz")), _get(row, _key(p, "combo_fb_hz"))
        if math.isfinite(fa) and math.isfinite(fb):
            m = int(_get(row, _key(p, "combo_order")))
            parts.append(f"combination {fa:.1f} Hz + {fb:.1f} Hz = {m}×")
            break
    return "; ".join(parts) if parts else "no significant line"
