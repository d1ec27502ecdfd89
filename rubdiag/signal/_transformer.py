"""scikit-learn transformer: rows of X are signals, columns of the output are features."""

from __future__ import annotations

from dataclasses import fields

import numpy as np
from sklearn.base import BaseEstimator, TransformerMixin
from sklearn.utils.validation import check_is_fitted, validate_data

from rubdiag import _check
from rubdiag.signal._options import Options
from rubdiag.signal._records import MIN_SAMPLES, check_fs, transposed_hint
from rubdiag.signal._table import FEATURE_NAMES, feature_matrix

#: between channel and feature in a dataset's column names (``shaft11_y_disp__amp_1x``); the
#: dataset layer, above this one, uses the same (tests/signal/test_transformer.py)
CHANNEL_SEPARATOR = "__"


class RubFeatures(TransformerMixin, BaseEstimator):
    """Rub-impact spectral features of equal-length signals (rows of X).

    Stateless: ``fit`` only checks X and records its width; ``transform`` runs the batch
    path of :func:`rubdiag.signal.signal_features` on all rows at once. Output columns are
    :data:`rubdiag.signal.FEATURE_NAMES` (see :mod:`rubdiag.signal._table` for units, for
    0 / NaN meaning absent / unmeasurable, and for still rows, whose lines are all absent);
    ``set_output(transform="pandas")`` names them.

    Parameters
    ----------
    fs : float
        Sampling frequency of every row, Hz. Required: ``fit`` and ``transform`` refuse
        to guess it (None is only the placeholder scikit-learn's cloning needs).
    speed_rpm : float, optional
        Running speed in rpm, the same for all rows. None: each row's strongest line is 1×
        (refused when it does not stand out of the noise, see ``speed_confidence``),
        unless ``speed_col`` is given.
    speed_col : int, optional
        Index of a column of X that holds each row's speed in rpm (per-row speeds); that
        column is not part of the signal.
    band, threshold, window, nperseg, detrend, min_revolutions, combo_tol_hz
        As for :func:`rubdiag.signal.signal_features`; the defaults are those of
        :class:`~rubdiag.signal._options.Options`.
    channel : str, optional
        The rows' channel name. When given, the output columns are named as a dataset's:
        ``speed_rpm``, then ``<channel>__<feature>``; so
        :class:`rubdiag.learn.OrderFeatures` (and any model trained on a dataset's rows of
        that channel) can follow it in a pipeline whose output is pandas
        (``pipeline.set_output(transform="pandas")``).

    Examples
    --------
    >>> import numpy as np
    >>> fs = 1000.0
    >>> t = np.arange(2000) / fs
    >>> X = np.vstack([a * np.cos(2 * np.pi * 20.0 * t) for a in (1.0, 2.0)])
    >>> Z = RubFeatures(fs=fs, speed_rpm=1200.0).fit_transform(X)
    >>> names = list(RubFeatures(fs=fs).fit(X).get_feature_names_out())
    >>> Z[:, names.index("amp_1x")].round(6).tolist()
    [1.0, 2.0]

    Named as a dataset's channel, to chain with the classifier features:

    >>> named = RubFeatures(fs=fs, speed_rpm=1200.0, channel="shaft11_y_disp")
    >>> list(named.fit(X).get_feature_names_out()[:3])
    ['speed_rpm', 'shaft11_y_disp__speed_confidence', 'shaft11_y_disp__rms']
    """

    def __init__(
        self,
        fs: float | None = None,
        speed_rpm: float | None = None,
        speed_col: int | None = None,
        band: float = Options.band,
        threshold: float = Options.threshold,
        window=Options.window,
        nperseg: int | None = Options.nperseg,
        detrend=Options.detrend,
        min_revolutions: float = Options.min_revolutions,
        combo_tol_hz: float | None = Options.combo_tol_hz,
        channel: str | None = None,
    ):
        self.fs = fs
        self.speed_rpm = speed_rpm
        self.speed_col = speed_col
        self.band = band
        self.threshold = threshold
        self.window = window
        self.nperseg = nperseg
        self.detrend = detrend
        self.min_revolutions = min_revolutions
        self.combo_tol_hz = combo_tol_hz
        self.channel = channel

    def fit(self, X, y=None):
        """Check X (n_signals, n_samples) and record its width; returns self."""
        self._fs()
        X = validate_data(self, X, dtype=np.float64)
        self._split(X)
        self._options()
        return self

    def transform(self, X):
        """Features of every row of X: ndarray (n_signals, n_features_out)."""
        check_is_fitted(self, "n_features_in_")
        X = validate_data(self, X, dtype=np.float64, reset=False)
        signals, speed = self._split(X)
        return feature_matrix(signals, self._fs(), speed, self._options())

    def get_feature_names_out(self, input_features=None):
        """Names of the output columns (the feature table's columns)."""
        check_is_fitted(self, "n_features_in_")
        if self.channel is None:
            return np.asarray(FEATURE_NAMES, dtype=object)
        speed, *rest = FEATURE_NAMES        # the speed stays unprefixed, as in a dataset
        return np.asarray([speed, *(f"{self.channel}{CHANNEL_SEPARATOR}{name}"
                                    for name in rest)], dtype=object)

    def _fs(self) -> float:
        if self.fs is None:
            raise ValueError("RubFeatures needs fs, the sampling frequency in Hz of the rows "
                             "of X: RubFeatures(fs=...)")
        return check_fs(self.fs)

    def _options(self) -> Options:
        return Options(**{f.name: getattr(self, f.name) for f in fields(Options)})

    def _split(self, X: np.ndarray):
        """Signals and per-row speeds (or the fixed speed) from X."""
        speed = self.speed_rpm
        if self.speed_col is not None:
            col = _check.integer("speed_col", self.speed_col, lo=-X.shape[1], hi=X.shape[1] - 1)
            speed = X[:, col]
            X = np.delete(X, col, axis=1)
        if X.shape[1] < MIN_SAMPLES:
            hint = transposed_hint(X.shape, "X", "signal")
            raise ValueError(
                f"RubFeatures needs signals of at least {MIN_SAMPLES} samples; "
                f"got {X.shape[1]} feature(s)" + (f"; {hint}" if hint else "")
            )
        return X, speed
