"""The faults that look like rub, beside rub: one row per run (waveform, orbit, spectrum).

Each row shows a shaft point's displacement in one direction over its last revolutions, its
orbit, and the amplitude spectrum of the analysis window against the order of the running
speed, with the lines the fault's model predicts marked (``PREDICTED``): what an analyst
compares when the question is "rub, or something that also makes harmonics?".

Each figure function draws on the figure ``fig`` when given, else on one of its own, and
returns it (:func:`rubdiag.plotting.save_figure` writes it).
"""

from __future__ import annotations

import numpy as np

from rubdiag._figures import new_figure

#: the orders each fault's reference predicts at the shaft (rub: the study's 1×, 2×, 4× and
#: half orders; a breathing crack: 2× and 3× (Gasch 1993, Mayes & Davies 1984); a misaligned
#: coupling: 2× (and 4×, weak); a loose pedestal: ½× or ⅓× and their multiples (Muszynska &
#: Goldman 1995); oil whirl: just under ½× (whip: at the first natural frequency, an order
#: that depends on the speed: ``faults_figure(predicted=...)``))
PREDICTED = {"rub": (1.0, 1.5, 2.0, 3.5, 4.0), "crack": (1.0, 2.0, 3.0),
             "misalignment": (1.0, 2.0, 4.0),
             "looseness": (1 / 3, 0.5, 2 / 3, 1.0, 1.5, 2.0, 3.0), "none": (1.0,),
             "whirl": (0.5, 1.0)}
REVOLUTIONS = 4     # the waveform panel's length
MAX_ORDER = 5.0
#: The log-scale spectrum's floor, relative to its peak: zero bins would leave holes in the
#: line; 1e-12 lies far below the axis (5 decades shown).
_LOG_FLOOR = 1e-12


def _window_signal(result, point: str):
    t = result.t[result.window]
    return t, {d: result.displacement(f"{point} {d}", True) for d in "yz"}


def _spectrum(t, x, speed_rad_s: float):
    """Orders and peak amplitudes (Hann window, coherent gain divided out)."""
    from rubdiag.signal import amplitude_spectrum

    fs = 1.0 / (t[1] - t[0])
    f, amp = amplitude_spectrum(x, fs)
    return f / (speed_rad_s / (2 * np.pi)), amp


def faults_figure(results: dict, point: str = "shaft 11", kinds: dict | None = None,
                  direction: str = "y", predicted: dict | None = None, *, fig=None):
    """Rub beside the faults that look like it: one row of panels per simulated run.

    Each row shows the last :data:`REVOLUTIONS` (4) revolutions of ``point``'s displacement
    along ``direction``, its orbit over the analysis window, and its amplitude spectrum
    along ``direction`` against the order of the running speed (0.2× to 5×), with the lines
    the fault's model predicts marked. Displacements and amplitudes in µm; the waveform
    and the orbit about their means.

    Parameters
    ----------
    results : dict of str to SimulationResult
        The runs by the name their row is titled with.
    point : str
        The node whose displacement is shown (a DOF map node label such as
        ``"shaft 11"``).
    kinds : dict of str to str, optional
        Name -> a key of :data:`PREDICTED` (``"rub"``, ``"crack"``, ``"misalignment"``,
        ``"looseness"``, ``"whirl"``, ``"none"``): whose predicted lines a run's spectrum
        marks. Default: the run's name itself (no lines when it is no such key).
    direction : {"y", "z"}
        The direction of the waveform and the spectrum.
    predicted : dict of str to sequence of float, optional
        Name -> orders to mark in place of :data:`PREDICTED`'s, for a line that depends on
        the run (a whip's, at the first natural frequency).
    fig : matplotlib.figure.Figure, optional
        An empty figure to draw the rows of panels on; default a new one, 13 in wide and
        2.9 in per run.

    Returns
    -------
    matplotlib.figure.Figure
        The figure, one row of three panels (waveform, orbit, spectrum) per run.

    See Also
    --------
    full_spectrum_figure : Forward and reverse precession apart, for one probe pair.
    save_figure : Write the figure.
    """
    kinds = {} if kinds is None else kinds
    predicted_orders = {} if predicted is None else predicted
    n = len(results)
    fig = new_figure(figsize=(13, 2.9 * n)) if fig is None else fig
    axes = fig.subplots(n, 3, squeeze=False, gridspec_kw={"width_ratios": (2.2, 1, 2.2)})
    for row, (name, result) in zip(axes, results.items(), strict=True):
        t, x = _window_signal(result, point)
        y, z, u = x["y"], x["z"], x[direction]
        speed = result.run.speed_rad_s
        period = 2 * np.pi / speed
        last = t >= t[-1] - REVOLUTIONS * period
        wave, orbit, spec = row
        wave.plot(t[last], 1e6 * (u[last] - u.mean()), lw=0.9, color="C0")
        wave.set(ylabel=f"{point} {direction} (µm)", title=f"{name}: {point} {direction}, "
                 f"last {REVOLUTIONS} revolutions at {result.run.speed_rpm:.0f} rpm")
        orbit.plot(1e6 * (y - y.mean()), 1e6 * (z - z.mean()), lw=0.5, color="C0")
        orbit.set(xlabel="y (µm)", ylabel="z (µm)", title="orbit over the window",
                  aspect="equal")
        orders, amp = _spectrum(t, u, speed)
        keep = (orders > 0.2) & (orders <= MAX_ORDER)
        spec.semilogy(orders[keep], 1e6 * amp[keep], lw=0.8, color="C0")
        predicted = (predicted_orders[name] if name in predicted_orders
                     else PREDICTED.get(kinds.get(name, name), ()))
        for k, order in enumerate(predicted):
            spec.axvline(order, color="C3", lw=0.8, ls="--", alpha=0.7,
                         label="lines its model predicts" if k == 0 else None)
        top = float(1e6 * amp[keep].max())
        spec.set(xlim=(0.2, MAX_ORDER), ylim=(top * 1e-5, top * 3),
                 ylabel="amplitude (µm)", title=f"{point} {direction} spectrum")
        if predicted:
            spec.legend(loc="upper right", fontsize="small")
        for ax in row:
            ax.grid(alpha=0.3)
    axes[-1, 0].set_xlabel("time (s)")
    axes[-1, 2].set_xlabel("order (× running speed)")
    fig.tight_layout()
    return fig


