"""RubFeatures: the scikit-learn contract and the features it computes."""

from __future__ import annotations

import numpy as np
import pytest
from sklearn.impute import SimpleImputer
from sklearn.pipeline import make_pipeline
from sklearn.preprocessing import StandardScaler
from sklearn.utils.estimator_checks import parametrize_with_checks

from rubdiag.signal import RubFeatures, feature_names, features

FS = 1000.0


def _expected_failures(estimator):
    return {
        "check_estimators_dtypes": (
            "the check's integer data have constant rows; a constant signal has no spectrum and "
            "is refused with a ValueError by design"
        ),
    }


# The checks use 2-20 'samples' per row: min_revolutions=0 lets such rows through (their
# features are NaN: no line fits in so short a record), so the API contract is still checked.
@parametrize_with_checks(
    [RubFeatures(fs=FS, speed_rpm=6000.0, min_revolutions=0.0)],
    expected_failed_checks=_expected_failures,
)
def test_sklearn_compatible(estimator, check):
    check(estimator)


def _rows(synth, speeds, n=2000):
    return np.vstack([
        synth([(r / 60, 1.0 + i), (1.5 * r / 60, 0.1)], FS, n / FS, noise=1e-3, seed=i)
        for i, r in enumerate(speeds)
    ])


def test_transform_matches_features(synth):
    X = _rows(synth, [1200.0] * 5)
    Z = RubFeatures(fs=FS, speed_rpm=1200.0).fit_transform(X)
    names = list(RubFeatures(fs=FS).fit(X).get_feature_names_out())
    assert names == feature_names()
    np.testing.assert_allclose(Z[:, names.index("amp_1x")], 1.0 + np.arange(5), rtol=0.01)
    np.testing.assert_allclose(Z, features(X, FS, 1200.0).iloc[:, 1:].to_numpy(float),
                               equal_nan=True)


def test_per_row_speed_from_a_column(synth):
    speeds = np.array([1200.0, 1500.0, 2400.0, 3000.0])
    X = np.column_stack([speeds, _rows(synth, speeds)])
    Z = RubFeatures(fs=FS, speed_col=0).fit_transform(X)
    names = feature_names()
    np.testing.assert_allclose(Z[:, names.index("speed_rpm")], speeds)
    np.testing.assert_allclose(Z[:, names.index("amp_1p5x")], 0.1, rtol=0.02)
    np.testing.assert_allclose(Z[:, names.index("freq_1x_hz")], speeds / 60, rtol=1e-4)


def test_pandas_output_and_pipeline(synth):
    X = _rows(synth, [1500.0] * 6)
    out = RubFeatures(fs=FS, speed_rpm=1500.0).set_output(transform="pandas").fit_transform(X)
    assert list(out.columns) == feature_names()
    assert out["amp_1x"].to_numpy() == pytest.approx(1.0 + np.arange(6), rel=0.01)
    # absent lines have NaN frequencies: impute before scaling
    pipe = make_pipeline(
        RubFeatures(fs=FS, speed_rpm=1500.0),
        SimpleImputer(strategy="constant", fill_value=0.0, keep_empty_features=True),
        StandardScaler(),
    )
    Z = pipe.fit_transform(X)
    assert Z.shape == (6, len(feature_names()))
    assert np.isfinite(Z).all()


def test_bad_input(synth):
    X = _rows(synth, [1500.0] * 3)
    with pytest.raises(ValueError, match="too short"):
        RubFeatures(fs=FS, speed_rpm=1500.0).fit_transform(X[:, :200])
    with pytest.raises(ValueError, match="Nyquist"):
        RubFeatures(fs=FS, speed_rpm=60000.0).fit_transform(X)
    with pytest.raises(ValueError, match="speed_col"):
        RubFeatures(fs=FS, speed_col=5000).fit(X)
