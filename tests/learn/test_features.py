"""OrderFeatures and the pipelines, on feature tables of synthetic signals with known lines.

Every table here comes from ``rubdiag.signal._table.prefixed_features`` on sums of cosines
whose amplitudes and frequencies are set in this file, so the expected classifier inputs
follow from the signal, not from the code under test.
"""

from __future__ import annotations

import warnings

import numpy as np
import pandas as pd
import pytest
from sklearn.base import clone
from sklearn.model_selection import GridSearchCV, StratifiedKFold
from sklearn.utils import estimator_checks
from threadpoolctl import threadpool_limits

from rubdiag.learn import (
    DEFAULT_FAMILIES,
    ESTIMATORS,
    OrderFeatures,
    SelectColumns,
    make_pipeline,
)
from rubdiag.signal._orders import HALF_ORDERS, HARMONICS, THIRD_ORDERS, order_label
from rubdiag.signal._table import prefixed_features

FS = 2000.0
DURATION_S = 4.0
N = round(FS * DURATION_S)
T = np.arange(N) / FS

# One shaft signal in orders of 1× (order, amplitude): 1× of amplitude A, a line at 1.52×
# (inside the 1.5× search band of ±0.03×, so dev_1p5x = +0.02), sidebands 2× ∓ 0.2×, and
# a combination pair 0.41× + 1.59× = 2× (neither line within 0.03× of a half or third order,
# 1.18× apart). No line at 3.5×: its location is NaN in every row.
A, B, NOISE = 1.0, 0.2, 0.01
LINES = [(1.0, A), (1.52, B), (1.8, 0.05), (2.2, 0.03), (0.41, 0.10), (1.59, 0.08)]
# RMS of the record: the sum of cosines (a²/2 each) plus the noise variance (the lines lie
# on whole periods of the 4-s record closely enough that the detrending removes nothing).
RMS = np.sqrt(sum(a * a for _, a in LINES) / 2 + NOISE**2)
# The channel's level, which the ratios divide by (rubdiag.learn._features): the RMS within
# the searched orders — the order lines (1×, 1.52× in the 1.5× band) and the broadband
# n× ± 0.25× around each harmonic, which holds the two sidebands of 2×. The combination
# lines 0.41× and 1.59× lie in no searched band. The noise in the eight 0.5×-wide bands
# adds 8 · NOISE² · 12.5 Hz / 1000 Hz = 1e-5 to 0.52 (1e-5 relative on the level).
LEVEL = np.sqrt((A**2 + B**2 + 0.05**2 + 0.03**2) / 2)
# A tolerance of 2 % on amplitudes (tests/signal/test_table.py allows 1–2 % for lines of
# this size); the noise alone moves a line's amplitude by about
# NOISE·sqrt(2·1.5/N) ≈ 2e-4, i.e. 0.1 % of B.
AMP_REL = 0.02
# Frequencies: interpolated peaks are good to far better than a tenth of the 0.25-Hz
# resolution; 0.025 Hz is 1e-3 of 1× at 1500 rpm.
ORDER_ABS = 1e-3


@pytest.fixture(autouse=True, scope="module")
def one_thread():
    """hgb's OpenMP threads on a shared 2-core machine spin against the other processes
    (a 20-iteration fit went from 0.14 s to 8 s): one thread, as the rest of the suite."""
    with threadpool_limits(1):
        yield


def orders_signal(rpm, scale=1.0, lines=LINES, seed=0):
    f1 = rpm / 60.0
    x = sum(a * np.cos(2 * np.pi * k * f1 * T + 0.3 * k) for k, a in lines)
    x = x + NOISE * np.random.default_rng(seed).standard_normal(N)
    return scale * x


def table(rows):
    """A frame of prefixed feature rows: ``rows`` is a list of (rpm, {channel: signal})."""
    return pd.concat([prefixed_features(signals, FS, rpm, separator="__")
                      for rpm, signals in rows], ignore_index=True)


@pytest.fixture(scope="module")
def two_speeds():
    """The same order content at 1500 rpm and, three times as large, at 2400 rpm; a second
    channel that is still (all zeros) in the first row and moving in the second."""
    still = np.zeros(N)
    return table([
        (1500.0, {"shaft": orders_signal(1500.0), "casing": still}),
        (2400.0, {"shaft": orders_signal(2400.0, scale=3.0, seed=1),
                  "casing": orders_signal(2400.0, scale=0.5, seed=2)}),
    ])