def full_spectrum_figure(y, z, fs: float, speed_hz: float, *, rotation: int = 1,
                         clearance=None, title: str = "", max_order: float = 5.0,
                         fig=None):
    """The full spectrum of a probe pair against the order of the running speed, beside the
    orbit.

    The spectrum (:func:`rubdiag.signal.full_spectrum`, log scale) shows reverse precession
    to the left of order 0 and forward to the right; the orbit is drawn about its mean, in
    the probes' unit.

    Parameters
    ----------
    y, z : array_like
        The two probes' signals, sampled together (the same unit, e.g. m).
    fs : float
        Sampling frequency (Hz).
    speed_hz : float
        The running speed (Hz): order 1.
    rotation : {1, -1}
        1 when the shaft turns from y towards z, -1 when from z towards y.
    clearance : float, optional
        A clearance circle's radius about the orbit's mean (the probes' unit); default
        none drawn.
    title : str
        Put before "full spectrum" in the spectrum panel's title.
    max_order : float
        The spectrum panel spans orders -max_order to +max_order.
    fig : matplotlib.figure.Figure, optional
        An empty figure to draw the two panels on; default a new 11 × 3.6 in one.

    Returns
    -------
    matplotlib.figure.Figure
        The figure: the full spectrum on the left, the orbit on the right.

    See Also
    --------
    rubdiag.signal.full_spectrum : The spectrum drawn.
    faults_figure : One probe's spectrum, run beside run.
    """
    from rubdiag.signal import full_spectrum

    f, amp = full_spectrum(y, z, fs, rotation=rotation)
    order = f / speed_hz
    keep = np.abs(order) <= max_order
    fig = new_figure(figsize=(11, 3.6)) if fig is None else fig
    spec, orbit = fig.subplots(1, 2, gridspec_kw={"width_ratios": (2.4, 1)})
    spec.semilogy(order[keep], np.maximum(amp[keep], _LOG_FLOOR * amp.max()), lw=0.8,
                  color="C0")
    spec.axvline(0.0, color="k", lw=0.8)
    top = float(amp[keep].max())
    spec.set(xlim=(-max_order, max_order), ylim=(top * 1e-5, top * 3),
             xlabel="order (× running speed): reverse < 0 < forward",
             ylabel="amplitude", title=f"{title} full spectrum".strip())
    spec.text(0.02, 0.92, "reverse", transform=spec.transAxes, fontsize="small")
    spec.text(0.98, 0.92, "forward", transform=spec.transAxes, fontsize="small",
              ha="right")
    y = np.asarray(y, float) - np.mean(y)
    z = np.asarray(z, float) - np.mean(z)
    orbit.plot(y, z, lw=0.5, color="C0")
    if clearance is not None:
        angle = np.linspace(0.0, 2 * np.pi, 361)
        orbit.plot(clearance * np.cos(angle), clearance * np.sin(angle), "C3--", lw=0.8,
                   label="clearance")
        orbit.legend(loc="upper right", fontsize="small")
    orbit.set(xlabel="y", ylabel="z", aspect="equal", title="orbit")
    for ax in (spec, orbit):
        ax.grid(alpha=0.3)
    fig.tight_layout()
    return fig
