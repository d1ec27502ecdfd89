"""Amplitude spectra over orders of the running speed, with the detected features marked."""

from __future__ import annotations

import numpy as np
from matplotlib.collections import LineCollection
from matplotlib.lines import Line2D
from matplotlib.ticker import NullLocator

from rubdiag._figures import figure_and_axes
from rubdiag.plotting._ticks import decade_labels

__all__ = ["MARKERS", "order_spectra_figure"]

_COLOURS = ("#2471a3", "#c0392b", "#229954", "#7d3c98")
_MAX_ORDER = 8.5
# feature kind -> (marker style, legend text)
MARKERS = {
    "line": (dict(marker="o", ms=5, mfc="none", mew=1.2), "order line n× (detected)"),
    "sideband": (dict(marker="v", ms=6, mfc="none", mew=1.2), "sideband pair n× ± Δf"),
    "combination": (dict(marker="s", ms=7, mfc="none", mew=1.2),
                    "combination pair fa + fb = k×"),
}


def order_spectra_figure(curves, title: str = "", max_order: float = _MAX_ORDER, ax=None,
                       unit: str = "signal unit", scale: float = 1.0, colours=_COLOURS,
                       headroom: float = 0.25):
    """Overlay amplitude spectra against order (f / 1×) on a log scale.

    Parameters
    ----------
    curves : sequence of (label, f, amplitude, row)
        ``f`` in Hz and ``amplitude`` (signal unit) as from
        :func:`rubdiag.signal.amplitude_spectrum`; ``row`` is the curve's feature row (a
        mapping with ``speed_rpm``, ``amp_*``/``freq_*_hz``, ``sb_*`` and ``combo_*`` as
        in :func:`rubdiag.signal.signal_features`). Detected order lines are marked with circles,
        sideband pairs with triangles, a combination pair with squares; the legend names
        each kind drawn (see ``MARKERS``).
    title : str
        Axes title.
    max_order : float
        Right end of the order axis.
    ax : matplotlib Axes, optional
        Axes to draw on; default a new 9 × 4.8 in figure.
    unit : str
        Unit of the plotted amplitude (after ``scale``), shown on the axis label.
    scale : float
        Factor applied to the amplitudes and the marked feature amplitudes (e.g. 1e6 to
        draw metres in µm).
    colours : sequence of str
        Curve colours, cycled.
    headroom : float
        Share of the axes height kept above the highest plotted amplitude (on the log
        scale) for the legend, so that the legend hides no part of a spectrum.

    Returns
    -------
    matplotlib.figure.Figure
    """
    fig, ax = figure_and_axes(ax, figsize=(9, 4.8), layout="constrained")
    lowest, highest = np.inf, -np.inf
    drawn = set()
    for i, (label, f, amp, row) in enumerate(curves):
        colour = colours[i % len(colours)]
        f1 = float(row["speed_rpm"]) / 60.0
        order = np.asarray(f) / f1
        keep = (order > 0) & (order <= max_order)
        a = np.asarray(amp)[keep] * scale
        positive = a[a > 0]
        if positive.size:
            lowest = min(lowest, float(np.percentile(positive, 1)))
            highest = max(highest, float(positive.max()))
        ax.semilogy(
            order[keep], np.where(a > 0, a, np.nan), color=colour, lw=1.4 if i == 0 else 0.8,
            alpha=0.9, label=label, zorder=2 + i,
        )
        drawn |= _mark(ax, row, f1, colour, scale, zorder=10 + i)
    ax.set(xlabel="order (f / 1×)", ylabel=f"peak amplitude ({unit})", title=title,
           xlim=(0, max_order))
    if np.isfinite(lowest) and highest > lowest:
        decades = np.log10(highest / lowest) * 1.05
        ax.set_ylim(lowest, lowest * 10 ** (decades / (1.0 - headroom)))
    ax.set_xticks(np.arange(0, int(max_order) + 1))
    ax.yaxis.set_minor_locator(NullLocator())
    decade_labels(ax.yaxis)
    ax.grid(alpha=0.3)
    # half orders (3×/2 …) as one collection of lines: minor ticks would cost a tick object each
    halves = np.arange(0.5, max_order, 1.0)
    ax.add_collection(LineCollection([((x, 0), (x, 1)) for x in halves], colors="0.85", lw=0.6,
                                     transform=ax.get_xaxis_transform(), zorder=0.5),
                      autolim=False)
    handles, _ = ax.get_legend_handles_labels()
    handles += [Line2D([], [], ls="none", color="0.2", label=MARKERS[kind][1],
                       **MARKERS[kind][0]) for kind in MARKERS if kind in drawn]
    ax.legend(handles=handles, loc="upper right", fontsize="small", ncols=2)
    return fig


def _mark(ax, row, f1: float, colour: str, scale: float, zorder: int) -> set[str]:
    """Mark the features of ``row``; returns the kinds drawn."""
    xs = {kind: [] for kind in MARKERS}
    ys = {kind: [] for kind in MARKERS}
    for key in list(row.keys()):
        if key.startswith("freq_") and key.endswith("_hz"):
            amp = row["amp_" + key[5:-3]]
            if np.isfinite(row[key]) and amp > 0:
                xs["line"].append(row[key] / f1)
                ys["line"].append(amp)
        elif key.startswith("sb_") and key.endswith("_delta_hz") and np.isfinite(row[key]):
            n = float(key[3:].split("x")[0])
            stem = key[: -len("delta_hz")]
            for sign, side in ((-1, "lower"), (1, "upper")):
                xs["sideband"].append(n + sign * row[key] / f1)
                ys["sideband"].append(row[stem + side])
    if "combo_fa_hz" in row and np.isfinite(row["combo_fa_hz"]):
        for fk, ak in (("combo_fa_hz", "combo_amp_a"), ("combo_fb_hz", "combo_amp_b")):
            xs["combination"].append(row[fk] / f1)
            ys["combination"].append(row[ak])
    for kind, (style, _) in MARKERS.items():
        if xs[kind]:
            ax.plot(xs[kind], np.asarray(ys[kind], dtype=float) * scale, ls="none",
                    color=colour, zorder=zorder, **style)
    return {kind for kind in MARKERS if xs[kind]}
