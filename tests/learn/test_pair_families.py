"""The probe-pair families of OrderFeatures (``full_spectrum``, ``orbit``): scale-free,
chosen only for pairs whose two probes are among the channels, nothing from a frame without
pair columns, and a classifier on them sees what the single-channel families cannot."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest
from sklearn.metrics import f1_score
from sklearn.model_selection import StratifiedKFold, cross_val_predict

from rubdiag.dataset._card import column_map
from rubdiag.dataset._schema import PAIR_FEATURES
from rubdiag.learn import OrderFeatures, make_pipeline
from rubdiag.learn._columns import LINE_FEATURES
from rubdiag.simulation._sensors import Sensor

SENSORS = (Sensor("shaft 11", "y"), Sensor("shaft 11", "z"), Sensor("shaft 4", "y"))
PAIR = "shaft11_yz_disp"
LINES = [n for n in PAIR_FEATURES if n[:4] in ("fwd_", "rev_")]
OTHER_ORDERS = [n[4:] for n in LINES if n.startswith("fwd_") and n != "fwd_1x"]


def synthetic(n: int, share, seed: int = 0) -> pd.DataFrame:
    """``n`` rows: every single-channel feature of the three probes drawn alike for all
    rows, and the pair's lines with a non-1x power split so that the reverse share of each
    row is ``share[i]`` (its 1x forward and reverse, and the orbit measures, drawn alike)."""
    rng = np.random.default_rng(seed)
    data = {"speed_rpm": np.full(n, 5700.0)}
    for s in SENSORS:
        for f in LINE_FEATURES:
            data[f"{s.name}__{f}"] = rng.uniform(0.0, 1e-5, n)
    share = np.asarray(share, dtype=float)
    power = rng.uniform(0.5, 2.0, (n, len(OTHER_ORDERS))) * 1e-12   # fwd^2 + rev^2 (m^2)
    rows = {}
    for j, k in enumerate(OTHER_ORDERS):
        rows[f"fwd_{k}"] = np.sqrt((1.0 - share) * power[:, j])
        rows[f"rev_{k}"] = np.sqrt(share * power[:, j])
    rows["fwd_1x"], rows["rev_1x"] = rng.uniform(2e-5, 4e-5, n), rng.uniform(0.0, 1e-5, n)
    rows.update(forward_1x=rows["fwd_1x"], reverse_1x=rows["rev_1x"],
                ellipticity_1x=rows["rev_1x"] / rows["fwd_1x"], precession_1x=np.ones(n),
                reverse_share=share, flattening=rng.uniform(0.0, 0.5, n),
                limit_radius=rng.uniform(2e-5, 5e-5, n),
                near_limit_share=rng.uniform(0.0, 0.3, n))
    for f in PAIR_FEATURES:
        data[f"{PAIR}__{f}"] = rows[f]
    return pd.DataFrame(data)


def test_the_pair_families_are_scale_free():
    """Every length column (unit m in the dataset's column map) times 10: the same derived
    features; and the ratios are the lines over sqrt(sum fwd^2 + rev^2), computed here."""
    X = synthetic(6, np.linspace(0.0, 1.0, 6))
    units = column_map(X.columns, SENSORS).set_index("column")["unit"]
    lengths = [c for c in X.columns if units[c] == "m"]
    assert f"{PAIR}__limit_radius" in lengths and f"{PAIR}__rev_2x" in lengths
    assert f"{PAIR}__reverse_share" not in lengths
    scaled = X.copy()
    scaled[lengths] *= 10.0
    features = OrderFeatures(families=["full_spectrum", "orbit"]).fit(X)
    assert features.pairs_ == [PAIR]
    np.testing.assert_allclose(features.transform(scaled), features.transform(X), rtol=1e-12)
    out = pd.DataFrame(features.transform(X), columns=features.get_feature_names_out())
    level = np.sqrt((X[[f"{PAIR}__{n}" for n in LINES]] ** 2).sum(axis=1))
    np.testing.assert_allclose(out[f"{PAIR}__rev_rel_2x"], X[f"{PAIR}__rev_2x"] / level)
    np.testing.assert_allclose(out[f"{PAIR}__limit_radius_rel"],
                               X[f"{PAIR}__limit_radius"] / level)
    np.testing.assert_allclose(out[f"{PAIR}__reverse_share"], np.linspace(0.0, 1.0, 6))


def test_a_pair_is_used_only_with_both_probes_and_only_when_the_data_has_it():
    X = synthetic(8, np.full(8, 0.5))
    orders = OrderFeatures(channels=["shaft11_y_disp", "shaft4_y_disp"],
                           families=["orders"]).fit(X)
    one_probe = OrderFeatures(channels=["shaft11_y_disp", "shaft4_y_disp"],
                              families=["orders", "full_spectrum", "orbit"]).fit(X)
    assert one_probe.pairs_ == [] and one_probe.pair_required_ == []
    np.testing.assert_array_equal(one_probe.transform(X), orders.transform(X))
    both = OrderFeatures(channels=["shaft11_z_disp", "shaft11_y_disp"],
                         families=["orders", "full_spectrum"]).fit(X)
    assert both.pairs_ == [PAIR]
    assert f"{PAIR}__rev_rel_1p5x" in list(both.get_feature_names_out())
    # an old dataset without pair columns: the pair families add nothing
    old = X[[c for c in X.columns if not c.startswith(PAIR)]]
    plain = OrderFeatures(families=["orders"]).fit(old)
    asked = OrderFeatures(families=["orders", "full_spectrum", "orbit"]).fit(old)
    np.testing.assert_array_equal(asked.transform(old), plain.transform(old))
    with pytest.raises(ValueError, match="no probe pair"):
        OrderFeatures(families=["orbit"]).fit(old)
    # a model fitted before the pair families existed (no pair attributes) still transforms
    del plain.pair_required_, plain.pairs_
    np.testing.assert_array_equal(plain.transform(old), asked.transform(old))
    # a model using the pair is refused on data without it, naming the column
    with pytest.raises(ValueError, match=f"no column '{PAIR}__"):
        both.transform(old)


def test_only_the_full_spectrum_sees_a_reverse_share():
    """Two classes that differ only in the reverse share of the pair's non-1x motion
    (below 0.3 or above 0.7): the full-spectrum family separates them, the single-channel
    orders cannot (their columns are drawn alike for both)."""
    rng = np.random.default_rng(1)
    y = np.repeat([0, 1], 60)
    share = np.where(y == 1, rng.uniform(0.7, 1.0, y.size), rng.uniform(0.0, 0.3, y.size))
    X = synthetic(y.size, share, seed=2)
    folds = StratifiedKFold(5, shuffle=True, random_state=0)
    scores = {}
    for family in ("full_spectrum", "orders"):
        predicted = cross_val_predict(make_pipeline("rf", families=[family]), X, y, cv=folds)
        scores[family] = f1_score(y, predicted, average="macro")
    assert scores["full_spectrum"] == 1.0
    assert scores["orders"] < 0.65
