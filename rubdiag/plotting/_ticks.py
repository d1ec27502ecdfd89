"""Tick labels without mathtext: matplotlib's log-axis labels (``$10^{-2}$``) go through its
TeX-like parser, about 0.1 s per label set and figure, a third of a run figure's drawing."""

from __future__ import annotations

import math

from matplotlib.ticker import FuncFormatter, LogLocator, NullFormatter

from rubdiag._tolerances import ON_LEVEL

__all__ = ["decade_labels"]

_SUPERSCRIPT = str.maketrans("-0123456789", "⁻⁰¹²³⁴⁵⁶⁷⁸⁹")


def _decade(value: float, _pos=None) -> str:
    if value <= 0 or not math.isfinite(value):
        return ""
    exponent = math.log10(value)
    if abs(exponent - round(exponent)) > ON_LEVEL:
        return ""
    return "10" + str(round(exponent)).translate(_SUPERSCRIPT)


def decade_labels(axis) -> None:
    """Label a log axis at whole decades as ``10⁻²`` (plain Unicode text); no minor labels."""
    axis.set_major_locator(LogLocator(base=10.0))
    axis.set_major_formatter(FuncFormatter(_decade))
    axis.set_minor_formatter(NullFormatter())
