"""The engine's settings: defaults written once (Options), checked once, numpy scalars welcome."""

from __future__ import annotations

import dataclasses
import inspect

import numpy as np
import pytest

from rubdiag.signal import RubFeatures, combination_pairs, signal_features, spectral_lines
from rubdiag.signal._options import Options

DEFAULTS = {f.name: f.default for f in dataclasses.fields(Options)}


@pytest.mark.parametrize("function", [signal_features, combination_pairs, RubFeatures])
def test_every_entry_point_shows_the_options_defaults(function):
    parameters = inspect.signature(function).parameters
    shown = {name: parameters[name].default for name in DEFAULTS}
    assert shown == DEFAULTS


def test_spectral_lines_shares_the_line_settings():
    parameters = inspect.signature(spectral_lines).parameters
    for name in ("threshold", "window", "nperseg", "detrend"):
        assert parameters[name].default == DEFAULTS[name]


def test_transformer_passes_every_option_on():
    changed = {"band": 0.05, "threshold": 3.0, "window": "hamming", "nperseg": 1000,
               "detrend": "linear", "min_revolutions": 5.0, "combo_tol_hz": 0.5}
    assert set(changed) == set(DEFAULTS)
    assert RubFeatures(fs=1000.0, **changed)._options() == Options(**changed)


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        ({"band": 0.0}, r"band = 0\.0 is out of range \(allowed: > 0 and < 0\.25 orders\)"),
        ({"band": np.float64(np.inf)}, r"band = inf is out of range"),
        ({"threshold": True}, "threshold = True has the wrong type"),
        ({"nperseg": 1}, r"nperseg = 1 is out of range \(allowed: >= 2\)"),
        ({"combo_tol_hz": 0}, r"combo_tol_hz = 0 is out of range \(allowed: > 0 Hz\)"),
    ],
)
def test_bad_options_are_named(kwargs, message):
    with pytest.raises(ValueError, match=message):
        Options(**kwargs)


def test_numpy_scalars_become_python_numbers():
    opts = Options(band=np.float32(0.05), threshold=np.int64(4), nperseg=np.int32(512),
                   min_revolutions=np.float64(3.0), combo_tol_hz=np.float32(2.3))
    values = dataclasses.astuple(opts)
    assert values == pytest.approx((0.05, 4.0, "hann", 512, "constant", 3.0, 2.3))
    assert [type(v) for v in values] == [float, float, str, int, str, float, float]
