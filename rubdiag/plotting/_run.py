"""Figures of one simulated run, laid out as the study's Figs. 7-10.

(a) shaft waveform, (b) casing waveform — each the whole analysis window above a zoom on its
last few revolutions, (c) rotor orbit with the clearance circle, (d) amplitude spectra of the
shaft and of the blade tip (one axes each) with the detected features marked, (e) normal
forces of the contact elements, (f) their contact status, drawn from the per-step
status-segment log so that no episode is lost between two output samples.

``FIGSIZE`` and ``DPI`` are the size and resolution of the saved figure (``rubdiag plot`` and
``rubdiag table2`` both save with them). :func:`run_figure` draws on the figure ``fig`` when
given, else on one of its own, and returns it (:func:`rubdiag.plotting.save_figure` writes
it; :func:`save_run_figures` draws and writes).
"""

from __future__ import annotations

from pathlib import Path

import matplotlib as mpl
import numpy as np
from matplotlib.collections import PolyCollection
from matplotlib.patches import Patch
from matplotlib.ticker import MaxNLocator

from rubdiag._figures import PNG_OPTIONS, new_figure, save_figure
from rubdiag.plotting._spectra import order_spectra_figure

__all__ = ["DPI", "FIGSIZE", "PNG_OPTIONS", "STATUS_COLOURS", "ZOOM_REVOLUTIONS", "run_figure",
           "save_run_figures"]

FIGSIZE = (14.0, 15.0)          # inches
DPI = 110                       # saved resolution (dots per inch)
ZOOM_REVOLUTIONS = 5            # revolutions shown in the zoom under each waveform
STATUS_COLOURS = {2: "#f39c12", 3: "#c0392b"}          # sliding, sticking
_STATUS_NAMES = {2: "sliding (status 2)", 3: "sticking (status 3)"}
_MIN_PX = 1.0                   # narrowest drawn status segment (pixels at the drawn DPI)


def _few_ticks(ax, x: int | None = 6, y: int | None = 5) -> None:
    """At most about ``x``/``y`` labelled ticks: each tick is an object with its own lines and
    text, and ticks were a third of the figure's drawing time."""
    for axis, n in ((ax.xaxis, x), (ax.yaxis, y)):
        if n is not None:
            axis.set_major_locator(MaxNLocator(n))


def _unprefixed(row, prefix: str) -> dict:
    out = {"speed_rpm": row["speed_rpm"]}
    out.update({k[len(prefix) + 1:]: v for k, v in row.items() if k.startswith(prefix + "_")})
    return out


def _panel_waveform(axes, t, y_um, title, colour, zoom):
    """The whole record on ``axes[0]``, the ``zoom`` interval (s) on ``axes[1]``."""
    full, near = axes
    full.plot(t, y_um, lw=0.6, color=colour)
    full.axvspan(*zoom, color="0.5", alpha=0.3, lw=0)
    full.set(ylabel="displacement (µm)", title=title, xlim=(t[0], t[-1]))
    keep = (t >= zoom[0]) & (t <= zoom[1])
    near.plot(t[keep], y_um[keep], lw=0.9, color=colour)
    near.set(xlabel="time (s)", ylabel="displacement (µm)", xlim=zoom)
    near.set_title(f"last {ZOOM_REVOLUTIONS} revolutions (shaded above)", fontsize="medium")
    for ax in axes:
        ax.grid(alpha=0.3)
        _few_ticks(ax)


def _panel_orbit(ax, y_mm, z_mm, gap_mm, title):
    ax.plot(y_mm, z_mm, lw=0.4, color="#2471a3")
    if gap_mm:
        theta = np.linspace(0, 2 * np.pi, 361)
        ax.plot(gap_mm * np.cos(theta), gap_mm * np.sin(theta), "r:", lw=1.5,
                label=f"initial clearance g0 = {gap_mm:g} mm")
        ax.legend(loc="upper right", fontsize="small")
    ax.set(xlabel="y (mm)", ylabel="z (mm)", title=title, aspect="equal")
    ax.grid(alpha=0.3)
    _few_ticks(ax, 6, 6)


