"""Figures of run-ups and coast-downs: Bode, polar and rub-order plots here, the waterfall
and the order map in :mod:`rubdiag.plotting._runup_maps`; :func:`runup_figures` all of them.

The inputs are the order analyses of :mod:`rubdiag.signal` — plain arrays and
:func:`~rubdiag.signal.order_track` DataFrames — so measured and simulated records plot alike.
Tracks are given as a dict label -> DataFrame (``{"run-up": up, "coast-down": down}``) and
overlaid in the colours ``COLOURS``; each sweep's markers point the way its speed went (``>``
rising, ``<`` falling). Lines that tests and readers look up carry a ``gid``: ``"order 1x"``,
``"critical"``, ``"linear"``, ``"track <label>"``, ``"peak <label>"``,
``"contact <label>"``.

Phase convention, as :func:`~rubdiag.signal.order_track` and
:func:`rubdiag.modal.harmonic_response`: order k is ``A cos(k φ + θ)``, φ the shaft angle
from the tacho's reference, i.e. ``x = Re(z e^{ikφ})`` with the complex amplitude
``z = A e^{iθ}``. A response lagging the unbalance has θ < 0, and θ falls through -90° at a
critical speed. (A simulated 100 rpm/s run-up without contact agrees with the linear response
in this convention within 1.1° off the critical, from the exact angle and from the tacho.)

Where to look: the critical speed is the 1× peak of the linear response with its phase at
-90° (Bode, polar plot); a rub shows where the measured 1× leaves the linear response
(clipped near the clearance, run-up and coast-down apart) and where the rub orders — 0.5×,
2×, 3× … — rise from their floor (order map, :func:`rub_orders_figure`); for simulated runs
the contact bars (``contact_rpm``) give the speeds of the first and last contact.

Each figure function draws on the figure ``fig`` (the polar plot: the axes ``ax``) when
given, else on one of its own, and returns it (:func:`rubdiag.plotting.save_figure` writes
it; :func:`save_runup_figures` writes them all).
"""

from __future__ import annotations

import os
import re
from pathlib import Path

import numpy as np
from matplotlib.lines import Line2D
from matplotlib.ticker import MaxNLocator, MultipleLocator

from rubdiag._figures import save_figure
from rubdiag.plotting._run import DPI
from rubdiag.plotting._runup_axes import (
    ROUND_STEPS,
    criticals,
    figure_axes,
    log_labels,
    round_ticks,
)
from rubdiag.plotting._runup_maps import order_map_figure, waterfall_figure
from rubdiag.signal import order_label, tracking_leakage

__all__ = ["COLOURS", "RUB_ORDERS", "bode_figure", "polar_figure", "rub_orders_figure",
           "runup_figures", "save_runup_figures"]

COLOURS = ("#2471a3", "#c0392b", "#229954", "#7d3c98", "#d68910")
RUB_ORDERS = (0.5, 1.5, 2, 3)       # the panels of rub_orders_figure
_LINEAR = dict(color="0.2", ls="--", lw=1.3)
_CRITICAL = dict(color="0.35", ls=":", lw=1.0)
_LEAKAGE = dict(ls="--", lw=0.9, alpha=0.85)
_BOX = dict(boxstyle="round,pad=0.15", fc="w", ec="none", alpha=0.8)


def _phase_ticks(ax, lo: float, hi: float) -> None:
    """Phase ticks at multiples of 45°, 90°, 180° … , at most about six."""
    turns = max(0.0, np.ceil(np.log2(max(hi - lo, 1.0) / (6 * 45.0))))
    ax.yaxis.set_major_locator(MultipleLocator(45.0 * 2.0**turns))


def _vector(df, order, name) -> tuple[np.ndarray, np.ndarray]:
    """Speed (rpm) and complex amplitude ``A e^{iθ}`` of one order of an order track."""
    amp, phase = f"amp_{order_label(order)}", f"phase_{order_label(order)}_deg"
    missing = [c for c in ("rpm", amp, phase) if c not in df]
    if missing:
        raise ValueError(f"track {name!r} has no column {', '.join(missing)} (allowed: an "
                         f"order_track table with order {order:g} among its orders)")
    if len(df) < 2:
        raise ValueError(f"track {name!r} has {len(df)} rows (allowed: at least 2 bins)")
    return (np.asarray(df["rpm"], dtype=float),
            np.asarray(df[amp], dtype=float)
            * np.exp(1j * np.radians(np.asarray(df[phase], dtype=float))))