def level_of(rows, channel):
    """The level as the module docstring defines it: sqrt of Σ amp_k²/2 over the half and
    third orders plus Σ bb_nx_rms² over the harmonics (NaN adds nothing)."""
    amps = [f"{channel}__amp_{order_label(k)}" for k in (*HALF_ORDERS, *THIRD_ORDERS)]
    bands = [f"{channel}__bb_{n}x_rms" for n in HARMONICS]
    power = ((rows[amps].fillna(0.0) ** 2).sum(axis=1) / 2
             + (rows[bands].fillna(0.0) ** 2).sum(axis=1))
    return np.sqrt(power.to_numpy())


def frame_of(features: OrderFeatures, X):
    return pd.DataFrame(features.transform(X), columns=features.get_feature_names_out())


def expected_default_names(channel):
    """The default families' names, from the feature vocabulary of the module docstring."""
    half = [order_label(k) for k in HALF_ORDERS]
    third = [order_label(k) for k in THIRD_ORDERS]
    names = ([f"rel_amp_{k}" for k in half] + [f"rel_amp_{k}" for k in third]
             + [f"dev_{k}" for k in half if k != "1x"] + ["n_half_orders", "n_third_orders"])
    for n in HARMONICS:
        names += [f"sb_{n}x_delta_order", f"sb_{n}x_rel_lower", f"sb_{n}x_rel_upper",
                  f"bb_{n}x_over_floor"]
    names += ["combo_fa_order", "combo_fb_order", "combo_order", "combo_rel_amp_a",
              "combo_rel_amp_b"]
    return {f"{channel}__{n}" for n in names}


