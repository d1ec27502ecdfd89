"""Amplitude spectra over orders of the running speed, with the detected features marked."""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

__all__ = ["plot_order_spectra"]

_COLOURS = ("#2471a3", "#c0392b", "#229954", "#7d3c98")
_MAX_ORDER = 8.5


def plot_order_spectra(curves, title: str = "", max_order: float = _MAX_ORDER, ax=None):
    """Overlay amplitude spectra against order (f / 1×) on a log scale.

    Parameters
    ----------
    curves : sequence of (label, f, amplitude, row)
        ``f`` in Hz and ``amplitude`` (signal unit) as from
        :func:`rubdiag.signal.amplitude_spectrum`; ``row`` is the curve's feature row (a
        mapping with ``speed_rpm``, ``amp_*``/``freq_*_hz``, ``sb_*`` and ``combo_*`` as
        in :func:`rubdiag.signal.features`). Present order lines are marked with dots,
        sidebands with triangles, a combination pair with squares.
    title : str
        Axes title.
    max_order : float
        Right end of the order axis.
    ax : matplotlib Axes, optional
        Axes to draw in; a new figure when None.

    Returns
    -------
    matplotlib.figure.Figure
    """
    if ax is None:
        fig, ax = plt.subplots(figsize=(9, 4.8), constrained_layout=True)
    else:
        fig = ax.figure
    lowest = np.inf
    for i, (label, f, amp, row) in enumerate(curves):
        colour = _COLOURS[i % len(_COLOURS)]
        f1 = float(row["speed_rpm"]) / 60.0
        order = np.asarray(f) / f1
        keep = (order > 0) & (order <= max_order)
        a = np.asarray(amp)[keep]
        positive = a[a > 0]
        if positive.size:
            lowest = min(lowest, float(np.percentile(positive, 1)))
        ax.semilogy(
            order[keep], np.where(a > 0, a, np.nan), color=colour, lw=1.4 if i == 0 else 0.8,
            alpha=0.9, label=label, zorder=2 + i,
        )
        _mark(ax, row, f1, colour)
    ax.set(xlabel="order (f / 1×)", ylabel="peak amplitude", title=title, xlim=(0, max_order))
    if np.isfinite(lowest):
        ax.set_ylim(bottom=lowest)
    ax.set_xticks(np.arange(0, max_order + 0.01, 0.5), minor=True)
    ax.set_xticks(np.arange(0, int(max_order) + 1))
    ax.grid(alpha=0.3, which="both")
    ax.legend(loc="upper right", fontsize="small")
    return fig


def _mark(ax, row, f1: float, colour: str) -> None:
    keys = list(row.keys())
    for key in keys:
        if key.startswith("freq_") and key.endswith("_hz"):
            amp = row["amp_" + key[5:-3]]
            if np.isfinite(row[key]) and amp > 0:
                ax.plot(row[key] / f1, amp, "o", ms=4, mfc="none", color=colour)
        elif key.startswith("sb_") and key.endswith("_delta_hz") and np.isfinite(row[key]):
            n = float(key[3:].split("x")[0])
            stem = key[: -len("delta_hz")]
            for sign, side in ((-1, "lower"), (1, "upper")):
                x = n + sign * row[key] / f1
                ax.plot(x, row[stem + side], "v", ms=5, color=colour)
    if "combo_fa_hz" in row and np.isfinite(row["combo_fa_hz"]):
        for fk, ak in (("combo_fa_hz", "combo_amp_a"), ("combo_fb_hz", "combo_amp_b")):
            ax.plot(row[fk] / f1, row[ak], "s", ms=6, mfc="none", color=colour)
