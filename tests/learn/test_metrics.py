"""Scores, their bootstrap intervals over design points, and the permutation null.

Point values are checked against scikit-learn's metrics; intervals against what resampling
whole groups implies (1/√n narrowing, no narrowing from rows copied inside a group) and
the null against the exact moments of a permutation of fixed margins.
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from sklearn.metrics import (
    balanced_accuracy_score,
    confusion_matrix,
    f1_score,
    recall_score,
)

from rubdiag.learn._metrics import (
    confusion,
    group_permutations,
    macro_f1,
    null_interval,
    score,
)

CLASSES = ["light", "none", "serious", "unseen"]

labels = st.lists(st.tuples(st.sampled_from(CLASSES[:3]), st.sampled_from(CLASSES)),
                  min_size=1, max_size=60)


@settings(max_examples=150, deadline=None)
@given(pairs=labels)
def test_point_values_match_sklearn(pairs):
    y_true = np.array([t for t, _ in pairs])
    y_pred = np.array([p for _, p in pairs])
    present = sorted(set(y_true))
    # macro over the classes present in the truth; a class only predicted (here "unseen")
    # costs precision of nobody but recall of the rows it took
    f1 = f1_score(y_true, y_pred, labels=present, average="macro", zero_division=0)
    recall = recall_score(y_true, y_pred, labels=present, average="macro", zero_division=0)
    assert macro_f1(y_true, y_pred, CLASSES) == pytest.approx(f1, abs=1e-12)
    s = score(y_true, y_pred, np.arange(y_true.size), CLASSES, n_bootstrap=0)
    assert s["macro_f1"].value == pytest.approx(f1, abs=1e-12)
    assert s["balanced_accuracy"].value == pytest.approx(recall, abs=1e-12)
    if len(present) > 1 and set(y_pred) <= set(y_true):   # its own case (else it warns)
        assert s["balanced_accuracy"].value == pytest.approx(
            balanced_accuracy_score(y_true, y_pred), abs=1e-12)
    np.testing.assert_array_equal(confusion(y_true, y_pred, CLASSES),
                                  confusion_matrix(y_true, y_pred, labels=CLASSES))


def test_confusion_refuses_an_unknown_prediction():
    with pytest.raises(ValueError, match="not one of the classes"):
        confusion(["a", "b"], ["a", "c"], ["a", "b"])


def noisy_prediction(n_groups, rows_per_group, seed, accuracy=0.7):
    """Random truths over three classes, predicted right with probability ``accuracy``."""
    rng = np.random.default_rng(seed)
    n = n_groups * rows_per_group
    y_true = rng.choice(CLASSES[:3], size=n)
    y_pred = np.where(rng.random(n) < accuracy, y_true, rng.choice(CLASSES[:3], size=n))
    return y_true, y_pred, np.repeat(np.arange(n_groups), rows_per_group)


def widths(scores):
    return np.array([s.hi - s.lo for s in scores.values()])


class TestBootstrap:
    def test_interval_holds_the_value(self):
        for seed in range(3):
            s = score(*noisy_prediction(40, 2, seed), CLASSES[:3], n_bootstrap=500, seed=seed)
            for v in s.values():
                assert v.lo < v.value < v.hi

    def test_perfect_prediction_has_no_spread(self):
        y = np.repeat(["none", "light"], 10)
        s = score(y, y, np.arange(20) // 2, CLASSES, n_bootstrap=200)
        for v in s.values():
            assert (v.value, v.lo, v.hi) == (1.0, 1.0, 1.0)

    @pytest.mark.parametrize("seed", [0, 1])
    def test_narrows_as_one_over_sqrt_groups(self, seed):
        # the same prediction on 50, 200 and 800 design points (new copies of the points):
        # the bootstrap spread of a smooth statistic goes as 1/√n, so each 4× halves the
        # interval. Monte-Carlo error of a 2000-draw percentile width is about 3 %, 4 % on
        # a ratio of two; the nonlinearity of F1 at 50 points adds a little: ±12 % (the
        # ratios of seeds 0…4 lie in 1.91…2.13).
        y_true, y_pred, groups = noisy_prediction(50, 2, seed)
        w = []
        for copies in (1, 4, 16):
            g = np.concatenate([groups + 1000 * c for c in range(copies)])
            w.append(widths(score(np.tile(y_true, copies), np.tile(y_pred, copies), g,
                                  CLASSES[:3], n_bootstrap=2000, seed=seed)))
        np.testing.assert_allclose(w[0] / w[1], 2.0, rtol=0.12)
        np.testing.assert_allclose(w[1] / w[2], 2.0, rtol=0.12)

    def test_rows_copied_inside_their_group_change_nothing(self):
        # every row twice, in its own group: the same design points, the same information.
        # A whole-group bootstrap draws the same groups with the same seed and every
        # confusion matrix doubles, so every score and interval is exactly the same.
        y_true, y_pred, groups = noisy_prediction(30, 2, seed=3)
        once = score(y_true, y_pred, groups, CLASSES[:3], n_bootstrap=500, seed=7)
        twice = score(np.repeat(y_true, 2), np.repeat(y_pred, 2), np.repeat(groups, 2),
                      CLASSES[:3], n_bootstrap=500, seed=7)
        for k in once:
            assert twice[k].value == pytest.approx(once[k].value, abs=1e-12)
            assert twice[k].lo == pytest.approx(once[k].lo, abs=1e-12)
            assert twice[k].hi == pytest.approx(once[k].hi, abs=1e-12)

    def test_resamples_groups_not_rows(self):
        # 60 design points of 8 identical replicates: grouped, the interval is that of 60
        # draws; drawing rows (each row its own group) would make it √8 ≈ 2.8 × narrower.
        y_true, y_pred, groups = noisy_prediction(60, 1, seed=4)
        reps = 8
        grouped = score(np.repeat(y_true, reps), np.repeat(y_pred, reps),
                        np.repeat(groups, reps), CLASSES[:3], n_bootstrap=2000, seed=1)
        by_row = score(np.repeat(y_true, reps), np.repeat(y_pred, reps),
                       np.arange(60 * reps), CLASSES[:3], n_bootstrap=2000, seed=1)
        np.testing.assert_allclose(widths(grouped) / widths(by_row), np.sqrt(reps),
                                   rtol=0.12)


class TestNullInterval:
    # 600 rows: truth 300/200/100, predictions 100/300/200 of the same classes. Shuffling
    # the predictions fixes both margins, so each tp_i is hypergeometric with mean
    # s_i·q_i/n, and F1_i = 2 tp_i / (s_i + q_i) is linear in it: the null mean of
    # macro-F1 is exactly mean_i 2 s_i q_i / (n (s_i + q_i)); that of balanced accuracy
    # mean_i q_i / n = 1/3. The variance of balanced accuracy follows from the covariances
    # of the diagonal of a table with fixed margins:
    # var tp_i = s_i q_i (n − s_i)(n − q_i) / (n² (n − 1)),
    # cov(tp_i, tp_j) = s_i q_i s_j q_j / (n² (n − 1)).
    s = np.array([300, 200, 100])
    q = np.array([100, 300, 200])
    n = 600

    def prediction(self):
        y_true = np.repeat(CLASSES[:3], self.s)
        y_pred = np.random.default_rng(0).permutation(np.repeat(CLASSES[:3], self.q))
        return y_true, y_pred

    def test_centred_on_the_chance_macro_f1(self):
        s, q, n = self.s, self.q, self.n
        mean = np.mean(2 * s * q / (n * (s + q)))
        for seed in range(3):
            lo, hi = null_interval(*self.prediction(), CLASSES, n=2000, seed=seed)
            # Monte-Carlo error of the midpoint of 2.5/97.5 % percentiles of 2000 draws:
            # about 0.06 σ = 0.015 of the width; the skew of these hypergeometrics is
            # smaller still: 10 % of the width is several times both
            assert lo < mean < hi
            assert abs((lo + hi) / 2 - mean) < 0.1 * (hi - lo)

    def test_balanced_accuracy_null_has_the_exact_spread(self):
        s, q, n = self.s, self.q, self.n
        var = np.sum(q * (n - s) * (n - q) / (s * n**2 * (n - 1)))
        var += sum(q[i] * q[j] / (n**2 * (n - 1))
                   for i in range(3) for j in range(3) if i != j)
        sd = np.sqrt(var) / 3
        lo, hi = null_interval(*self.prediction(), CLASSES, n=2000, seed=0,
                               metric="balanced_accuracy")
        # near-normal at n = 600: the 95 % interval is 2 × 1.96 σ around 1/3, to the
        # Monte-Carlo error of the percentiles (≈ 3 % of the width) and the discreteness
        assert (lo + hi) / 2 == pytest.approx(1 / 3, abs=0.1 * (hi - lo))
        assert hi - lo == pytest.approx(2 * 1.96 * sd, rel=0.08)

    def test_a_perfect_prediction_lies_far_above_it(self):
        y = np.repeat(CLASSES[:3], self.s)
        hi = null_interval(y, y, CLASSES, n=500)[1]
        assert hi < 0.5 < macro_f1(y, y, CLASSES)


def test_group_permutations_move_whole_groups():
    # groups of 1, 2 and 3 rows, rows of a group scattered
    groups = np.array(["a", "b", "c", "a", "d", "c", "e", "c", "f", "b", "g"])
    perms = group_permutations(groups, 200, np.random.default_rng(0))
    assert perms.shape == (200, groups.size)
    rows_of = {g: list(np.flatnonzero(groups == g)) for g in set(groups)}
    seen = set()
    for perm in perms:
        np.testing.assert_array_equal(np.sort(perm), np.arange(groups.size))
        for g, rows in rows_of.items():
            sources = perm[rows]
            donor = groups[sources[0]]
            assert list(sources) == rows_of[donor]          # a whole group, in order
            seen.add((g, donor))
    # every group of one row received every other one-row group at least once
    singles = [g for g, r in rows_of.items() if len(r) == 1]
    assert {(g, h) for g in singles for h in singles} <= seen


def test_null_of_replicated_points_is_that_of_the_points():
    # 8 identical replicates of each of 60 points: shuffled point by point, the null is
    # exactly that of the 60 points (each confusion matrix times 8, drawn from the same
    # stream); shuffled row by row it would be about √8 times narrower
    rng = np.random.default_rng(2)
    y_true = rng.choice(CLASSES[:3], 60)
    y_pred = rng.choice(CLASSES[:3], 60)
    reps, groups = 8, np.repeat(np.arange(60), 8)
    points = null_interval(y_true, y_pred, CLASSES, n=2000, seed=4)
    grouped = null_interval(np.repeat(y_true, reps), np.repeat(y_pred, reps), CLASSES,
                            n=2000, seed=4, groups=groups)
    by_row = null_interval(np.repeat(y_true, reps), np.repeat(y_pred, reps), CLASSES,
                           n=2000, seed=4)
    np.testing.assert_allclose(grouped, points, atol=1e-12)
    # Monte-Carlo error of each width ≈ 3 %: 12 % on the ratio is several of it
    assert (grouped[1] - grouped[0]) / (by_row[1] - by_row[0]) == pytest.approx(
        np.sqrt(reps), rel=0.12)


def test_group_permutations_within_strata():
    groups = np.array([0, 0, 1, 1, 2, 2, 3, 3, 4, 5, 6])
    strata = np.array([0, 0, 0, 0, 1, 1, 1, 1, 0, 0, 1])
    perms = group_permutations(groups, 200, np.random.default_rng(1), strata=strata)
    for perm in perms:
        np.testing.assert_array_equal(strata[perm], strata)      # nothing crosses a stratum
    # and within a stratum the groups do move: groups 0 and 1 swap in some permutation
    assert (perms[:, 0] == 2).any() and (perms[:, 0] == 0).any()
    with pytest.raises(ValueError, match="strata"):
        group_permutations(groups, 2, np.random.default_rng(1),
                           strata=np.array([0, 1, 0, 0, 1, 1, 1, 1, 0, 0, 1]))


def test_null_within_folds_is_exact_for_a_no_information_cross_validated_model():
    """Labels shuffled between 60 points (2 rows each), 5 fixed bands of 12 points; in
    each band a model without information predicts each point a class drawn at (its
    training side's class rates)³, normalised — so its predictions follow the training
    composition, which mirrors the band's own. Given the training side, the band's labels
    are any arrangement of its own multiset: the null within folds is exact, and the
    shuffled-label score falls inside its 95 % interval 95 % of the time (300 trials:
    binomial σ = 0.013; ≥ 0.92 is 2.4 σ below)."""
    classes = ["a", "b", "c"]
    rng = np.random.default_rng(0)
    labels = np.array(["a"] * 27 + ["b"] * 9 + ["c"] * 24)
    groups, band_of_point = np.repeat(np.arange(60), 2), np.repeat(np.arange(5), 12)
    band = np.repeat(band_of_point, 2)
    trials, inside = 300, 0
    for trial in range(trials):
        shuffled = rng.permutation(labels)
        pred = np.empty(120, dtype=object)
        for b in range(5):
            rates = np.array([np.mean(shuffled[band_of_point != b] == c) for c in classes])
            drawn = rng.choice(classes, size=12, p=rates**3 / (rates**3).sum())
            pred[band == b] = np.repeat(drawn, 2)
        y = np.repeat(shuffled, 2)
        lo, hi = null_interval(y, pred, classes, n=400, seed=trial, groups=groups,
                               strata=band)
        inside += lo <= macro_f1(y, pred, classes) <= hi
    assert inside / trials >= 0.92
