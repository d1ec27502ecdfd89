"""The full spectrum and the orbit of a pair of orthogonal probes in one plane.

A rotor's motion in a plane is an orbit: two probes at right angles see its two components.
The **full spectrum** tells forward precession (the orbit turning with the shaft) from
reverse precession at each frequency, which one probe cannot: rub drives reverse
components, dry whip is reverse at a natural frequency, oil whirl forward.

Convention: with ``y`` and ``z`` the displacements along two orthogonal probe axes and the
shaft turning from y towards z (``rotation = +1``; ``-1`` when it turns from z towards y),
the complex signal ``s = y + i z`` (``y − i z`` for ``rotation = -1``) holds forward
precession at positive frequencies and reverse precession at negative ones. A circle
``y = A cos ωt, z = A sin ωt`` is forward of amplitude A; an ellipse of semi-axes a and b
(``y = a cos ωt, z = b sin ωt``) is forward (a + b)/2 plus reverse (a − b)/2.

* :func:`full_spectrum` — the whole full spectrum ``(f, amplitude)``, f from −fs/2 to
  fs/2 (negative: reverse), a Hann-windowed periodogram of the complex signal;
* :func:`full_spectrum_lines` — forward and reverse amplitudes at chosen orders of the
  running speed, by a lock-in over the record's whole revolutions (exact for lines at those
  orders);
* :func:`orbit_features` — both as one row: ``fwd_<order>``, ``rev_<order>`` at the half and
  third orders the feature table searches, and the orbit measures;
  :func:`orbit_features_by_pair` — the rows of several pairs of one record, sharing its lock-in
  references (the costly part: complex exponentials of every order at every sample);
* :func:`orbit_measures` — the 1× ellipticity and precession, the reverse share of the
  non-1× motion, and the orbit's shape: its flattening, its clearance-limited radius and
  the share of time it spends near that radius (definitions in the function's docstring).

Units: the probes' (m, µm …); speed in Hz of rotation; fs in Hz.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from rubdiag import _check
from rubdiag._tolerances import ON_LEVEL

__all__ = [
    "ROTATIONS",
    "OrbitMeasures",
    "full_spectrum",
    "full_spectrum_lines",
    "orbit_features",
    "orbit_features_by_pair",
    "orbit_measures",
]

#: the senses of rotation: +1 from y towards z, -1 from z towards y
ROTATIONS = (1, -1)
#: the orbit's "near the clearance-limited radius" band, as a share of that radius
NEAR_RADIUS = 0.05
#: the percentile of the radius taken as the clearance-limited radius
RADIUS_PERCENTILE = 99.0


def _complex(y, z, rotation: int) -> np.ndarray:
    y = np.asarray(y, dtype=np.float64)
    z = np.asarray(z, dtype=np.float64)
    if y.ndim != 1 or y.shape != z.shape or y.size < 2:
        raise ValueError(f"y and z have shapes {y.shape} and {z.shape} (allowed: two 1-D "
                         "records of the same length, at least 2 samples)")
    if not (np.all(np.isfinite(y)) and np.all(np.isfinite(z))):
        raise ValueError("y and z hold NaN or inf (allowed: finite samples)")
    if rotation not in ROTATIONS:
        raise _check.out_of_range("rotation", rotation, "+1 (from y towards z) or -1")
    return y + 1j * rotation * z


def _whole_revolutions(n: int, fs: float, speed_hz: float) -> int:
    """The number of samples in the record's whole revolutions, a multiple of 6 of them when
    it holds 6 or more (so that the half and third orders are orthogonal to the harmonics
    and to each other: no line leaks into another's lock-in); at least one needed."""
    per_rev = fs / speed_hz
    revs = int(np.floor(n / per_rev + ON_LEVEL))
    if revs >= 6:
        revs -= revs % 6
    if revs < 1:
        raise ValueError(f"the record holds {n / per_rev:.3g} revolutions at {speed_hz:g} Hz "
                         "(allowed: at least 1)")
    return round(revs * per_rev)


def full_spectrum(y, z, fs: float, *, rotation: int = 1) -> tuple[np.ndarray, np.ndarray]:
    """The full spectrum of an x–y probe pair: forward and reverse precession apart.

    The pair is read as one complex signal ``y + i z`` (the shaft turning from y towards z
    for ``rotation=1``), so a positive frequency is forward precession and a negative one
    reverse. Amplitudes are peak amplitudes (Hann window, its coherent gain divided out: a
    forward circle of radius A on a bin reads A at its frequency), the mean removed.

    Parameters
    ----------
    y, z : array_like
        The two probes' signals, sampled together (their unit).
    fs : float
        Sampling frequency (Hz).
    rotation : {1, -1}
        1 when the shaft turns from y towards z, -1 when from z towards y.

    Returns
    -------
    f : numpy.ndarray
        Frequencies (Hz), ascending from −fs/2 (reverse) to fs/2 (forward).
    amplitude : numpy.ndarray
        Peak amplitude of each precession line (the probes' unit).

    See Also
    --------
    orbit_features : The lines at the running speed's orders, and the orbit's measures.

    Examples
    --------
    A forward circle of 3 µm at 25 Hz reads 3 µm at +25 Hz and nothing at −25 Hz:

    >>> import numpy as np
    >>> fs = 1000.0
    >>> t = np.arange(2000) / fs
    >>> y, z = 3e-6 * np.cos(2 * np.pi * 25 * t), 3e-6 * np.sin(2 * np.pi * 25 * t)
    >>> f, a = full_spectrum(y, z, fs)
    >>> print(f"{a[f == 25.0][0] * 1e6:.2f} um forward, {a[f == -25.0][0] * 1e6:.2f} um reverse")
    3.00 um forward, 0.00 um reverse
    """
    fs = _check.positive("fs", fs, unit="Hz")
    s = _complex(y, z, rotation)
    window = np.hanning(s.size)
    spectrum = np.fft.fftshift(np.fft.fft((s - s.mean()) * window)) / window.sum()
    return np.fft.fftshift(np.fft.fftfreq(s.size, 1.0 / fs)), np.abs(spectrum)


def full_spectrum_lines(y, z, fs: float, speed_hz: float, orders, *,
                        rotation: int = 1) -> tuple[np.ndarray, np.ndarray]:
    """Forward and reverse amplitudes (the probes' unit) at each order ``k`` of the running
    speed ``speed_hz`` (Hz): ``|mean(s e^{∓ikΩt})|`` over the record's whole revolutions (a
    multiple of 6 from 6 on) of the complex signal ``s`` (module docstring), its mean
    removed. Returns ``(forward,
    reverse)``, arrays over ``orders``. A line at one of the orders is measured exactly
    whatever its phase; a line at another frequency leaks in as a sinc over the window."""
    fs = _check.positive("fs", fs, unit="Hz")
    speed_hz = _check.positive("speed_hz", speed_hz, unit="Hz")
    s = _complex(y, z, rotation)
    return _lines(s, _references(s.size, fs, speed_hz, orders))


def _references(size: int, fs: float, speed_hz: float, orders) -> np.ndarray:
    """The lock-in references ``e^{-ikΩt}`` (rows: the orders k) over the whole revolutions
    of a record of ``size`` samples: what :func:`full_spectrum_lines` costs (a complex
    exponential per order and sample), so that the pairs of one record share them."""
    n = min(_whole_revolutions(size, fs, speed_hz), size)
    phase = 2.0 * np.pi * speed_hz * np.arange(n) / fs
    k = np.atleast_1d(np.asarray(orders, dtype=np.float64))
    return np.exp(-1j * np.outer(k, phase))


def _lines(s: np.ndarray, turn: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``(forward, reverse)`` of the complex signal ``s`` at the orders of the references
    ``turn`` (:func:`_references`). The reverse lock-in ``conj(turn) @ s`` is taken as
    ``turn @ conj(s)``: the same bits (conjugation only flips signs), without conjugating
    the references."""
    n = turn.shape[1]
    s = s[:n] - s[:n].mean()
    return np.abs(turn @ s) / n, np.abs(turn @ np.conj(s)) / n


@dataclass(frozen=True)
class OrbitMeasures:
    """What an analyst reads off an orbit (definitions in :func:`orbit_measures`)."""

    forward_1x: float
    reverse_1x: float
    ellipticity_1x: float
    precession_1x: int
    reverse_share: float
    flattening: float
    limit_radius: float
    near_limit_share: float


def orbit_measures(y, z, fs: float, speed_hz: float, orders, *,
                   rotation: int = 1) -> OrbitMeasures:
    """The orbit's measures, for the probes ``y``, ``z`` (module docstring) at the running
    speed ``speed_hz`` (Hz), with the non-1× motion counted at ``orders`` (1 among them or
    not: it is left out of that count):

    ``forward_1x``, ``reverse_1x``
        The 1× forward and reverse amplitudes (:func:`full_spectrum_lines`).
    ``ellipticity_1x``
        ``reverse_1x / forward_1x``: 0 for a forward circle, 1 for a line, above 1 for a
        reverse orbit (NaN without 1×).
    ``precession_1x``
        +1 when the 1× orbit turns with the shaft (forward larger), -1 against it.
    ``reverse_share``
        The reverse share of the non-1× motion: Σ reverse² / Σ (forward² + reverse²) over
        the other ``orders`` (NaN when they hold no motion).
    ``flattening``
        ``1 − r_min / r_max`` of the orbit's radius about its mean over the record: 0 for a
        circle, 1 for a line through the centre.
    ``limit_radius``
        The clearance-limited radius estimate: the :data:`RADIUS_PERCENTILE` th percentile
        of the radius (an orbit held by a clearance spends its time at it; the percentile
        ignores a few outliers).
    ``near_limit_share``
        The share of samples whose radius lies within :data:`NEAR_RADIUS` of
        ``limit_radius`` (a clipped orbit sits there; a circle all the time, an ellipse
        rarely).
    """
    k = np.atleast_1d(np.asarray(orders, dtype=np.float64))
    forward, reverse = full_spectrum_lines(y, z, fs, speed_hz, np.r_[1.0, k],
                                           rotation=rotation)
    return _orbit(_complex(y, z, rotation), k, forward, reverse)


def _orbit(s: np.ndarray, k: np.ndarray, forward: np.ndarray,
           reverse: np.ndarray) -> OrbitMeasures:
    """:func:`orbit_measures` of the complex signal ``s`` from its lines at 1× then at the
    orders ``k`` (``forward``, ``reverse``: 1 + len(k) values)."""
    f1, r1 = float(forward[0]), float(reverse[0])
    others = np.abs(k - 1.0) > ON_LEVEL
    motion = float(np.sum(forward[1:][others] ** 2 + reverse[1:][others] ** 2))
    radius = np.abs(s - s.mean())
    r_max = float(radius.max())
    limit = float(np.percentile(radius, RADIUS_PERCENTILE))
    return OrbitMeasures(
        forward_1x=f1, reverse_1x=r1,
        ellipticity_1x=r1 / f1 if f1 > 0.0 else float("nan"),
        precession_1x=1 if f1 >= r1 else -1,
        reverse_share=(float(np.sum(reverse[1:][others] ** 2)) / motion if motion > 0.0
                       else float("nan")),
        flattening=1.0 - float(radius.min()) / r_max if r_max > 0.0 else 0.0,
        limit_radius=limit,
        near_limit_share=float(np.mean(np.abs(radius - limit) <= NEAR_RADIUS * limit)),
    )


def orbit_features(y, z, fs: float, speed_rpm: float, *, rotation: int = 1) -> dict:
    """Full-spectrum and orbit features of an x–y probe pair at its running speed.

    Parameters
    ----------
    y, z : array_like
        The two probes' signals, sampled together (their unit); the shaft turns from y
        towards z for ``rotation=1``.
    fs : float
        Sampling frequency (Hz).
    speed_rpm : float
        Running speed (rpm).
    rotation : {1, -1}
        1 when the shaft turns from y towards z, -1 when from z towards y.

    Returns
    -------
    dict
        ``fwd_<order>`` and ``rev_<order>`` (the probes' unit): the forward and reverse lines
        at the half orders 0.5× … 8× and the third orders the feature table searches
        (labels as :func:`order_label`), measured over whole revolutions; then the orbit's
        measures over those orders (:func:`orbit_measures`: ``reverse_share``, ``flattening``,
        ``limit_radius``, ``near_limit_share`` …).

    See Also
    --------
    full_spectrum : The whole full spectrum of the pair.
    signal_features : The features of each probe alone.

    Examples
    --------
    A forward 1× of 1.0 with a reverse 2× of 0.2 (a backward-whirling 2×), at 1500 rpm:

    >>> import numpy as np
    >>> fs, speed_hz = 2000.0, 25.0
    >>> w = 2 * np.pi * speed_hz * np.arange(8000) / fs
    >>> y = np.cos(w) + 0.2 * np.cos(2 * w)
    >>> z = np.sin(w) - 0.2 * np.sin(2 * w)
    >>> row = orbit_features(y, z, fs, 60 * speed_hz)
    >>> print(f"{row['fwd_1x']:.2f} {row['rev_1x']:.2f} {row['rev_2x']:.2f}")
    1.00 0.00 0.20
    """
    return orbit_features_by_pair({"pair": (y, z)}, fs, speed_rpm, rotation=rotation)["pair"]


def orbit_features_by_pair(pairs, fs: float, speed_rpm: float, *, rotation: int = 1) -> dict:
    """:func:`orbit_features` of every pair of ``pairs`` (name -> ``(y, z)``), as
    ``{name: row}``: the pairs of one record (of equal length) share one set of lock-in
    references, the costly part; the rows are those of :func:`orbit_features`, bit for bit."""
    from rubdiag.signal._orders import HALF_ORDERS, THIRD_ORDERS, order_label

    fs = _check.positive("fs", fs, unit="Hz")
    speed_hz = _check.positive("speed_rpm", speed_rpm, unit="rpm") / 60.0
    orders = np.array(sorted(HALF_ORDERS + THIRD_ORDERS))
    labels = [order_label(k) for k in orders]
    rows, turns = {}, {}
    for name, (y, z) in pairs.items():
        s = _complex(y, z, rotation)
        if s.size not in turns:     # 1× first, for the orbit; then the orders
            turns[s.size] = _references(s.size, fs, speed_hz, np.r_[1.0, orders])
        forward, reverse = _lines(s, turns[s.size])
        row = {}
        for label, f, r in zip(labels, forward[1:], reverse[1:], strict=True):
            row[f"fwd_{label}"] = float(f)
            row[f"rev_{label}"] = float(r)
        measures = _orbit(s, orders, forward, reverse)
        row.update({n: getattr(measures, n) for n in OrbitMeasures.__dataclass_fields__})
        rows[name] = row
    return rows
