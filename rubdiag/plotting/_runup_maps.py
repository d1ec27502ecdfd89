"""Run-ups and coast-downs as colour maps: the waterfall (frequency across, speed upwards)
and the order map (order across), with order lines and the critical speeds marked
(:mod:`rubdiag.plotting._runup` has the conventions and the other run-up figures).
"""

from __future__ import annotations

import numpy as np
from matplotlib import patheffects
from matplotlib.colors import LogNorm

from rubdiag.plotting._runup_axes import criticals, figure_axes, log_labels, round_ticks
from rubdiag.signal import order_label

__all__ = ["CMAP", "ORDERS", "order_map_figure", "waterfall_figure"]

ORDERS = (0.5, 1, 1.5, 2, 3, 4)     # order lines of the colour maps
CMAP = "magma"
_OUTLINE = [patheffects.withStroke(linewidth=2.5, foreground="k")]


def _colour_map(x, rpm, amplitude, *, per_rpm, xlabel, orders, critical_rpm, unit, scale,
                dynamic_range_db, title, x_max=None, fig=None):
    """The shared body of the waterfall and the order map: rpm upwards, ``x`` across."""
    x, rpm = np.asarray(x, dtype=float), np.asarray(rpm, dtype=float)
    amp = np.asarray(amplitude, dtype=float) * scale
    if x.ndim != 1 or rpm.ndim != 1 or amp.shape != (x.size, rpm.size) or rpm.size < 2:
        raise ValueError(f"amplitude has shape {amp.shape} (allowed: ({x.size}, {rpm.size}), "
                         "one column per speed, at least two speeds)")
    keep = (x > 0) & (x <= (x[-1] if x_max is None else x_max))    # not the mean
    sort = np.argsort(rpm, kind="stable")          # a coast-down is drawn the right way up
    fig, (ax, cax) = figure_axes((8.0, 6.2), 0.85, 0.85, 0.65, 0.75, fig, ncols=2,
                             gridspec_kw=dict(width_ratios=(36, 1), wspace=0.05))
    top = float(np.nanmax(amp[keep]))
    norm = LogNorm(top * 10.0 ** (-dynamic_range_db / 20.0), top)
    mesh = ax.pcolormesh(x[keep], rpm[sort], np.maximum(amp[keep][:, sort].T, norm.vmin),
                         norm=norm, cmap=CMAP, shading="nearest", rasterized=True)
    (x0, x1), (y0, y1) = ax.get_xlim(), ax.get_ylim()
    for k in orders:
        whole = float(k).is_integer()
        xs = [k * y0 / 60.0, k * y1 / 60.0] if per_rpm else [k, k]
        # white with a dark edge: visible on the darkest and the brightest colours
        ax.plot(xs, [y0, y1], color="w", lw=1.1 if whole else 0.8, ls="--" if whole else ":",
                alpha=1.0 if whole else 0.75, gid=f"order {order_label(k)}",
                path_effects=[patheffects.withStroke(linewidth=2.4, foreground="0.15")])
        # labels where the line leaves the map: fractional orders one row further out
        text = dict(text=f"{k:g}×", color="k" if whole else "0.4", annotation_clip=False,
                    fontsize="medium" if whole else "small", textcoords="offset points")
        if xs[1] <= x1:                     # through the top
            ax.annotate(xy=(xs[1], y1), xytext=(0, 2 if whole else 14), va="bottom",
                        ha="center", **text)
        elif per_rpm and xs[0] < x1:        # through the right-hand side
            ax.annotate(xy=(x1, 60.0 * x1 / k), xytext=(2, 0), va="center", ha="left", **text)
    for c in criticals(critical_rpm):
        ax.axhline(c, color="#5dade2", lw=1.0, ls="-.", gid="critical")
        ax.text(0.99, c, f"critical {c:.0f} rpm", transform=ax.get_yaxis_transform(),
                ha="right", va="bottom", color="#aed6f1", path_effects=_OUTLINE)
    ax.set(xlim=(x0, x1), ylim=(y0, y1), xlabel=xlabel, ylabel="speed (rpm)")
    ax.set_title(title, pad=30)
    round_ticks(ax)
    bar = fig.colorbar(mesh, cax=cax)
    bar.set_label(f"peak amplitude ({unit})")
    log_labels(bar.ax.yaxis)
    return fig


def waterfall_figure(f_hz, rpm, amplitude, orders=ORDERS, critical_rpm=None, max_hz=None,
                     unit: str = "µm", scale: float = 1e6, dynamic_range_db: float = 60.0,
                     title: str = "Waterfall", *, fig=None):
    """Short-time spectra as a colour map: frequency across, speed upwards, order lines.

    Parameters
    ----------
    f_hz, rpm, amplitude
        As returned by :func:`rubdiag.signal._waterfall` (its ``t_s`` is not needed):
        amplitude of shape ``(f_hz.size, rpm.size)``. Segments are drawn in speed order,
        so a coast-down reads like a run-up.
    orders : sequence of float
        Order lines ``f = k × rpm / 60`` drawn in white and labelled where they leave the
        map; whole orders dashed, fractional ones dotted and fainter.
    critical_rpm : float or sequence of float, optional
        Critical speed(s), drawn as horizontal dash-dotted lines.
    max_hz : float, optional
        Right end of the frequency axis; default 5 % beyond the highest order at the
        highest speed.
    unit, scale
        The colour bar's unit and the factor that turns ``amplitude`` into it (default m
        to µm).
    dynamic_range_db : float
        Colours span this range below the largest amplitude shown (log scale, 60 dB: three
        decades); anything lower is drawn in the lowest colour.
    title : str
    fig : matplotlib.figure.Figure, optional
        An empty figure to draw the map and its colour bar on; default a new 8 × 6.2 in one.

    Returns
    -------
    matplotlib.figure.Figure
    """
    if max_hz is None:
        max_hz = 1.05 * max(orders, default=1.0) * float(np.max(rpm)) / 60.0
    return _colour_map(f_hz, rpm, amplitude, per_rpm=True, xlabel="frequency (Hz)",
                       orders=orders, critical_rpm=critical_rpm, unit=unit, scale=scale,
                       dynamic_range_db=dynamic_range_db, title=title, x_max=max_hz, fig=fig)


def order_map_figure(orders, rpm, amplitude, guides=ORDERS, critical_rpm=None,
                     max_order=None, unit: str = "µm", scale: float = 1e6,
                     dynamic_range_db: float = 60.0, title: str = "Order map", *, fig=None):
    """Order spectra against speed as a colour map: order across, speed upwards.

    Parameters
    ----------
    orders, rpm, amplitude
        As returned by :func:`rubdiag.signal.rpm_order_map`: amplitude of shape
        ``(orders.size, rpm.size)``.
    guides : sequence of float
        Orders marked by vertical white lines (whole orders dashed, fractional dotted).
    max_order : float, optional
        Right end of the order axis; default 2.5 times the highest guide (10 with the
        default guides), as far as the map goes.
    critical_rpm, unit, scale, dynamic_range_db, title, fig
        As for :func:`waterfall_figure`.

    Returns
    -------
    matplotlib.figure.Figure
    """
    if max_order is None:
        max_order = 2.5 * max(guides, default=4.0)
    return _colour_map(orders, rpm, amplitude, per_rpm=False, xlabel="order (f / 1×)",
                       orders=guides, critical_rpm=critical_rpm, unit=unit, scale=scale,
                       dynamic_range_db=dynamic_range_db, title=title, x_max=max_order,
                       fig=fig)