def _panel_forces(ax, t, fn):
    n = fn.shape[1]
    offset = max(float(fn.max()), 1.0) * 1.05
    for k in range(n):
        ax.plot(t, fn[:, k] + k * offset, lw=0.6)
        ax.text(1.01, (k * offset) / (n * offset), str(k + 1), transform=ax.transAxes,
                fontsize="small", va="bottom")
    ax.set(xlabel="time (s)", ylabel=f"normal force (N), traces offset by {offset:.0f} N",
           title=f"(e) normal contact force, elements 1-{n} (bottom to top)",
           xlim=(t[0], t[-1]), ylim=(-0.02 * offset, n * offset))
    ax.grid(alpha=0.3)
    _few_ticks(ax)


class SegmentBars(PolyCollection):
    """Horizontal bars ``[t_start, t_end] x [row - height/2, row + height/2]`` that are never
    drawn narrower than ``min_px`` pixels: the minimum width in data units is computed from
    the axes' width in pixels at draw time, so it holds at whatever size and DPI the figure
    is saved. A widened bar keeps its midpoint. Bars are drawn in the given order (later on
    top) and without antialiasing, so a bar one pixel wide keeps its own colour."""

    def __init__(self, t_start, t_end, rows, height=0.8, min_px=_MIN_PX, **kwargs):
        self._t0 = np.asarray(t_start, dtype=float)
        self._t1 = np.asarray(t_end, dtype=float)
        self._rows = np.asarray(rows, dtype=float)
        self._half = 0.5 * height
        self._min_px = float(min_px)
        kwargs.setdefault("antialiased", False)
        kwargs.setdefault("linewidths", 0)
        super().__init__(self._verts(0.0), **kwargs)

    def _verts(self, min_width: float) -> np.ndarray:
        t0, t1 = self._t0, self._t1
        mid = 0.5 * (t0 + t1)
        half = 0.5 * np.maximum(t1 - t0, min_width)
        a, b = np.minimum(t0, mid - half), np.maximum(t1, mid + half)
        lo, hi = self._rows - self._half, self._rows + self._half
        return np.stack([np.stack([a, lo], 1), np.stack([b, lo], 1),
                         np.stack([b, hi], 1), np.stack([a, hi], 1)], axis=1)

    def min_width(self) -> float:
        """The narrowest drawn width (data units) at the axes' current size in pixels."""
        x0, x1 = self.axes.get_xlim()
        return self._min_px * abs(x1 - x0) / max(self.axes.bbox.width, 1.0)

    def draw(self, renderer):
        if self.axes is not None:
            self.set_verts(self._verts(self.min_width()))
        super().draw(renderer)


def _panel_status(ax, segments, n_elements: int, window: tuple[float, float]):
    """Every status segment of the per-step log as a bar in its element's row: sliding in
    the upper half of the row, sticking in the lower half, so neither hides the other."""
    t0, t1 = window
    keep = (segments.t_end >= t0) & (segments.t_start <= t1)
    element, status = segments.element[keep], segments.status[keep]
    start, end = segments.t_start[keep], segments.t_end[keep]
    colours = [STATUS_COLOURS.get(int(s), "k") for s in status]
    ax.add_collection(SegmentBars(start, end, element + np.where(status == 3, -0.2, 0.2),
                                  height=0.38, facecolors=colours), autolim=False)
    handles = [Patch(color=c, label=f"{_STATUS_NAMES[s]}: {int((status == s).sum())} "
                     "segments") for s, c in STATUS_COLOURS.items()]
    ax.legend(handles=handles, loc="upper center", bbox_to_anchor=(0.5, -0.1), ncols=2,
              fontsize="small", frameon=False)
    ax.set_title("(f) contact status: every segment of the per-step log (open: blank)")
    ax.set(xlabel="time (s)", ylabel="contact element (upper half: sliding, lower: sticking)",
           xlim=window,
           ylim=(0.5, n_elements + 0.5), yticks=range(1, n_elements + 1))
    ax.grid(alpha=0.3, axis="x")
    _few_ticks(ax, y=None)


def run_figure(result, row=None, title: str | None = None, *, fig=None):
    """The six-panel figure of one run (analysis window only), ``FIGSIZE`` at ``DPI``.

    The panels, as the study's Figs. 7-10 (module docstring): shaft and casing waveforms,
    the rotor orbit with the clearance circle, the shaft's and the blade tip's spectra with
    the detected features marked, the contact elements' normal forces and their contact
    status.

    Parameters
    ----------
    result : SimulationResult
        The run.
    row : dict, optional
        The run's feature row (:func:`rubdiag.runs.run_features`); computed when not given.
    title : str, optional
        The figure's title; default the run's label and speed (rpm).
    fig : matplotlib.figure.Figure, optional
        An empty figure to draw the panels on (the layout's margins are tuned for
        ``FIGSIZE``); default a new one.

    Returns
    -------
    matplotlib.figure.Figure
        The figure.

    See Also
    --------
    save_run_figures : Draw and write it.
    """
    from rubdiag.runs import run_features

    if row is None:
        row = run_features(result).iloc[0].to_dict()
    # titles at a fixed height: automatic placement measures every tick label again
    with mpl.rc_context({"axes.titley": 1.0}):
        return _draw_run(result, row, title, fig)