class TestOrderNormalised:
    def test_values_from_the_signal(self, two_speeds):
        of = OrderFeatures(channels="shaft").fit(two_speeds)
        z = frame_of(of, two_speeds)
        for i, (rpm, scale) in enumerate(((1500.0, 1.0), (2400.0, 3.0))):
            assert z.loc[i, "shaft__rel_amp_1x"] == pytest.approx(A / LEVEL, rel=AMP_REL)
            assert z.loc[i, "shaft__rel_amp_1p5x"] == pytest.approx(B / LEVEL, rel=AMP_REL)
            assert z.loc[i, "shaft__dev_1p5x"] == pytest.approx(0.02, abs=ORDER_ABS)
            assert "shaft__dev_1x" not in z.columns        # the 1× line is the speed
            assert z.loc[i, "shaft__sb_2x_delta_order"] == pytest.approx(0.2, abs=ORDER_ABS)
            assert z.loc[i, "shaft__sb_2x_rel_lower"] == pytest.approx(0.05 / LEVEL, rel=AMP_REL)
            assert z.loc[i, "shaft__sb_2x_rel_upper"] == pytest.approx(0.03 / LEVEL, rel=AMP_REL)
            assert z.loc[i, "shaft__combo_fa_order"] == pytest.approx(0.41, abs=ORDER_ABS)
            assert z.loc[i, "shaft__combo_fb_order"] == pytest.approx(1.59, abs=ORDER_ABS)
            assert z.loc[i, "shaft__combo_order"] == 2.0
            assert z.loc[i, "shaft__combo_rel_amp_a"] == pytest.approx(0.10 / LEVEL, rel=AMP_REL)
            assert z.loc[i, "shaft__rel_amp_3p5x"] == 0.0          # absent line
            # the definitions, exactly, against the raw table: ratio over the channel's
            # level, Hz over the speed in Hz
            raw, f1 = two_speeds.iloc[i], rpm / 60.0
            level = level_of(two_speeds, "shaft")[i]
            assert level == pytest.approx(scale * LEVEL, rel=AMP_REL)
            assert level < raw["shaft__rms"]          # the combination lines are not in it
            assert z.loc[i, "shaft__rel_amp_1p5x"] == pytest.approx(
                raw["shaft__amp_1p5x"] / level, rel=1e-12)
            floor = min(raw[f"shaft__bb_{n}x_rms"] for n in HARMONICS)
            assert z.loc[i, "shaft__bb_2x_over_floor"] == pytest.approx(
                raw["shaft__bb_2x_rms"] / floor, rel=1e-12)
            assert z.loc[i, "shaft__dev_1p5x"] == pytest.approx(
                raw["shaft__freq_1p5x_hz"] / f1 - 1.5, abs=1e-12)
            assert z.loc[i, "shaft__sb_2x_delta_order"] == pytest.approx(
                raw["shaft__sb_2x_delta_hz"] / f1, rel=1e-12)
            assert z.loc[i, "shaft__combo_fb_order"] == pytest.approx(
                raw["shaft__combo_fb_hz"] / f1, rel=1e-12)

    def test_same_orders_same_features_at_any_speed_and_scale(self, two_speeds):
        # row 1 is row 0's order content at 1.6 × the speed and 3 × the size: the default
        # features agree to the estimation tolerance, the levels and frequencies do not.
        # Not the bands over the floor: white noise spreads over Hz, so a band 1.6 × as
        # wide holds 1.6 × the noise power under the same lines (TestNoiseFloor).
        of = OrderFeatures(channels="shaft").fit(two_speeds)
        keep = ["over_floor" not in n for n in of.get_feature_names_out()]
        z = of.transform(two_speeds)[:, keep]
        np.testing.assert_allclose(z[1], z[0], rtol=AMP_REL, atol=ORDER_ABS)
        raw = two_speeds[["shaft__rms", "shaft__freq_1x_hz"]].to_numpy()
        np.testing.assert_allclose(raw[1] / raw[0], [3.0, 1.6], rtol=AMP_REL)

    def test_default_names(self, two_speeds):
        names = OrderFeatures().fit(two_speeds).get_feature_names_out()
        assert len(names) == len(set(names))
        shaft = OrderFeatures(channels="shaft").fit(two_speeds)
        # shaft: every location measured in some row except the absent lines' (dev_k of
        # k with no line in either row), which are dropped (NaN policy below)
        kept = set(shaft.get_feature_names_out())
        assert kept | set(shaft.dropped_) == expected_default_names("shaft")
        assert not kept & set(shaft.dropped_)
        for name in names:
            assert "speed" not in name and not name.endswith("_hz")
            assert not name.endswith(("__rms", "__amp_1x"))

    def test_levels_and_absolute_only_when_asked(self, two_speeds):
        default = OrderFeatures(channels="shaft").fit(two_speeds)
        levels = OrderFeatures(channels="shaft", families=("orders", "levels")).fit(two_speeds)
        absolute = OrderFeatures(families=["orders", "absolute"]).fit(two_speeds)
        assert "speed_rpm" not in default.get_feature_names_out()
        assert "speed_rpm" not in levels.get_feature_names_out()
        names = list(absolute.get_feature_names_out())
        assert names.count("speed_rpm") == 1                 # once, not once per channel
        z = frame_of(absolute, two_speeds)
        np.testing.assert_array_equal(z["speed_rpm"], [1500.0, 2400.0])
        np.testing.assert_allclose(z["shaft__freq_1p5x_hz"], [1.52 * 25.0, 1.52 * 40.0],
                                   atol=ORDER_ABS * 40.0)
        zl = frame_of(levels, two_speeds)
        np.testing.assert_allclose(zl["shaft__rms"], [RMS, 3.0 * RMS], rtol=AMP_REL)
        np.testing.assert_allclose(zl["shaft__amp_1p5x"], [B, 3.0 * B], rtol=AMP_REL)
        assert not any(n.endswith("_hz") for n in levels.get_feature_names_out())

    def test_channels_select_and_keep_order(self, two_speeds):
        both = OrderFeatures().fit(two_speeds)
        assert both.channels_ == ["shaft", "casing"]
        casing = OrderFeatures(channels=["casing"]).fit(two_speeds)
        assert all(n.startswith("casing__") for n in casing.get_feature_names_out())
        # the columns of a channel do not depend on which other channels are used
        np.testing.assert_array_equal(
            frame_of(casing, two_speeds),
            frame_of(both, two_speeds)[list(casing.get_feature_names_out())])


