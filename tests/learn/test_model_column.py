"""A dataset's ``model`` column ("full" or "reduced") is metadata: no channel, no
factor, no input of a classifier. Synthetic rows, no simulation."""

import numpy as np
import pandas as pd
import pytest

from rubdiag.dataset._schema import MODEL_COLUMN
from rubdiag.learn import make_pipeline
from rubdiag.learn._columns import channels_of, factor_columns
from rubdiag.learn._features import FAMILIES, OrderFeatures
from rubdiag.signal._table import prefixed_features

FS = 2000.0


@pytest.fixture(scope="module")
def rows():
    """Rows of two channels, rub = a 2x line; ``model`` says "reduced" exactly for the rubbing
    rows, so a classifier that read it would need nothing else."""
    t = np.arange(4000) / FS
    rng = np.random.default_rng(0)
    frames = []
    for a in (0.0, 0.0, 0.0, 0.3, 0.4, 0.5):
        x = np.sin(2 * np.pi * 25 * t) + a * np.sin(2 * np.pi * 50 * t)
        frames.append(prefixed_features(
            {"shaft": x + 1e-3 * rng.standard_normal(t.size),
             "casing": 0.1 * x + 1e-3 * rng.standard_normal(t.size)}, FS, 1500.0,
            separator="__"))
    data = pd.concat(frames, ignore_index=True)
    data.insert(1, "case", 1)
    data.insert(2, MODEL_COLUMN, ["full"] * 3 + ["reduced"] * 3)
    data["rub"] = [False] * 3 + [True] * 3
    return data


def test_model_is_no_channel_and_no_factor(rows):
    assert MODEL_COLUMN not in channels_of(rows)
    assert sorted(channels_of(rows)) == ["casing", "shaft"]
    assert MODEL_COLUMN not in factor_columns(rows)           # no design: every factor name
    named = rows.copy()
    named.attrs["factors"] = ["case"]                          # as read_dataset sets it
    assert factor_columns(named) == ["case"]


def test_no_feature_family_reads_the_model_column(rows):
    features = OrderFeatures(channels=None, families=FAMILIES).fit(rows)
    names = list(features.get_feature_names_out())
    assert not any(MODEL_COLUMN in n for n in names)
    assert MODEL_COLUMN not in features.required_


def test_a_classifier_ignores_the_model_column(rows):
    y = rows["rub"].astype(str).to_numpy()
    pipe = make_pipeline("logreg").fit(rows, y)
    flipped = rows.assign(**{MODEL_COLUMN: rows[MODEL_COLUMN].map(
        {"full": "reduced", "reduced": "full"})})
    # the same probabilities (to float noise: the frames' layouts differ)
    np.testing.assert_allclose(pipe.predict_proba(flipped), pipe.predict_proba(rows),
                               rtol=1e-12, atol=1e-15)
    np.testing.assert_allclose(pipe.predict_proba(rows.drop(columns=[MODEL_COLUMN])),
                               pipe.predict_proba(rows), rtol=1e-12, atol=1e-15)