def _draw_run(result, row, title, fig):
    from rubdiag.runs import run_points, run_signals
    from rubdiag.signal import amplitude_spectrum

    window = result.window
    t = result.t[window]
    signals = run_signals(result)
    run = result.run
    # a fixed layout (margins in figure fractions, tuned for FIGSIZE): constrained layout
    # measured every tick label again and doubled the drawing time
    fig = new_figure(figsize=FIGSIZE, dpi=DPI) if fig is None else fig
    grid = fig.add_gridspec(3, 2, height_ratios=(1.25, 1.0, 1.0), left=0.06, right=0.965,
                            top=0.945, bottom=0.085, wspace=0.2, hspace=0.2)
    fig.suptitle(title or f"{run.label} at {run.speed_rpm:.0f} rpm", fontsize=14, y=0.985)
    points = run_points(result)
    node = points["shaft"][:-2]          # "shaft 11"
    zoom = (max(t[0], t[-1] - ZOOM_REVOLUTIONS * 60.0 / run.speed_rpm), t[-1])
    waveforms = [("shaft", f"(a) {node}, y", "#2471a3"),
                 ("casing", "(b) casing at contact 1, y", "#7d3c98")]
    for column, (prefix, name, colour) in enumerate(waveforms):
        if prefix in signals:
            cell = grid[0, column].subgridspec(2, 1, hspace=0.45)
            axes = (fig.add_subplot(cell[0]), fig.add_subplot(cell[1]))
            _panel_waveform(axes, t, signals[prefix] * 1e6, name, colour, zoom)
    y = result.displacement(f"{node} y", True) * 1e3
    z = result.displacement(f"{node} z", True) * 1e3
    _panel_orbit(fig.add_subplot(grid[1, 0]), y, z, (run.gap_m or 0) * 1e3,
                 f"(c) rotor orbit, {node}")
    spectra = [(prefix, label) for prefix, label in
               (("shaft", f"{node} y"), ("blade", "blade tip (contact 1) y"))
               if prefix in signals]
    cell = grid[1, 1].subgridspec(len(spectra), 1, hspace=0.08)
    first = None
    for i, (prefix, label) in enumerate(spectra):
        ax = fig.add_subplot(cell[i], sharex=first, sharey=first)
        first = first or ax
        f, amp = amplitude_spectrum(signals[prefix], result.fs)
        order_spectra_figure([(label, f, amp, _unprefixed(row, prefix))], ax=ax, unit="µm",
                           scale=1e6, colours=("#2471a3",) if i == 0 else ("#c0392b",),
                           title="(d) amplitude spectra (features marked)" if i == 0 else "")
        if i < len(spectra) - 1:
            ax.set_xlabel("")
            ax.tick_params(labelbottom=False)
    fn = result.system.contact_fn[window]
    if fn.shape[1]:
        _panel_forces(fig.add_subplot(grid[2, 0]), t, fn)
        _panel_status(fig.add_subplot(grid[2, 1]), result.system.status_segments, fn.shape[1],
                      (float(t[0]), float(t[-1])))
    return fig


def save_run_figures(result, out_dir: str | Path, stem: str = "run", row=None,
                     title: str | None = None) -> list[Path]:
    """Write the run figure (:func:`run_figure`) as ``out_dir/<stem>.png``, ``FIGSIZE`` at
    ``DPI``.

    Parameters
    ----------
    result : SimulationResult
        The run.
    out_dir : str or Path
        The folder to write to (made when missing).
    stem : str
        The file name without its suffix.
    row : dict, optional
        The run's feature row (:func:`rubdiag.runs.run_features`); computed when not given.
    title : str, optional
        The figure's title; default the run's label and speed (rpm).

    Returns
    -------
    list of Path
        The written files.
    """
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    fig = run_figure(result, row=row, title=title)
    return [save_figure(fig, out_dir / f"{stem}.png", dpi=DPI)]
