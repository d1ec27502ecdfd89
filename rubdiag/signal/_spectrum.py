"""One-sided peak-amplitude spectra and exact line estimates.

:func:`amplitude_spectrum` is the public door; it and every feature in this package run on one
private engine, :func:`_spectra`, which works on a 2-D array of signals at once (rows are
signals). Exact line estimates come from :class:`_Kernel`: the discrete-time Fourier transform
of the window, tabulated once per window, inverts the ratio of the two largest bins of a line
into the line's offset from the bin, then corrects amplitude (no scalloping loss) and phase.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass

import numpy as np
import scipy.signal

from rubdiag import _check
from rubdiag.signal._records import MIN_SAMPLES, check_fs

# Bins from a line over which its sidelobes are checked against weaker local maxima.
_SIDELOBE_BINS = 16
#: Added per step to the running maximum of the window's ratio curve, so that it increases
#: strictly (it is interpolated inverted): at most 3e-10 over its 257 steps.
_TIE_BREAK = 1e-12
#: A sidelobe counts as rising only by more than the interpolated magnitudes' rounding.
_RISING = 1e-9
# Rows of signals transformed at once: bounds the memory of the batch path (complex bins).
_MAX_BINS_PER_CHUNK = 1 << 22


def amplitude_spectrum(
    x,
    fs: float = 1.0,
    window="hann",
    nperseg: int | None = None,
    noverlap: int | None = None,
    nfft: int | None = None,
    detrend="constant",
    axis: int = -1,
):
    """One-sided peak-amplitude spectrum with window correction.

    A sine of amplitude ``A`` whose frequency falls on a bin shows as ``A`` at that bin,
    whatever the window (the window's coherent gain is divided out). Between bins the value
    falls by the window's scalloping loss (up to 15 % for ``"hann"``); use
    :func:`spectral_lines` for exact line amplitudes and frequencies.

    Parameters
    ----------
    x : array_like
        Signal, in any unit; the amplitude comes out in the same unit.
    fs : float
        Sampling frequency in Hz.
    window : str or tuple or array_like
        Window, as for :func:`scipy.signal.get_window` (periodic), or the window itself
        (length ``nperseg``).
    nperseg : int, optional
        Samples per segment. Default: the whole record (one segment, the finest resolution).
    noverlap : int, optional
        Samples shared by consecutive segments. Default ``nperseg // 2``.
    nfft : int, optional
        FFT length (zero padding); default ``nperseg``.
    detrend : {"constant", "linear", False} or callable
        Removed from each segment before windowing.
    axis : int
        Time axis of ``x``.

    Returns
    -------
    f : ndarray
        Frequencies in Hz, ``0 … fs/2``, spacing ``fs / nfft``.
    amplitude : ndarray
        Peak amplitude per bin (unit of ``x``); with several segments, the RMS average over
        segments. The frequency axis replaces ``axis``.

    Examples
    --------
    >>> import numpy as np
    >>> fs = 1000.0
    >>> t = np.arange(2000) / fs
    >>> f, a = amplitude_spectrum(2.0 * np.sin(2 * np.pi * 50.0 * t), fs)
    >>> round(float(f[np.argmax(a)]), 3), round(float(a.max()), 3)
    (50.0, 2.0)
    """
    fs = check_fs(fs)
    arr = np.asarray(x, dtype=np.float64)
    if arr.ndim == 0:
        raise _check.wrong_type("x", x, "an array of samples, not a scalar")
    if arr.size == 0:
        raise ValueError(f"x is empty (allowed: at least {MIN_SAMPLES} samples)")
    if not np.isfinite(arr).all():
        raise ValueError("x contains NaN or inf")
    moved = np.moveaxis(arr, axis, -1)
    shape = moved.shape
    flat = moved.reshape(-1, shape[-1])
    spec = _spectra(flat, fs, window, nperseg, noverlap, nfft, detrend, phase=False)
    amp = spec.amplitude.reshape(*shape[:-1], -1)
    return spec.f, np.moveaxis(amp, -1, axis)


@dataclass(frozen=True)
class _Spectra:
    """Spectra of a stack of signals (rows), as the feature engine needs them."""

    f: np.ndarray  # (n_bins,) Hz
    amplitude: np.ndarray  # (n_rows, n_bins) peak amplitude, RMS-averaged over segments
    first: np.ndarray | None  # (n_rows, n_bins) complex amplitude of the first segment
    df: float  # bin spacing in Hz (fs / nfft)
    resolution: float  # fs / nperseg, Hz
    nperseg: int
    kernel: _Kernel
    window: np.ndarray  # (nperseg,) the window array
    noverlap: int
    nfft: int
    detrend: object


def _segment_params(n: int, nperseg, noverlap, nfft) -> tuple[int, int, int]:
    nperseg = n if nperseg is None else _check.integer("nperseg", nperseg, lo=MIN_SAMPLES)
    if nperseg > n:
        raise _check.out_of_range("nperseg", nperseg, f"<= {n}, the record's length")
    noverlap = (nperseg // 2 if noverlap is None
                else _check.integer("noverlap", noverlap, lo=0, hi=nperseg - 1))
    nfft = nperseg if nfft is None else _check.integer("nfft", nfft, lo=nperseg)
    return nperseg, noverlap, nfft


def _window_array(window, nperseg: int) -> np.ndarray:
    if isinstance(window, str | tuple):
        try:
            w = scipy.signal.get_window(window, nperseg)
        except ValueError as exc:
            raise ValueError(f"unknown window {window!r}: {exc}") from None
    else:
        w = np.asarray(window, dtype=np.float64)
        if w.shape != (nperseg,):
            raise ValueError(f"the window must have nperseg = {nperseg} samples, got {w.shape}")
    if not np.isfinite(w).all() or w.sum() <= 0.0:
        raise ValueError("the window must be finite with a positive sum")
    return np.ascontiguousarray(w, dtype=np.float64)


def _detrend(seg: np.ndarray, detrend) -> np.ndarray:
    if detrend is False or detrend is None:
        return seg
    if detrend == "constant":
        return seg - seg.mean(axis=-1, keepdims=True)
    if detrend == "linear":
        return scipy.signal.detrend(seg, axis=-1, type="linear")
    if callable(detrend):
        return np.asarray(detrend(seg), dtype=np.float64)
    raise ValueError(f"detrend = {_check.plain(detrend)} is not allowed (allowed: 'constant', "
                     "'linear', False or a callable)")


def _spectra(
    X: np.ndarray,
    fs: float,
    window="hann",
    nperseg=None,
    noverlap=None,
    nfft=None,
    detrend="constant",
    *,
    phase: bool = True,
) -> _Spectra:
    """Amplitude spectra of the rows of ``X`` (n_rows, n_samples), transformed in chunks."""
    n_rows, n = X.shape
    nperseg, noverlap, nfft = _segment_params(n, nperseg, noverlap, nfft)
    w = _window_array(window, nperseg)
    n_seg = 1 + (n - nperseg) // (nperseg - noverlap)
    n_bins = nfft // 2 + 1
    amplitude = np.empty((n_rows, n_bins))
    first = np.empty((n_rows, n_bins), dtype=np.complex128) if phase else None
    chunk = max(1, _MAX_BINS_PER_CHUNK // (n_bins * n_seg))
    for start in range(0, n_rows, chunk):
        seg = _segments(X[start : start + chunk], nperseg, noverlap)
        spec = _segment_spectra(seg, w, nfft, detrend)
        amplitude[start : start + chunk] = _mean_amplitude(spec)
        if phase:
            first[start : start + chunk] = spec[:, 0]
    return _Spectra(
        f=np.arange(n_bins) * (fs / nfft),
        amplitude=amplitude,
        first=first,
        df=fs / nfft,
        resolution=fs / nperseg,
        nperseg=nperseg,
        kernel=_kernel(w.tobytes(), nfft),
        window=w,
        noverlap=noverlap,
        nfft=nfft,
        detrend=detrend,
    )


def _segments(rows: np.ndarray, nperseg: int, noverlap: int) -> np.ndarray:
    """The segments of each row, a view (n_rows, n_seg, nperseg)."""
    step = nperseg - noverlap
    n_seg = 1 + (rows.shape[-1] - nperseg) // step
    if n_seg == 1:
        return rows[:, np.newaxis, :nperseg]
    view = np.lib.stride_tricks.sliding_window_view(rows, nperseg, axis=-1)
    return view[:, ::step][:, :n_seg]


def _segment_spectra(seg: np.ndarray, w: np.ndarray, nfft: int, detrend) -> np.ndarray:
    """Complex peak-amplitude spectra of segments (…, nperseg): a sine of amplitude ``A`` on
    bin ``k`` reads ``A e^{iφ}`` there (the window's coherent gain divided out)."""
    n_bins = nfft // 2 + 1
    scale = np.full(n_bins, 2.0 / w.sum())
    scale[0] /= 2.0
    if nfft % 2 == 0:
        scale[-1] /= 2.0
    spec = np.fft.rfft(_detrend(seg, detrend) * w, n=nfft, axis=-1)
    spec *= scale
    return spec


def _mean_amplitude(spec: np.ndarray) -> np.ndarray:
    """Amplitude of segment spectra (n_rows, n_seg, n_bins), RMS-averaged over segments."""
    if spec.shape[1] == 1:
        return np.abs(spec[:, 0])
    power = spec.real**2 + spec.imag**2
    return np.sqrt(power.mean(axis=1))


@dataclass(frozen=True)
class _Kernel:
    """The window's transform, tabulated for exact line estimates.

    ``d`` is an offset from a line in FFT bins; ``mag`` is ``|W(d)| / W(0)`` and ``arg`` the
    phase of ``W(d)`` (radians), where ``W(d) = sum_n w[n] exp(-2πi d n / nfft)``.
    """

    d: np.ndarray
    mag: np.ndarray
    arg: np.ndarray
    ratio_delta: np.ndarray  # offsets 0 … 0.5 bin
    ratio: np.ndarray  # |W(1 - δ)| / |W(δ)|, increasing in δ
    enbw: float  # equivalent noise bandwidth in bins
    lobe: int  # bins on each side of a line that its main lobe covers (|W| > 1 %)
    sidelobe: np.ndarray  # [m]: largest leakage at m bins that rises above that at m - 1

    def sidelobe_level(self, amplitude, rows, cols):
        """Largest amplitude at bins ``cols`` that a stronger line's sidelobes explain.

        Windows whose sampled skirt falls monotonically (Hann, rectangular) have none: their
        leakage never makes a local maximum. Others (Blackman, flat top) do, up to
        ``sidelobe[m]`` times a line ``m`` bins away.
        """
        if not self.sidelobe.any() or cols.size == 0:
            return np.zeros(cols.shape)
        n_bins = amplitude.shape[1]
        m = np.arange(1, self.sidelobe.size)
        level = np.zeros(cols.shape)
        for sign in (-1, 1):
            near = np.clip(cols[:, np.newaxis] + sign * m, 0, n_bins - 1)
            leak = amplitude[rows[:, np.newaxis], near] * self.sidelobe[m]
            level = np.maximum(level, leak.max(axis=1))
        return level

    def transform(self, d):
        """The window's transform at offsets ``d`` (bins, ``|d| <= 17``) over its value at 0:
        a line ``A e^{iφ}`` at bin ν reads ``A e^{iφ} transform(k - ν)`` at bin ``k``.
        ``W(-d)`` is the conjugate of ``W(d)`` (a real window)."""
        a = np.abs(d)
        value = np.interp(a, self.d, self.mag) * np.exp(1j * np.interp(a, self.d, self.arg))
        return np.where(d < 0.0, np.conj(value), value)

    def refine(self, amplitude, first, p, df):
        """Exact frequency (Hz), amplitude and phase (deg) of the lines peaking at bins ``p``.

        ``p`` is an integer array (rows of ``amplitude`` first); each entry must be a local
        maximum with both neighbours inside the spectrum. The two largest bins give the
        offset δ of the line from bin ``p``; amplitude and phase are corrected for it.
        """
        rows = np.arange(amplitude.shape[0]).reshape((-1,) + (1,) * (p.ndim - 1))
        a0 = amplitude[rows, p]
        am = amplitude[rows, p - 1]
        ap = amplitude[rows, p + 1]
        side = np.where(ap >= am, 1.0, -1.0)
        with np.errstate(invalid="ignore", divide="ignore"):
            r = np.where(a0 > 0.0, np.maximum(ap, am) / a0, 0.0)
        delta = side * np.interp(r, self.ratio, self.ratio_delta)
        amp = a0 / np.interp(np.abs(delta), self.d, self.mag)
        freq = (p + delta) * df
        if first is None:
            return freq, amp, np.full(p.shape, np.nan)
        # X[p] = (A/2) e^{iφ} W(p - (p + δ)) = (A/2) e^{iφ} W(-δ)
        phi = np.angle(first[rows, p]) - np.interp(-delta, self.d, self.arg)
        phase = np.degrees(np.angle(np.exp(1j * phi)))
        return freq, amp, phase


@functools.lru_cache(maxsize=16)
def _kernel(w_bytes: bytes, nfft: int) -> _Kernel:
    w = np.frombuffer(w_bytes, dtype=np.float64)
    step = 1.0 / 512.0
    lo, hi = -1.0, 17.0
    m = round((hi - lo) / step) + 1
    d = lo + step * np.arange(m)
    W = scipy.signal.zoom_fft(w, [lo, hi], m=m, fs=nfft, endpoint=True)
    W0 = w.sum()
    mag = np.abs(W) / W0
    arg = np.unwrap(np.angle(W))
    i0 = round(-lo / step)
    half = round(0.5 / step)
    delta = d[i0 : i0 + half + 1]
    ratio = np.interp(1.0 - delta, d, mag) / np.maximum(mag[i0 : i0 + half + 1], 1e-300)
    ratio = np.maximum.accumulate(ratio) + np.arange(ratio.size) * _TIE_BREAK
    beyond = np.flatnonzero((d >= 0) & (mag < 0.01))
    lobe = int(np.ceil(d[beyond[0]])) if beyond.size else int(hi)
    enbw = nfft * float(np.sum(w**2)) / W0**2
    offsets = np.linspace(-0.5, 0.5, 129)
    sidelobe = np.zeros(_SIDELOBE_BINS + 1)
    for k in range(1, _SIDELOBE_BINS + 1):
        here = np.interp(np.abs(k + offsets), d, mag)
        rising = here > np.interp(np.abs(k - 1 + offsets), d, mag) * (1.0 + _RISING)
        sidelobe[k] = here[rising].max(initial=0.0)
    return _Kernel(
        d=d, mag=mag, arg=arg, ratio_delta=delta, ratio=ratio, enbw=enbw, lobe=lobe,
        sidelobe=sidelobe,
    )
