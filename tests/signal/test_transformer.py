"""RubFeatures: the scikit-learn contract and the features it computes."""

from __future__ import annotations

import numpy as np
import pytest
from sklearn.impute import SimpleImputer
from sklearn.pipeline import make_pipeline
from sklearn.preprocessing import StandardScaler
from sklearn.utils.estimator_checks import parametrize_with_checks

from rubdiag.signal import RubFeatures, feature_names, signal_features
from rubdiag.signal._table import still_features

FS = 1000.0


# The checks use 2-20 'samples' per row: min_revolutions=0 lets such rows through (their
# features are NaN: no line fits in so short a record), so the API contract is still checked.
# Their integer data have constant rows: still signals, whose lines are all absent.
@parametrize_with_checks([RubFeatures(fs=FS, speed_rpm=6000.0, min_revolutions=0.0)])
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
    np.testing.assert_allclose(Z, signal_features(X, FS, 1200.0).iloc[:, 1:].to_numpy(float),
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
    with pytest.raises(ValueError, match="speed_col = 5000 is out of range"):
        RubFeatures(fs=FS, speed_col=5000).fit(X)
    with pytest.raises(TypeError, match=r"speed_col = 0\.0 has the wrong type"):
        RubFeatures(fs=FS, speed_col=0.0).fit(X)


class TestFsIsRequired:
    def test_fit_without_fs_is_refused(self, synth):
        X = _rows(synth, [1200.0] * 2)
        assert RubFeatures().get_params()["fs"] is None
        with pytest.raises(ValueError, match=r"RubFeatures needs fs.*RubFeatures\(fs=\.\.\.\)"):
            RubFeatures(speed_rpm=1200.0).fit(X)

    def test_transform_without_fs_is_refused(self, synth):
        X = _rows(synth, [1200.0] * 2)
        fitted = RubFeatures(fs=FS, speed_rpm=1200.0).fit(X)
        with pytest.raises(ValueError, match="RubFeatures needs fs"):
            fitted.set_params(fs=None).transform(X)

    def test_bad_fs_is_named(self, synth):
        X = _rows(synth, [1200.0] * 2)
        with pytest.raises(ValueError, match=r"fs = -1000\.0 is out of range \(allowed: > 0 Hz\)"):
            RubFeatures(fs=-FS, speed_rpm=1200.0).fit(X)


def test_still_rows_are_absent_and_the_batch_goes_on(synth):
    X = _rows(synth, [1200.0] * 3)
    X[1] = 0.25                                   # a dead sensor in the middle of the batch
    Z = RubFeatures(fs=FS, speed_rpm=1200.0).fit_transform(X)
    names = feature_names()
    still = dict(zip(names, Z[1], strict=True))
    assert still["speed_rpm"] == 1200.0 and np.isnan(still["speed_confidence"])
    for name, value in still_features().items():
        np.testing.assert_equal(still[name], value, err_msg=name)
    moving = RubFeatures(fs=FS, speed_rpm=1200.0).fit_transform(X[[0, 2]])
    np.testing.assert_allclose(Z[[0, 2]], moving, equal_nan=True)


def test_all_still_rows_give_all_absent_rows():
    X = np.vstack([np.zeros(2000), np.full(2000, 3.0), np.full(2000, -1e-9)])
    Z = RubFeatures(fs=FS).fit_transform(X)                # even with the speed to guess
    names = feature_names()
    assert np.isnan(Z[:, names.index("speed_rpm")]).all()
    assert (Z[:, names.index("amp_1x")] == 0.0).all() and (Z[:, names.index("rms")] == 0.0).all()


def test_transposed_array_gets_a_hint(synth):
    X = _rows(synth, [1200.0] * 2)
    with pytest.raises(ValueError, match=r"X has 2 samples per signal and 2000 signals: "
                                         r"rows are signals.*did you mean X\.T\?"):
        RubFeatures(fs=FS, speed_rpm=1200.0).fit_transform(X.T)


def test_numpy_scalars_are_numbers(synth):
    X = _rows(synth, [1200.0] * 2)
    plain = RubFeatures(fs=FS, speed_rpm=1200.0, threshold=2.5)
    numpy = RubFeatures(fs=np.int64(1000), speed_rpm=np.float32(1200.0),
                        threshold=np.float32(2.5), nperseg=np.int64(2000))
    np.testing.assert_allclose(numpy.fit_transform(X), plain.fit_transform(X), equal_nan=True)


def test_named_rows_chain_into_the_classifier_features():
    """RubFeatures named as a dataset's channel feeds OrderFeatures and a classifier in one
    pipeline: it tells a 1× record from one with a 2× line, and OrderFeatures computes the
    same values as on the dataset-style table of the same signals."""
    import pandas as pd
    from sklearn.linear_model import LogisticRegression
    from sklearn.pipeline import make_pipeline
    from sklearn.preprocessing import StandardScaler

    from rubdiag.dataset._schema import SEPARATOR
    from rubdiag.learn import OrderFeatures
    from rubdiag.signal._table import prefixed_features
    from rubdiag.signal._transformer import CHANNEL_SEPARATOR

    assert CHANNEL_SEPARATOR == SEPARATOR
    fs, rpm = 2000.0, 1500.0
    t = np.arange(4000) / fs
    rng = np.random.default_rng(3)
    y = np.arange(24) % 2 == 1                      # every other record rubs: a 2× line
    X = np.vstack([np.cos(2 * np.pi * 25 * t + rng.uniform(0, 2 * np.pi))
                   + rub * 0.3 * np.cos(2 * np.pi * 50 * t + rng.uniform(0, 2 * np.pi))
                   + 0.01 * rng.standard_normal(t.size) for rub in y])
    pipeline = make_pipeline(RubFeatures(fs=fs, speed_rpm=rpm, channel="shaft"),
                             OrderFeatures(), StandardScaler(), LogisticRegression())
    pipeline.set_output(transform="pandas")
    pipeline.fit(X[:12], y[:12])
    assert (pipeline.predict(X[12:]) == y[12:]).all()
    chained = pipeline[:2].transform(X)
    table = pd.concat([prefixed_features({"shaft": x}, fs, rpm, separator=SEPARATOR)
                       for x in X], ignore_index=True)
    direct = OrderFeatures().set_output(transform="pandas").fit(table).transform(table)
    assert list(chained.columns) == list(direct.columns)
    assert "shaft__rel_amp_2x" in chained.columns
    np.testing.assert_allclose(chained.to_numpy(), direct.to_numpy(), rtol=1e-12)
