"""Figures of one simulated run, laid out as the study's Figs. 7-10.

(a) shaft waveform, (b) casing waveform, (c) rotor orbit with the clearance circle,
(d) log amplitude spectra of shaft and blade with the detected features marked,
(e) normal forces of the contact elements, (f) their contact status.
"""

from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
from matplotlib.colors import ListedColormap

from rubdiag.plotting.spectra import plot_order_spectra

__all__ = ["run_figure", "save_run_figures"]

_STATUS_COLOURS = ListedColormap(["#f2f3f4", "#f39c12", "#c0392b"])   # open, sliding, sticking


def _unprefixed(row, prefix: str) -> dict:
    out = {"speed_rpm": row["speed_rpm"]}
    out.update({k[len(prefix) + 1:]: v for k, v in row.items() if k.startswith(prefix + "_")})
    return out


def _panel_waveform(ax, t, y_um, title, colour):
    ax.plot(t, y_um, lw=0.6, color=colour)
    ax.set(xlabel="time (s)", ylabel="displacement (µm)", title=title)
    ax.grid(alpha=0.3)


def _panel_orbit(ax, y_mm, z_mm, gap_mm, title):
    ax.plot(y_mm, z_mm, lw=0.4, color="#2471a3")
    if gap_mm:
        theta = np.linspace(0, 2 * np.pi, 361)
        ax.plot(gap_mm * np.cos(theta), gap_mm * np.sin(theta), "r:", lw=1.5,
                label=f"initial clearance g0 = {gap_mm:g} mm")
        ax.legend(loc="upper right", fontsize="small")
    ax.set(xlabel="y (mm)", ylabel="z (mm)", title=title, aspect="equal")
    ax.grid(alpha=0.3)


def _panel_forces(ax, t, fn):
    n = fn.shape[1]
    offset = max(float(fn.max()), 1.0) * 1.05
    for k in range(n):
        ax.plot(t, fn[:, k] + k * offset, lw=0.6)
        ax.text(1.01, (k * offset) / (n * offset), str(k + 1), transform=ax.transAxes,
                fontsize="small", va="bottom")
    ax.set(xlabel="time (s)", ylabel=f"normal force (N), traces offset by {offset:.0f} N",
           title="(e) normal contact force, elements 1-8 (bottom to top)",
           ylim=(-0.02 * offset, n * offset))
    ax.grid(alpha=0.3)


def _panel_status(fig, ax, t, status):
    image = ax.imshow(status.T, aspect="auto", origin="lower", cmap=_STATUS_COLOURS, vmin=0.5,
                      vmax=3.5, interpolation="nearest",
                      extent=(t[0], t[-1], 0.5, status.shape[1] + 0.5))
    bar = fig.colorbar(image, ax=ax, ticks=[1, 2, 3], fraction=0.04, pad=0.02)
    bar.ax.set_yticklabels(["1 open", "2 sliding", "3 sticking"])
    ax.set(xlabel="time (s)", ylabel="contact element", title="(f) contact status",
           yticks=range(1, status.shape[1] + 1))


def run_figure(result, row=None, title: str | None = None):
    """The six-panel figure of one run (analysis window only).

    ``row`` is the run's feature row (:func:`rubdiag.runs.features`); computed when
    not given.
    """
    from rubdiag.runs import run_features, run_points, run_signals
    from rubdiag.signal import amplitude_spectrum

    if row is None:
        row = run_features(result).iloc[0].to_dict()
    window = result.window
    t = result.t[window]
    signals = run_signals(result)
    run = result.run
    fig, axes = plt.subplots(3, 2, figsize=(14, 13), constrained_layout=True)
    fig.suptitle(title or f"{run.label} at {run.speed_rpm:.0f} rpm", fontsize=14)
    points = run_points(result)
    node = points["shaft"][:-2]          # "shaft 11"
    _panel_waveform(axes[0, 0], t, signals["shaft"] * 1e6, f"(a) {node}, y", "#2471a3")
    if "casing" in signals:
        _panel_waveform(axes[0, 1], t, signals["casing"] * 1e6, "(b) casing at contact 1, y",
                        "#7d3c98")
    y = result.displacement(f"{node} y", True) * 1e3
    z = result.displacement(f"{node} z", True) * 1e3
    _panel_orbit(axes[1, 0], y, z, (run.gap_m or 0) * 1e3, f"(c) rotor orbit, {node}")
    curves = []
    for prefix, label in (("shaft", node), ("blade", "blade tip (contact 1)")):
        if prefix in signals:
            f, amp = amplitude_spectrum(signals[prefix], result.fs)
            curves.append((label, f, amp, _unprefixed(row, prefix)))
    plot_order_spectra(curves, title="(d) amplitude spectra (features marked)", ax=axes[1, 1])
    fn = result.system.contact_fn[window]
    if fn.shape[1]:
        _panel_forces(axes[2, 0], t, fn)
        _panel_status(fig, axes[2, 1], t, result.system.contact_status[window])
    else:
        axes[2, 0].set_visible(False)
        axes[2, 1].set_visible(False)
    return fig


def save_run_figures(result, out_dir: str | Path, stem: str = "run", row=None) -> list[Path]:
    """Write the run figure as ``out_dir/<stem>.png``; returns the written paths."""
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    fig = run_figure(result, row=row)
    path = out_dir / f"{stem}.png"
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return [path]