def _sweep(rpm: np.ndarray, i: int) -> dict:
    """Line style of the i-th track; markers point the way the speed went."""
    return dict(color=COLOURS[i % len(COLOURS)], lw=1.4, ms=4.5,
                marker=">" if rpm[-1] >= rpm[0] else "<", markevery=max(1, rpm.size // 15))


def _mark_critical(axes, critical_rpm) -> None:
    """Thin vertical lines at the critical speeds, named in the first axes' legend."""
    for j, c in enumerate(criticals(critical_rpm)):
        for ax in axes:
            label = "critical speed" if j == 0 and ax is axes[0] else None
            ax.axvline(c, gid="critical", label=label, **_CRITICAL)


def _contact_bars(ax, tracks: dict, contact_rpm) -> None:
    """A bar per track from its first to its last contact speed along the bottom of
    ``ax``, in the track's colour, labelled with both speeds."""
    inch = 1.0 / (ax.get_position().height * ax.figure.get_figheight())   # axes fraction
    for i, name in enumerate(tracks):
        first, last = (contact_rpm or {}).get(name, (np.nan, np.nan))
        if not (np.isfinite(first) and np.isfinite(last)):
            continue
        y = (0.1 + 0.27 * i) * inch
        colour = COLOURS[i % len(COLOURS)]
        ax.plot([first, last], [y, y], transform=ax.get_xaxis_transform(), color=colour,
                lw=5, alpha=0.45, solid_capstyle="butt", gid=f"contact {name}")
        ax.text(0.5 * (first + last), y + 0.05 * inch,
                f"{name}: contact {first:.0f} → {last:.0f} rpm",
                transform=ax.get_xaxis_transform(), ha="center", va="bottom",
                fontsize="small", color=colour)


# --- order tracks ------------------------------------------------------------------------

def _unwrapped_deg(z: np.ndarray) -> np.ndarray:
    return np.degrees(np.unwrap(np.angle(z)))


def _aligned(rpm, phase, ref=None) -> np.ndarray:
    """``phase`` shifted by whole turns: to the reference curve ``ref = (rpm, phase)`` over
    its speeds, or without one so that the value at the lowest speed lies in (-180, 180]."""
    if ref is None:
        start = phase[np.argmin(rpm)]
        return phase - 360.0 * np.ceil((start - 180.0) / 360.0)
    sort = np.argsort(ref[0])
    gap = np.median(phase - np.interp(rpm, ref[0][sort], ref[1][sort]))
    return phase - 360.0 * np.round(gap / 360.0)


def _at(rpm: np.ndarray, z: np.ndarray, speeds) -> np.ndarray:
    """``z`` interpolated at ``speeds`` (rpm) along a sweep in one direction."""
    sort = np.argsort(rpm)
    speeds = np.atleast_1d(np.asarray(speeds, dtype=float))
    return (np.interp(speeds, rpm[sort], z.real[sort])
            + 1j * np.interp(speeds, rpm[sort], z.imag[sort]))


def _amount(value: float) -> str:
    return f"{value:.0f}" if abs(value) >= 100 else f"{value:.3g}"


def bode_figure(tracks: dict, linear=None, critical_rpm=None, contact_rpm=None,
                order: float = 1, unit: str = "µm", scale: float = 1e6,
                title: str | None = None, *, fig=None):
    """Amplitude and phase of one order against speed, tracks overlaid (Bode plot).

    Parameters
    ----------
    tracks : dict
        Label -> :func:`~rubdiag.signal.order_track` DataFrame holding ``order``. Each
        track's peak is circled and annotated with its amplitude and speed in a row of its
        own above the curves.
    linear : tuple (rpm, z), optional
        Speeds (rpm) and complex amplitudes ``z`` (unit of the tracks, same phase
        convention: module docstring) of the linear response, drawn dashed; for a
        simulated run ``(rpm, rubdiag.runs._runup.linear_response(run, point, rpm))``.
    critical_rpm : float or sequence of float, optional
        Critical speed(s), thin vertical lines on both panels.
    contact_rpm : dict, optional
        Label -> ``(first_rpm, last_rpm)``, the speeds where a track's contact began and
        ended (simulated runs: ``first_contact_rpm``, ``last_contact_rpm`` of
        :func:`rubdiag.runs._runup.runup_summary`); drawn as a bar in the track's colour
        along the bottom of the amplitude panel, labelled with both speeds. NaN: none.
    order : float
        The order shown (1: the unbalance response).
    unit, scale
        Amplitude unit and the factor that turns the tracks into it (default m to µm).
    title : str, optional
    fig : matplotlib.figure.Figure, optional
        An empty figure to draw both panels on; default a new 8.5 × 7 in one.

    Returns
    -------
    matplotlib.figure.Figure
        Amplitude above, phase θ below (degrees, unwrapped; whole turns chosen to match
        the linear response, else the first track, whose value at its lowest speed lies
        within ±180°).
    """
    fig, (ax_a, ax_p) = figure_axes((8.5, 7.0), 0.9, 0.25, 0.6, 0.95, fig, nrows=2, sharex=True,
                                gridspec_kw=dict(height_ratios=(3, 2), hspace=0.07))
    ref, highest, peaks = None, 0.0, []
    if linear is not None:
        rpm_l, z_l = np.asarray(linear[0], dtype=float), np.asarray(linear[1]) * scale
        ax_a.plot(rpm_l, np.abs(z_l), gid="linear", label="linear unbalance response",
                  **_LINEAR)
        ref = (rpm_l, _aligned(rpm_l, _unwrapped_deg(z_l)))
        ax_p.plot(*ref, gid="linear", **_LINEAR)
        highest = float(np.nanmax(np.abs(z_l)))
    for i, (name, df) in enumerate(tracks.items()):
        rpm, z = _vector(df, order, name)
        z = z * scale
        style = _sweep(rpm, i)
        ax_a.plot(rpm, np.abs(z), label=name, gid=f"track {name}", **style)
        phase = _aligned(rpm, _unwrapped_deg(z), ref)
        ref = (rpm, phase) if ref is None else ref
        ax_p.plot(rpm, phase, gid=f"track {name}", **style)
        j = int(np.nanargmax(np.abs(z)))
        peaks.append((name, rpm[j], abs(z[j]), style["color"]))
        highest = max(highest, abs(z[j]))
    # one row per annotated peak above the highest curve, the peak circled, a dotted riser
    rows = 0.075 * len(peaks)
    ax_a.set_ylim(0.0, highest * 1.04 / (1.0 - rows - 0.03))
    lo, hi = ax_a.get_xlim()
    for i, (name, r, a, colour) in enumerate(peaks):
        y_text = 1.0 - 0.03 - 0.075 * (i + 0.5)
        ax_a.plot(r, a, "o", ms=10, mfc="none", mec=colour, mew=1.6, gid=f"peak {name}")
        side = (r - lo) / (hi - lo)
        ax_a.annotate(f"{name}: peak {_amount(a)} {unit} at {r:.0f} rpm", (r, a),
                      xytext=(r, y_text), textcoords=ax_a.get_xaxis_transform(),
                      ha="left" if side < 0.3 else "right" if side > 0.7 else "center",
                      va="center", color=colour, fontsize="small", gid=f"peak {name}",
                      bbox=_BOX,
                      arrowprops=dict(arrowstyle="-", ls=":", color=colour, lw=0.9,
                                      shrinkA=2, shrinkB=6))
    _mark_critical((ax_a, ax_p), critical_rpm)
    _contact_bars(ax_a, tracks, contact_rpm)
    for c in criticals(critical_rpm):
        ax_p.text(c, 0.96, f" critical {c:.0f} rpm", transform=ax_p.get_xaxis_transform(),
                  ha="left", va="top", fontsize="small", color="0.3")
    ax_a.set(ylabel=f"{order:g}× amplitude ({unit})")
    ax_p.set(xlabel="speed (rpm)", ylabel=f"{order:g}× phase θ (deg)")
    _phase_ticks(ax_p, *ax_p.get_ylim())
    ax_a.set_title(title or f"Bode plot, {order:g}×", pad=26)
    for ax in (ax_a, ax_p):
        ax.grid(alpha=0.3)
    round_ticks(ax_a)
    handles, labels = ax_a.get_legend_handles_labels()
    ax_a.legend(handles, labels, loc="lower center", bbox_to_anchor=(0.5, 1.0), ncols=4,
                fontsize="small", frameon=False)
    return fig


def polar_figure(tracks: dict, linear=None, critical_rpm=None, order: float = 1,
                 n_labels: int = 5, unit: str = "µm", scale: float = 1e6,
                 title: str | None = None, *, ax=None):
    """The order's vector ``A e^{iθ}`` in the complex plane, tracks overlaid (polar plot).

    Parameters
    ----------
    tracks, linear, order, unit, scale
        As for :func:`bode_figure`. Each track ends in an arrowhead (the way it was run)
        and is labelled with its speed (rpm) at about ``n_labels`` round speeds; the
        labels of the second and fourth track sit inside the curve, the others outside.
    critical_rpm : float or sequence of float, optional
        Marked by a diamond on the linear response, or on each track without one
        (interpolated between bins).
    n_labels : int
    title : str, optional
    ax : matplotlib.axes.Axes, optional
        Axes to draw on; default a new 7 × 7.6 in figure.

    Returns
    -------
    matplotlib.figure.Figure
        ``A cos θ`` across, ``A sin θ`` upwards, equal scales.
    """
    fig, ax = (ax.figure, ax) if ax is not None else figure_axes((7.0, 7.6), 0.95, 0.3, 1.25, 0.5)
    ax.axhline(0.0, color="0.6", lw=0.8)
    ax.axvline(0.0, color="0.6", lw=0.8)
    critical = criticals(critical_rpm)
    marked = []
    if linear is not None:
        rpm_l, z_l = np.asarray(linear[0], dtype=float), np.asarray(linear[1]) * scale
        ax.plot(z_l.real, z_l.imag, gid="linear", label="linear unbalance response",
                **_LINEAR)
        marked.append(_at(rpm_l, z_l, critical))
    for i, (name, df) in enumerate(tracks.items()):
        rpm, z = _vector(df, order, name)
        z = z * scale
        style = _sweep(rpm, i)
        style.update(marker="")
        ax.plot(z.real, z.imag, label=name, gid=f"track {name}", **style)
        ax.annotate("", (z[-1].real, z[-1].imag), xytext=(z[-2].real, z[-2].imag),
                    arrowprops=dict(arrowstyle="-|>", color=style["color"], lw=1.4,
                                    mutation_scale=16, shrinkA=0, shrinkB=0))
        ticks = MaxNLocator(n_labels, steps=ROUND_STEPS).tick_values(rpm.min(), rpm.max())
        ticks = ticks[(ticks >= rpm.min()) & (ticks <= rpm.max())]
        at = _at(rpm, z, ticks)
        ax.plot(at.real, at.imag, "o", ms=5, color=style["color"], ls="none",
                gid=f"speeds {name}")
        # labels 14 pt off the curve, along the line from the origin: out, or in (odd i)
        out = np.exp(1j * np.angle(at)) * (-14.0 if i % 2 else 14.0)
        for r, p, u in zip(ticks, at, out, strict=True):
            ax.annotate(f"{r:.0f}", (p.real, p.imag), textcoords="offset points",
                        xytext=(u.real, u.imag), ha="center", va="center",
                        fontsize="small", color=style["color"], bbox=_BOX)
        if linear is None:
            marked.append(_at(rpm, z, critical))
    if critical.size and marked:
        marked = np.concatenate(marked)
        label = "critical speed " + ", ".join(f"{c:.0f}" for c in critical) + " rpm"
        ax.plot(marked.real, marked.imag, "D", ms=8, mfc="none", mec="k", mew=1.4,
                gid="critical", label=label, ls="none")
    ax.set_aspect("equal", adjustable="datalim")
    ax.set(xlabel=f"A cos θ ({unit})", ylabel=f"A sin θ ({unit})")
    ax.set_title(title or f"Polar plot, {order:g}× (labels: speed in rpm)")
    ax.grid(alpha=0.3)
    round_ticks(ax, 7, 7)
    ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.09), ncols=2, fontsize="small",
              frameon=False)
    return fig