class TestMissingValues:
    def test_never_measured_column_is_dropped_and_listed(self, two_speeds):
        of = OrderFeatures(channels="shaft").fit(two_speeds)
        # no line at 3.5× or 0.5× in either row: locations NaN everywhere
        assert {"shaft__dev_3p5x", "shaft__dev_0p5x"} <= set(of.dropped_)
        assert "shaft__dev_3p5x" not in of.get_feature_names_out()
        assert "shaft__dev_1p5x" not in of.dropped_
        assert "shaft__freq_1p5x_hz" in of.required_

    def test_nan_at_transform_is_zero(self, two_speeds):
        of = OrderFeatures(channels="shaft").fit(two_speeds)
        no_1p5x = [line for line in LINES if line[0] != 1.52]
        other = table([(1500.0, {"shaft": orders_signal(1500.0, lines=no_1p5x),
                                 "casing": np.zeros(N)})])
        assert np.isnan(other["shaft__freq_1p5x_hz"].iloc[0])
        z = frame_of(of, other)
        assert np.isfinite(z.to_numpy()).all()
        assert z.loc[0, "shaft__dev_1p5x"] == 0.0
        assert z.loc[0, "shaft__rel_amp_1p5x"] == 0.0

    def test_unmeasurable_orders(self):
        # at 9000 rpm 7× and 8× (1050, 1200 Hz) lie above Nyquist (1000 Hz): every column
        # of them is NaN in the fast row, amplitudes too; they are measured in the slow row
        rows = table([(1500.0, {"shaft": orders_signal(1500.0)}),
                      (9000.0, {"shaft": orders_signal(9000.0, lines=[(1.0, A)])})])
        assert np.isnan(rows["shaft__amp_8x"].iloc[1])
        of = OrderFeatures().fit(rows)
        z = frame_of(of, rows)
        assert np.isfinite(z.to_numpy()).all()
        assert z.loc[1, "shaft__rel_amp_8x"] == 0.0
        fast = OrderFeatures().fit(rows.iloc[[1]])
        assert "shaft__rel_amp_8x" in fast.dropped_
        assert "shaft__rel_amp_8x" not in fast.get_feature_names_out()

    def test_still_channel_gives_zeros_without_warnings(self, two_speeds):
        with warnings.catch_warnings():
            warnings.simplefilter("error")
            of = OrderFeatures(channels="casing").fit(two_speeds)
            z = frame_of(of, two_speeds)
            still_only = OrderFeatures(channels="casing").fit(two_speeds.iloc[[0]])
            z0 = still_only.transform(two_speeds.iloc[[0]])
        assert two_speeds.loc[0, "casing__rms"] == 0.0
        assert level_of(two_speeds, "casing")[0] == 0.0
        ratios = [n for n in z.columns if "rel_" in n or "over_floor" in n]
        assert (z.loc[0, ratios] == 0.0).all()
        assert z.loc[1, "casing__rel_amp_1x"] == pytest.approx(A / LEVEL, rel=AMP_REL)
        # a channel still in every training row keeps its ratios (0) and loses its
        # locations (never measured)
        assert np.array_equal(z0, np.zeros_like(z0))
        assert "casing__dev_2x" in still_only.dropped_
        assert "casing__rel_amp_1x" in still_only.get_feature_names_out()


def noise_band_rms(sigma, rpm):
    """RMS of white noise of std ``sigma`` in one band n× ± 0.25× (0.5× wide)."""
    return sigma * np.sqrt(0.5 * rpm / 60.0 / (FS / 2))


class TestNoiseFloor:
    """``bb_<n>x_over_floor``: the broadband around n× over the channel's quietest band."""

    # eight bands of ~50–80 bins each: a band's noise RMS scatters by ~7 %, so the
    # loudest of eight noise-only bands sits well within 1.5 × the quietest
    NOISE_ONLY = (1.0, 1.5)

    def test_noise_only_bands_are_one_at_any_noise_level(self):
        rows = table([(1500.0, {"shaft": orders_signal(1500.0, lines=[(1.0, A)])}),
                      (1500.0, {"shaft": 10.0 * orders_signal(1500.0, lines=[(1.0, 0.1 * A)])}),
                      (2400.0, {"shaft": orders_signal(2400.0, lines=[(1.0, A)], seed=3)})])
        z = frame_of(OrderFeatures(families="sidebands").fit(rows), rows)
        bands = [f"shaft__bb_{n}x_over_floor" for n in HARMONICS]
        assert z[bands].min(axis=1).to_numpy() == pytest.approx(1.0, abs=1e-12)
        assert z[bands].max(axis=1).max() <= self.NOISE_ONLY[1]
        # the same record ten times as loud, noise included: the same features
        assert z.loc[1, bands].to_numpy() == pytest.approx(z.loc[0, bands].to_numpy(), rel=1e-9)

    def test_a_band_with_lines_stands_above_the_floor(self, two_speeds):
        z = frame_of(OrderFeatures(channels="shaft").fit(two_speeds), two_speeds)
        sidebands = np.sqrt((0.05**2 + 0.03**2) / 2)       # the lines 1.8× and 2.2×
        for i, (rpm, scale) in enumerate(((1500.0, 1.0), (2400.0, 3.0))):
            floor = scale * noise_band_rms(NOISE, rpm)
            expected = np.hypot(scale * sidebands, floor) / floor
            # the floor is the least of eight bands' noise estimates (each within ~10 %,
            # Hann-windowed bins being correlated): below the true band RMS, by ≤ 30 %
            assert expected / 1.05 <= z.loc[i, "shaft__bb_2x_over_floor"] <= expected / 0.7
            quiet = [f"shaft__bb_{n}x_over_floor" for n in HARMONICS if n != 2]
            assert z.loc[i, quiet].max() <= self.NOISE_ONLY[1]


