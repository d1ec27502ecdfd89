"""Figures of the linear analysis: Campbell diagram, unbalance response, deflected shape.

Each draws on the axes ``ax`` when given, else on a figure of its own, and returns the figure
(:func:`rubdiag.plotting.save_figure` writes it)."""

from __future__ import annotations

import numpy as np

from rubdiag._figures import figure_and_axes, new_figure
from rubdiag._tolerances import PLANAR_WHIRL
from rubdiag.plotting._ticks import decade_labels

__all__ = ["campbell_figure", "deflection_figure", "unbalance_figure"]

_RPM = 30.0 / np.pi
_FORWARD, _BACKWARD = "#c0392b", "#2471a3"


def _fixed_axes(ax, bottom_in: float, size=(7.5, 4.5)):
    """``ax`` and its figure, or a figure with one axes placed by fixed margins (inches):
    constrained layout measured every label again, half of the drawing time of these small
    figures."""
    if ax is not None:
        return ax.figure, ax
    fig = new_figure(figsize=size)
    ax = fig.add_subplot()
    width, height = size
    fig.subplots_adjust(left=0.95 / width, right=1 - 0.2 / width, bottom=bottom_in / height,
                        top=1 - 0.4 / height)
    return fig, ax


def campbell_figure(campbell, title: str = "Campbell diagram", *, ax=None):
    """Damped natural frequencies (Hz) against speed (rpm), coloured by whirl; 1× line.

    Parameters
    ----------
    campbell : Campbell
        From :func:`rubdiag.modal._campbell`.
    title : str
        The axes' title.
    ax : matplotlib.axes.Axes, optional
        Axes to draw on; default a new 7.5 × 5 in figure.

    Returns
    -------
    matplotlib.figure.Figure
    """
    fig, ax = figure_and_axes(ax, figsize=(7.5, 5), layout="constrained")
    rpm = campbell.speeds * _RPM
    f_hz = campbell.frequencies / (2 * np.pi)
    for j in range(f_hz.shape[1]):
        ax.plot(rpm, f_hz[:, j], color="0.8", lw=0.8, zorder=1)
    rotor = campbell.shaft_share >= 0.25     # casing and blade modes do not whirl with the rotor
    fwd = (campbell.whirl_ratio > PLANAR_WHIRL) & rotor
    bwd = (campbell.whirl_ratio < -PLANAR_WHIRL) & rotor
    grid = np.broadcast_to(rpm[:, None], f_hz.shape)
    ax.scatter(grid[~rotor], f_hz[~rotor], s=6, color="0.6", label="casing / blade modes",
               zorder=2)
    # forward and backward whirl nearly coincide on a stiff rotor: the backward markers are
    # small and filled, the forward ones larger, hollow and drawn on top, so both show
    ax.scatter(grid[bwd], f_hz[bwd], s=10, marker="v", color=_BACKWARD, zorder=3,
               label="backward whirl")
    ax.scatter(grid[fwd], f_hz[fwd], s=42, marker="^", facecolors="none",
               edgecolors=_FORWARD, linewidths=1.1, zorder=4, label="forward whirl")
    ax.plot(rpm, rpm / 60.0, "k--", lw=1, label="1×")
    top = float(np.nanmax(f_hz)) * 1.05
    for cs in campbell.critical_speeds:
        if cs <= campbell.speeds[-1]:
            ax.plot(cs * _RPM, cs / (2 * np.pi), "ko", mfc="none", ms=9)
            ax.annotate(f"{cs * _RPM:.0f} rpm", (cs * _RPM, cs / (2 * np.pi)),
                        xytext=(6, -12), textcoords="offset points")
    ax.set(xlabel="speed (rpm)", ylabel="natural frequency (Hz)", title=title,
           xlim=(rpm[0], rpm[-1]), ylim=(0, top))
    ax.grid(alpha=0.3)
    ax.legend(loc="upper left")
    return fig


def unbalance_figure(responses: dict, critical_rpm=(), title="Unbalance response, disc 1 y",
                     *, ax=None):
    """Amplitude (mm, log) against speed (rpm) for several labelled UnbalanceResponse.

    Parameters
    ----------
    responses : dict
        Label -> :class:`~rubdiag.modal.UnbalanceResponse` (its first response point drawn).
    critical_rpm : sequence of float
        Critical speeds (rpm) marked by vertical lines.
    title : str
        The axes' title.
    ax : matplotlib.axes.Axes, optional
        Axes to draw on; default a new 7.5 × 4.5 in figure.

    Returns
    -------
    matplotlib.figure.Figure
    """
    fig, ax = _fixed_axes(ax, bottom_in=0.6)
    for label, resp in responses.items():
        ax.semilogy(resp.speeds * _RPM, np.abs(resp.amplitudes[:, 0]) * 1e3, lw=1.6,
                    label=label)
    for i, cs in enumerate(critical_rpm):
        ax.axvline(cs, color="0.5", ls=":", lw=1, label=None if i else "critical speeds")
    ax.set(xlabel="speed (rpm)", ylabel="amplitude (mm)", title=title)
    decade_labels(ax.yaxis)
    ax.grid(alpha=0.3, which="both")
    ax.legend()
    return fig


def deflection_figure(model, responses: dict, title="Deflected shape at the critical speeds",
                      *, ax=None):
    """Orbit semi-major axis (mm) along the shaft for labelled HarmonicResponse objects,
    with bearings and discs marked.

    Parameters
    ----------
    model : Model
        The assembled rig (:func:`rubdiag.assemble`): the shaft's nodes, bearings, discs.
    responses : dict
        Label -> :class:`~rubdiag.modal.HarmonicResponse`.
    title : str
        The axes' title.
    ax : matplotlib.axes.Axes, optional
        Axes to draw on; default a new 7.5 × 4.5 in figure (the legend under the axes).

    Returns
    -------
    matplotlib.figure.Figure
    """
    fig, ax = _fixed_axes(ax, bottom_in=1.15)       # the legend goes under the axes
    x_mm = model.shaft_x_m * 1e3
    for label, resp in responses.items():
        _, _, major = resp.shaft_deflection()
        ax.plot(x_mm, major * 1e3, "o-", ms=3, label=label)
    rig = model.rig
    first = rig.shaft.first_node
    for kind, items, style in (("bearing", rig.bearings, dict(color="k", lw=2, alpha=0.4)),
                               ("disc", rig.discs, dict(color="tab:green", lw=6, alpha=0.25))):
        nodes = [item.node for item in items]
        for i, node in enumerate(nodes):
            plural = "s" if len(nodes) > 1 else ""
            label = (f"{kind}{plural} (node{plural} {', '.join(str(n) for n in nodes)})"
                     if i == 0 else None)
            ax.axvline(x_mm[node - first], label=label, **style)
    ax.set(xlabel="axial position (mm)", ylabel="orbit semi-major axis (mm)", title=title)
    ax.grid(alpha=0.3)
    ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.16), ncols=2, fontsize="small",
              frameon=False)
    return fig