def rub_orders_figure(tracks: dict, orders=RUB_ORDERS, critical_rpm=None, contact_rpm=None,
                      unit: str = "µm", scale: float = 1e6, title: str = "Rub orders",
                      revs_per_bin: int | None = None, *, fig=None):
    """Amplitudes of the orders a rub excites against speed, one panel per order, tracks
    overlaid: a rub begins where they rise from their floor.

    Where a track's 1× changes within a bin (near a critical speed), the order tracking
    itself spreads it onto the orders beside it — about 1 % of 1× at 0.5× and 1.5× with
    4-revolution bins on a 300 rpm/s run-up, without any contact. Each track's leakage
    level (:func:`~rubdiag.signal._leakage.tracking_leakage`) is drawn dashed in its colour
    (gid ``"leakage <label>"``): an order on its dashed line is leakage, not rub.

    Parameters
    ----------
    tracks : dict
        Label -> :func:`~rubdiag.signal.order_track` DataFrame holding every order (and 1×
        for the leakage level).
    orders : sequence of float
        One panel each, top to bottom; log amplitude axes shared by all panels.
    critical_rpm, contact_rpm, unit, scale, title
        As for :func:`bode_figure` (the contact bars along the top panel).
    revs_per_bin : int, optional
        The tracks' bin length in revolutions (default: each track's ``attrs``, as
        :func:`~rubdiag.signal.order_track` sets them; unknown: no leakage level).
    fig : matplotlib.figure.Figure, optional
        An empty figure to draw the panels on; default a new one, 8.5 in wide.

    Returns
    -------
    matplotlib.figure.Figure
    """
    n = len(orders)
    fig, axes = figure_axes((8.5, 1.7 * n + 1.6), 0.9, 0.25, 0.6, 1.0, fig, nrows=n, sharex=True,
                        sharey=True, squeeze=False, gridspec_kw=dict(hspace=0.08))
    axes = axes[:, 0]
    leaks = {name: _leakage(df, orders, revs_per_bin) for name, df in tracks.items()}
    for ax, k in zip(axes, orders, strict=True):
        for i, (name, df) in enumerate(tracks.items()):
            rpm, z = _vector(df, k, name)
            amp = np.abs(z) * scale
            ax.semilogy(rpm, np.where(amp > 0, amp, np.nan), label=name,
                        gid=f"track {name}", **_sweep(rpm, i))
            if leaks[name] is not None:
                leak = leaks[name][f"amp_{order_label(k)}"].to_numpy() * scale
                ax.semilogy(rpm, np.where(leak > 0, leak, np.nan), gid=f"leakage {name}",
                            color=COLOURS[i % len(COLOURS)], **_LEAKAGE)
        ax.set_ylabel(f"{k:g}× ({unit})")
        ax.grid(alpha=0.3)
        log_labels(ax.yaxis)
    _mark_critical(axes, critical_rpm)
    _contact_bars(axes[0], tracks, contact_rpm)
    axes[-1].set_xlabel("speed (rpm)")
    round_ticks(axes[-1], 8, None)
    axes[0].set_title(title, pad=26)
    handles, labels = axes[0].get_legend_handles_labels()
    bins = {int(leak.attrs["revs_per_bin"]) for leak in leaks.values() if leak is not None}
    if bins:
        handles.append(Line2D([], [], color="0.3", **_LEAKAGE))
        labels.append(f"1× leakage of the tracking ({'/'.join(map(str, sorted(bins)))}-rev "
                      "bins): not rub")
    axes[0].legend(handles, labels, loc="lower center", bbox_to_anchor=(0.5, 1.0), ncols=5,
                   fontsize="small", frameon=False)
    return fig