class TestBadInput:
    def test_unknown_family(self, two_speeds):
        with pytest.raises(ValueError, match="'spectra'"):
            OrderFeatures(families=("orders", "spectra")).fit(two_speeds)
        with pytest.raises(ValueError, match="families"):
            OrderFeatures(families=()).fit(two_speeds)

    def test_unknown_channel(self, two_speeds):
        with pytest.raises(ValueError, match="'blade'"):
            OrderFeatures(channels=["shaft", "blade"]).fit(two_speeds)

    def test_not_a_frame(self, two_speeds):
        with pytest.raises(TypeError, match="DataFrame"):
            OrderFeatures().fit(two_speeds.to_numpy())

    def test_missing_column_at_transform(self, two_speeds):
        of = OrderFeatures().fit(two_speeds)
        with pytest.raises(ValueError, match="casing__amp_1x"):
            of.transform(two_speeds.drop(columns=["casing__amp_1x"]))

    def test_select_columns(self, two_speeds):
        with pytest.raises(ValueError, match="'nope'"):
            SelectColumns(columns=("speed_rpm", "nope")).fit(two_speeds)
        sel = SelectColumns(columns=("speed_rpm", "shaft__freq_0p5x_hz")).fit(two_speeds)
        np.testing.assert_array_equal(sel.transform(two_speeds), [[1500.0, 0.0],
                                                                  [2400.0, 0.0]])


# The generic scikit-learn checks that need no data. The others generate numpy arrays
# with anonymous columns; OrderFeatures refuses them by design (it needs C__feature names
# and speed_rpm) and SelectColumns needs the columns it is given, so they cannot apply.
API_CHECKS = ("check_estimator_cloneable", "check_estimator_repr",
              "check_no_attributes_set_in_init", "check_parameters_default_constructible",
              "check_get_params_invariance",
              "check_set_params", "check_do_not_raise_errors_in_init_or_set_params",
              "check_mixin_order", "check_transformers_unfitted",
              "check_get_feature_names_out_error", "check_estimator_tags_renamed",
              "check_valid_tag_types")


@pytest.mark.parametrize("check", API_CHECKS)
@pytest.mark.parametrize("estimator", [OrderFeatures(), SelectColumns()],
                         ids=lambda e: type(e).__name__)
def test_sklearn_api_checks(estimator, check):
    getattr(estimator_checks, check)(type(estimator).__name__, estimator)


@pytest.fixture(scope="module")
def level_target():
    """24 runs whose label is the size of the signal only (scale 1 or 4): the order content
    and the noise scale together, so every order-normalised feature is independent of the
    label and only the levels family can tell the classes apart."""
    scales = np.repeat([1.0, 4.0], 12)
    rpm = np.tile([1500.0, 1800.0, 2100.0], 8)
    rows = table([(r, {"shaft": orders_signal(r, scale=s, seed=i)})
                  for i, (r, s) in enumerate(zip(rpm, scales, strict=True))])
    return rows, np.where(scales > 1.0, "large", "small")


# Fast settings of the slow estimators; the pipeline is still make_pipeline's. hgb's
# default min_samples_leaf (20) cannot split 16 training rows at all: it would predict one
# class whatever the features.
FAST = {"rf": {"model__n_estimators": 30},
        "hgb": {"model__max_iter": 20, "model__min_samples_leaf": 3}}


@pytest.mark.parametrize("name", ESTIMATORS)
def test_pipeline_clones_and_grid_searches(name, level_target):
    X, y = level_target
    pipe = make_pipeline(name).set_params(**FAST.get(name, {}))
    assert list(pipe.named_steps) == ["features", "scale", "model"]
    twin = clone(pipe)
    assert twin is not pipe and twin.get_params()["features__families"] == DEFAULT_FAMILIES
    assert not hasattr(twin.named_steps["features"], "recipes_")
    twin.set_params(features__families=("orders", "levels"), features__channels=["shaft"])
    assert pipe.get_params()["features__families"] == DEFAULT_FAMILIES   # a copy
    twin.fit(X, y)
    names = twin[:-1].get_feature_names_out()
    assert "shaft__rms" in names and "shaft__rel_amp_1x" in names
    # grid search over the families: only the levels say which size a run has
    grid = GridSearchCV(pipe, {"features__families": [("orders",), ("orders", "levels")]},
                        cv=StratifiedKFold(3, shuffle=True, random_state=0),
                        scoring="balanced_accuracy")
    grid.fit(X, y)
    assert grid.best_params_["features__families"] == ("orders", "levels")
    assert grid.best_score_ == pytest.approx(1.0)
