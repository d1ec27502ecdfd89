"""Folds that do not leak: design points (and factor bands) on one side only."""

from __future__ import annotations

import re

import numpy as np
import pandas as pd
import pytest

from rubdiag.learn._splits import folds, split_names


def design_rows(values: dict, replicates, seed=0):
    """Rows of design points: ``values`` maps a factor to one value per point;
    ``replicates`` is one count per point (or one count for all). Rows are shuffled, so
    that nothing can rely on replicates being adjacent."""
    n_points = len(next(iter(values.values())))
    reps = np.broadcast_to(replicates, n_points)
    point = np.repeat(np.arange(n_points), reps)
    rows = pd.DataFrame({"point_id": [f"p{i:03d}" for i in point],
                         "replicate": np.concatenate([np.arange(r) for r in reps])})
    for name, v in values.items():
        rows[name] = np.asarray(v)[point]
    order = np.random.default_rng(seed).permutation(len(rows))
    return rows.iloc[order].reset_index(drop=True)


def assert_partition(data, splits):
    """Each fold splits every row into train and test; the tests cover every row once;
    no design point has rows on both sides."""
    n = len(data)
    tests = np.concatenate([f.test for f in splits])
    np.testing.assert_array_equal(np.sort(tests), np.arange(n))
    for f in splits:
        np.testing.assert_array_equal(np.sort(np.concatenate([f.train, f.test])),
                                      np.arange(n))
        ids = data["point_id"].to_numpy()
        assert not set(ids[f.train]) & set(ids[f.test]), f.name


def test_group_folds_keep_replicates_together():
    rng = np.random.default_rng(1)
    data = design_rows({"gap_mm": rng.uniform(0.5, 3.0, 23)}, rng.integers(1, 4, 23))
    y = np.where(data["gap_mm"] < 1.5, "serious", np.where(data["gap_mm"] < 2.2, "light",
                                                            "none"))
    for target in (y, None):
        for seed in (0, 1):
            splits = folds(data, "group", target, n_splits=5, seed=seed)
            assert len(splits) == 5
            assert_partition(data, splits)


def test_group_folds_are_stratified():
    # 30 points, a third of each class: StratifiedGroupKFold puts 2 points of every class
    # in each of 5 test folds
    data = design_rows({"gap_mm": np.arange(30) / 10.0}, 2)
    y = np.array(["a", "b", "c"])[(data["gap_mm"] * 10).round().astype(int) % 3]
    for f in folds(data, "group", y, n_splits=5):
        counts = pd.Series(y[f.test]).value_counts()
        assert sorted(counts.index) == ["a", "b", "c"] and (counts == 4).all(), f.name


def held_out_range(fold):
    """The (lo, hi) a fold's name says it holds out."""
    numbers = [float(v) for v in re.findall(r"-?\d+\.?\d*(?:e[-+]?\d+)?", fold.name)]
    return numbers[0], numbers[-1]


@pytest.mark.parametrize("factor", ["speed_ratio", "gap_mm", "mu"])
def test_band_folds_hold_out_contiguous_ranges(factor):
    # 40 points on a grid of 0.1 (distinct values, shuffled), 2 or 3 replicates each;
    # 4 quantile bands of 10 points
    rng = np.random.default_rng(2)
    values = rng.permutation(np.arange(1, 41) / 10.0)
    data = design_rows({factor: values, "case": rng.integers(1, 3, 40)},
                       rng.integers(2, 4, 40))
    splits = folds(data, factor, bands=4)
    assert len(splits) == 4
    assert_partition(data, splits)
    x = data[factor].to_numpy()
    for f in splits:
        lo, hi = held_out_range(f)
        assert factor in f.name
        assert data.iloc[f.test]["point_id"].nunique() == 10
        assert x[f.test].min() == lo and x[f.test].max() == hi
        train = x[f.train]
        assert not ((train >= lo) & (train <= hi)).any(), f.name


def test_band_folds_with_tied_values():
    # 6 levels, 3 points each: the bands cut between levels, never through one, and no
    # training point lies inside the held-out range (qcut's lower edges belong to the
    # band below)
    data = design_rows({"gap_mm": np.repeat([0.5, 1.0, 1.5, 2.0, 2.5, 3.0], 3)}, 2)
    splits = folds(data, "gap_mm", bands=3)
    assert len(splits) == 3
    assert_partition(data, splits)
    x = data["gap_mm"].to_numpy()
    for f in splits:
        lo, hi = held_out_range(f)
        assert x[f.test].min() == lo and x[f.test].max() == hi
        assert not ((x[f.train] >= lo) & (x[f.train] <= hi)).any(), f.name


def test_few_levels_give_one_fold_per_level():
    rng = np.random.default_rng(3)
    data = design_rows({"case": rng.permutation(np.repeat([1, 2], 6)),
                        "gap_mm": rng.permutation(np.repeat([0.7, 1.6, 3.5], 4))}, 2)
    for factor, bands, levels in (("case", 5, [1, 2]), ("gap_mm", 3, [0.7, 1.6, 3.5])):
        splits = folds(data, factor, bands=bands)
        assert len(splits) == len(levels)
        assert_partition(data, splits)
        for f, level in zip(splits, levels, strict=True):
            assert (data.iloc[f.test][factor] == level).all()
            assert (data.iloc[f.train][factor] != level).all()
            assert f.name == f"held out: {factor} = {level:g}"


def test_split_names_are_group_and_the_factors():
    data = design_rows({"case": [1, 2], "gap_mm": [1.0, 2.0]}, 1)
    data["rub"] = True
    assert split_names(data) == ["group", "case", "gap_mm"]


class TestBadInput:
    data = design_rows({"case": np.repeat([1, 2], 4), "gap_mm": np.full(8, 1.0)}, 2)

    @pytest.mark.parametrize("split", ["points", "mu", "rub"])
    def test_unknown_split(self, split):
        with pytest.raises(ValueError, match=f"split = '{split}' is not available"):
            folds(self.data, split)

    @pytest.mark.parametrize("n_splits", [1, 9])     # 8 design points
    def test_n_splits(self, n_splits):
        with pytest.raises(ValueError, match=f"n_splits = {n_splits} is out of range"):
            folds(self.data, "group", n_splits=n_splits)

    def test_n_splits_type(self):
        with pytest.raises(ValueError, match=r"n_splits = 2\.5"):
            folds(self.data, "group", n_splits=2.5)

    def test_bands(self):
        with pytest.raises(ValueError, match="bands = 1 is out of range"):
            folds(self.data, "case", bands=1)

    def test_constant_factor(self):
        with pytest.raises(ValueError, match=r"split = 'gap_mm'.*one value"):
            folds(self.data, "gap_mm")

    def test_no_point_id(self):
        with pytest.raises(ValueError, match="point_id"):
            folds(self.data.drop(columns="point_id"), "group")