def _leakage(df, orders, revs_per_bin):
    """The track's leakage at ``orders`` (:func:`tracking_leakage`), or None where its bin
    length or 1× is not known."""
    n_rev = revs_per_bin if revs_per_bin is not None else df.attrs.get("revs_per_bin")
    if n_rev is None or not {"amp_1x", "phase_1x_deg"} <= set(df.columns):
        return None
    leak = tracking_leakage(df, int(n_rev), orders,
                            samples_per_rev=df.attrs.get("samples_per_rev", 64),
                            window=df.attrs.get("window", "hann"))
    leak.attrs["revs_per_bin"] = int(n_rev)
    return leak


# --- a run's figures ---------------------------------------------------------------------

def _slug(label: str) -> str:
    return re.sub(r"[^0-9a-zA-Z]+", "_", label).strip("_").lower()


def runup_figures(tracks: dict, *, linear=None, critical_rpm=None, contact_rpm=None,
                  waterfalls=None, order_maps=None, unit: str = "µm",
                  scale: float = 1e6) -> dict:
    """All figures of a set of sweeps, name -> Figure.

    Parameters
    ----------
    tracks, linear, critical_rpm, contact_rpm, unit, scale
        As for :func:`bode_figure`. ``"bode"`` and ``"polar"`` show 1×; ``"rub_orders"``
        the ``RUB_ORDERS`` that every track holds (none: no such figure).
    waterfalls : dict, optional
        Label -> ``(f_hz, rpm, amplitude)`` (:func:`rubdiag.signal._waterfall`): one
        ``"waterfall_<label>"`` each.
    order_maps : dict, optional
        Label -> ``(orders, rpm, amplitude)`` (:func:`rubdiag.signal.rpm_order_map`): one
        ``"order_map_<label>"`` each.

    Returns
    -------
    dict of str to matplotlib.figure.Figure
        ``"bode"``, ``"polar"``, ``"rub_orders"`` (when drawn), then the waterfalls and
        order maps (labels lower-cased, non-alphanumerics as ``_``).

    See Also
    --------
    save_runup_figures : Draw and write them all.
    """
    common = dict(critical_rpm=critical_rpm, unit=unit, scale=scale)
    figures = {"bode": bode_figure(tracks, linear, contact_rpm=contact_rpm, **common),
               "polar": polar_figure(tracks, linear, **common)}
    rub = [k for k in RUB_ORDERS
           if all(f"amp_{order_label(k)}" in df for df in tracks.values())]
    if rub:
        figures["rub_orders"] = rub_orders_figure(tracks, rub, contact_rpm=contact_rpm,
                                                  **common)
    for name, (f_hz, rpm, amp) in (waterfalls or {}).items():
        figures[f"waterfall_{_slug(name)}"] = waterfall_figure(
            f_hz, rpm, amp, title=f"Waterfall, {name}", **common)
    for name, (orders, rpm, amp) in (order_maps or {}).items():
        figures[f"order_map_{_slug(name)}"] = order_map_figure(
            orders, rpm, amp, title=f"Order map, {name}", **common)
    return figures


def save_runup_figures(tracks: dict, out_dir: str | Path, stem: str = "runup",
                       **options) -> list[Path]:
    """Write :func:`runup_figures` as ``out_dir/<stem>_<name>.png`` at ``DPI``.

    The order of the first two arguments is that of every saving function (what is drawn,
    then where); the earlier order, ``(out_dir, tracks)``, is still understood.

    Parameters
    ----------
    tracks : dict
        Label -> :func:`~rubdiag.signal.order_track` DataFrame, as for
        :func:`runup_figures`.
    out_dir : str or Path
        The folder to write to (made when missing).
    stem : str
        The files' common name before ``_<name>.png``.
    **options
        Those of :func:`runup_figures` (``linear``, ``critical_rpm``, ``contact_rpm``,
        ``waterfalls``, ``order_maps``, ``unit``, ``scale``).

    Returns
    -------
    list of Path
        The written files, in the order of :func:`runup_figures`.
    """
    if isinstance(tracks, str | os.PathLike) and isinstance(out_dir, dict):
        tracks, out_dir = out_dir, tracks
    out_dir = Path(out_dir)
    return [save_figure(fig, out_dir / f"{stem}_{name}.png", dpi=DPI)
            for name, fig in runup_figures(tracks, **options).items()]
