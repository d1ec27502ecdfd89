"""Waterfall: short-time peak-amplitude spectra of a record, with the speed of each segment.

The time-frequency view of a run-up or coast-down: orders fan out as lines through the origin
of the (speed, frequency) plane, resonances and fixed-frequency tones stand still. The
segments are transformed by :class:`scipy.signal.ShortTimeFFT`; only segments wholly inside
the record are kept (a segment padded with zeros would read low).
"""

from __future__ import annotations

import math

import numpy as np
import scipy.signal

from rubdiag.signal._records import check_fs, check_signals
from rubdiag.signal._spectrum import _segment_params, _window_array
from rubdiag.signal._tacho import check_angle


def waterfall(x, fs: float, nperseg: int, noverlap: int | None = None, window="hann",
              detrend="constant", *, speed_rpm=None, angle=None):
    """Short-time peak-amplitude spectra and the mean speed of each segment.

    Each segment is scaled like :func:`amplitude_spectrum`: a sine of amplitude ``A`` whose
    frequency falls on a bin shows as ``A`` at that bin.

    Parameters
    ----------
    x : array_like
        One signal (1-D) or several (2-D, rows are signals).
    fs : float
        Sampling frequency in Hz.
    nperseg : int
        Samples per segment (resolution ``fs / nperseg`` Hz).
    noverlap : int, optional
        Samples shared by consecutive segments; default ``nperseg // 2``.
    window, detrend
        As for :func:`amplitude_spectrum`.
    speed_rpm : array_like, 1-D, optional
        Running speed in rpm at every sample. Give this or ``angle``.
    angle : array_like, 1-D, optional
        Shaft angle in rad at every sample, strictly increasing (:func:`tacho_angle`).

    Returns
    -------
    f_hz : ndarray
        Frequencies in Hz, ``0 … fs/2``.
    t_s : ndarray
        Centre time of each segment in s (``t = 0`` at the first sample).
    rpm : ndarray
        Mean speed over each segment in rpm.
    amplitude : ndarray
        Peak amplitude, shape ``(f_hz.size, t_s.size)``, or ``(rows, f_hz.size, t_s.size)``
        for 2-D ``x``.
    """
    fs = check_fs(fs)
    X, _ = check_signals(x, "x")
    n = X.shape[1]
    nperseg, noverlap, _ = _segment_params(n, nperseg, noverlap, None)
    hop = nperseg - noverlap
    sft = scipy.signal.ShortTimeFFT(_window_array(window, nperseg), hop, fs,
                                    fft_mode="onesided2X", scale_to="magnitude")
    # Slice p covers samples p·hop − m_num_mid … + nperseg − 1: keep those inside the record.
    p0 = math.ceil(sft.m_num_mid / hop)
    p1 = (n - nperseg + sft.m_num_mid) // hop + 1
    start = np.arange(p0, p1) * hop - sft.m_num_mid
    rpm = _segment_speed(speed_rpm, angle, n, fs, start, nperseg)
    detr = None if detrend is False else detrend
    amp = np.abs(sft.stft_detrend(X, detr, p0, p1, axis=-1))
    return sft.f, sft.t(n, p0, p1), rpm, (amp[0] if np.ndim(x) == 1 else amp)


def _segment_speed(speed_rpm, angle, n: int, fs: float, start: np.ndarray,
                   nperseg: int) -> np.ndarray:
    """Mean speed (rpm) over segments of ``nperseg`` samples from ``start``."""
    if (speed_rpm is None) == (angle is None):
        raise ValueError("give the speed as speed_rpm or as angle (allowed: exactly one)")
    if angle is not None:
        phi = check_angle(angle, n)
        dphi = phi[start + nperseg - 1] - phi[start]
        return 60.0 * dphi * fs / (2.0 * np.pi * (nperseg - 1))
    rpm, _ = check_signals(speed_rpm, "speed_rpm")
    if rpm.shape != (1, n):
        raise ValueError(f"speed_rpm has shape {np.shape(speed_rpm)} (allowed: ({n},), one "
                         "speed per sample of x)")
    total = np.concatenate(([0.0], np.cumsum(rpm[0])))
    return (total[start + nperseg] - total[start]) / nperseg
