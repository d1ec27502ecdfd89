"""The least sampling rate at which a model's features are measured (training records it,
prediction checks a signal file against it)."""

from __future__ import annotations

__all__ = ["EDGE_BINS", "required_fs"]

#: Bins between the top of a feature's search band and the Nyquist frequency that the
#: feature table needs (the spectrum's last bins are never searched).
EDGE_BINS = 3


def required_fs(reach: float, speed_rpm: float, window_s: float) -> float:
    """Least sampling rate (Hz) at which features reaching ``reach`` orders are measured at
    ``speed_rpm`` in a window of ``window_s``: the band's top plus :data:`EDGE_BINS`
    frequency bins below the Nyquist frequency.

    Parameters
    ----------
    reach : float
        Highest order (multiple of the rotation frequency) a feature's search reaches.
    speed_rpm : float
        Rotor speed (rpm).
    window_s : float
        Length of the analysis window (s).

    Returns
    -------
    float
        Sampling rate (Hz).
    """
    return 2.0 * (reach * float(speed_rpm) / 60.0 + EDGE_BINS / float(window_s))
