"""Figures of an evaluation and of a noise curve: what they draw is what the data holds."""

from __future__ import annotations

import sys

import numpy as np
import pandas as pd
import pytest

from rubdiag.learn import cross_validate, make_pipeline
from rubdiag.learn._columns import LINE_FEATURES
from rubdiag.learn._figures import confusion_figure, importances_figure, noise_curve_figure

CHANNELS = ("shaft11_y_disp", "shaft11_z_disp", "bearing2_y_acc")
CLASSES = ("full", "none", "partial")
NOISE = ("amp_1p5x", "amp_2x", "amp_0p5x", "sb_2x_upper", "sb_3x_lower", "bb_2x_rms",
         "amp_1p33x", "combo_amp_a")


def synthetic_rows(n_points: int = 18, replicates: int = 2, seed: int = 0) -> pd.DataFrame:
    """Dataset-like rows: three classes of ``rub_state``; the 1.5× line of
    ``shaft11_y_disp`` (beside a strong 1×) tells them apart, with overlap; a few other
    features are noise, the rest zero (a forest finds the one that matters among few)."""
    rng = np.random.default_rng(seed)
    state = np.repeat(np.resize(CLASSES, n_points), replicates)
    n = state.size
    cols = {"run_id": [f"{i:08x}" for i in range(n)],
            "point_id": np.repeat(np.arange(n_points), replicates),
            "speed_rpm": np.full(n, 3000.0), "rub_state": state}
    for c in CHANNELS:
        for f in LINE_FEATURES:
            cols[f"{c}__{f}"] = np.zeros(n)
        for f in NOISE:
            cols[f"{c}__{f}"] = rng.random(n)
        cols[f"{c}__rms"] = np.ones(n)
    code = np.searchsorted(CLASSES, state)
    cols["shaft11_y_disp__amp_1p5x"] = 1.0 + code + rng.normal(0.0, 0.45, n)
    # a 1× line that dominates the channel's level, as on a rotor: the 1.5× line's share of
    # the level (what the classifier sees) then follows its amplitude
    cols["shaft11_y_disp__amp_1x"] = np.full(n, 20.0)
    return pd.DataFrame(cols)


@pytest.fixture(scope="module")
def evaluation():
    # a small forest: the figures need an evaluation, not a good model
    pipe = make_pipeline("rf", channels=list(CHANNELS)).set_params(model__n_estimators=50)
    return cross_validate(synthetic_rows(), "rub_state", pipeline=pipe, n_splits=3, n_bootstrap=50,
                    n_null=20, n_repeats=2, baselines=False, audit=False)


def _texts(ax):
    return [t.get_text() for t in ax.texts]


class TestConfusionFigure:
    def test_cells_read_counts_and_row_percentages(self, evaluation, tmp_path):
        fig = confusion_figure(evaluation, tmp_path / "c.png")
        assert (tmp_path / "c.png").stat().st_size > 0
        ax = fig.axes[0]
        cm = evaluation.confusion.to_numpy()
        assert cm.sum() > 0 and (cm != np.diag(np.diag(cm))).any()  # not a trivial matrix
        expected = sorted(f"{cm[i, j]}\n{100 * cm[i, j] / cm[i].sum():.0f} %"
                          for i in range(3) for j in range(3))
        assert sorted(_texts(ax)) == expected
        # each annotation sits on its own cell: x = predicted column, y = true row
        for t in ax.texts:
            j, i = (round(v) for v in t.get_position())
            assert t.get_text().split("\n")[0] == str(cm[i, j])

    def test_colour_is_recall_and_every_class_labelled(self, evaluation, tmp_path):
        fig = confusion_figure(evaluation, tmp_path / "c.png")
        ax = fig.axes[0]
        cm = evaluation.confusion.to_numpy()
        shown = np.asarray(ax.images[0].get_array())
        np.testing.assert_allclose(shown, cm / cm.sum(axis=1, keepdims=True))
        np.testing.assert_allclose(np.diag(shown), evaluation.per_class["recall"])
        assert [t.get_text() for t in ax.get_xticklabels()] == list(CLASSES)
        assert [t.get_text().split("\n")[0] for t in ax.get_yticklabels()] == list(CLASSES)

    def test_title_states_what_was_scored(self, evaluation, tmp_path):
        title = confusion_figure(evaluation, tmp_path / "c.png").axes[0].get_title()
        f1 = evaluation.scores["macro_f1"]
        for part in ("rub_state", "rf", "split group", f"{f1.value:.3f}", f"{f1.lo:.3f}",
                     f"{f1.hi:.3f}"):
            assert part in title

    def test_a_class_never_seen_leaves_an_empty_row(self, evaluation, tmp_path):
        ev = _with_confusion(evaluation, [[5, 1, 0], [0, 0, 0], [2, 0, 7]])
        fig = confusion_figure(ev, tmp_path / "c.png")
        assert len(fig.axes[0].texts) == 6
        assert np.isnan(np.asarray(fig.axes[0].images[0].get_array())[1]).all()


def _with_confusion(evaluation, counts):
    from dataclasses import replace

    index = pd.Index(CLASSES, name="true")
    return replace(evaluation, confusion=pd.DataFrame(counts, index=index,
                                                      columns=pd.Index(CLASSES)))


class TestImportancesFigure:
    def test_one_bar_per_top_feature_in_order(self, evaluation, tmp_path):
        top = 7
        fig = importances_figure(evaluation, tmp_path / "i.png", top=top)
        ax_f = fig.axes[0]
        expected = evaluation.importances.sort_values("importance", ascending=False).head(top)
        bars = ax_f.patches
        assert len(bars) == top
        # bars from top to bottom (y grows downwards after the inverted limits)
        bars = sorted(bars, key=lambda b: b.get_y())
        np.testing.assert_allclose([b.get_width() for b in bars], expected["importance"])
        labels = {round(t.get_position()[1]): t.get_text() for t in ax_f.get_yticklabels()}
        assert [labels[i] for i in range(top)] == list(expected.index)
        assert ax_f.get_ylim()[0] > ax_f.get_ylim()[1]           # first row drawn on top

    def test_the_separating_feature_leads(self, evaluation, tmp_path):
        ax_f = importances_figure(evaluation, tmp_path / "i.png").axes[0]
        first = min(ax_f.get_yticklabels(), key=lambda t: t.get_position()[1])
        # the 1.5× line's share of the level, or the 1× line's, which falls as it grows:
        # both carry the separating line, no noise feature does
        assert first.get_text() in ("rel_amp_1p5x", "rel_amp_1x")
        assert first.get_text() == evaluation.importances["importance"].idxmax()

    def test_channel_panel_has_every_channel_and_error_bars(self, evaluation, tmp_path):
        fig = importances_figure(evaluation, tmp_path / "i.png")
        ax_c = fig.axes[1]
        shown = [t.get_text() for t in ax_c.get_yticklabels()]
        assert sorted(shown) == sorted(evaluation.channel_importances.index)
        assert shown[0] == "shaft11_y_disp"
        # the error bars' half-lengths are the std column
        segments = ax_c.collections[0].get_segments()
        half = sorted(float(s[1][0] - s[0][0]) / 2 for s in segments)
        np.testing.assert_allclose(half, sorted(evaluation.channel_importances["std"]),
                                   atol=1e-12)

    def test_long_names_stay_inside_the_figure(self, evaluation, tmp_path):
        fig = importances_figure(evaluation, tmp_path / "i.png", top=20)
        renderer = fig.canvas.get_renderer()
        width = fig.bbox.width
        for ax in fig.axes:
            for t in ax.get_yticklabels():
                box = t.get_window_extent(renderer)
                assert box.x0 >= 0 and box.x1 <= width

    def test_a_panel_of_zeros_says_why_instead_of_drawing_nothing(self, evaluation,
                                                                 tmp_path):
        from dataclasses import replace

        zero = evaluation.channel_importances.assign(importance=0.0, std=0.0)
        fig = importances_figure(replace(evaluation, channel_importances=zero),
                                 tmp_path / "i.png")
        ax_f, ax_c = fig.axes
        assert len(ax_f.patches) == 20 and not ax_f.texts       # features: bars as before
        assert not ax_c.patches
        (text,) = [" ".join(t.get_text().split()) for t in ax_c.texts]   # lines unwrapped
        assert text.startswith("No bars: every importance is 0.")
        # this model's held-out predictions are of several classes
        assert "do not depend on these features" in text
        # the words stay inside the figure at its saved size
        renderer = fig.canvas.get_renderer()
        box = ax_c.texts[0].get_window_extent(renderer)
        assert box.x0 >= 0 and box.x1 <= fig.bbox.width
        assert box.y0 >= 0 and box.y1 <= fig.bbox.height

    def test_no_importances_is_a_clear_error(self, evaluation, tmp_path):
        from dataclasses import replace

        with pytest.raises(ValueError, match="importances=True"):
            importances_figure(replace(evaluation, importances=None), tmp_path / "i.png")
        with pytest.raises(ValueError, match="top"):
            importances_figure(evaluation, tmp_path / "i.png", top=0)


def _curve():
    return pd.DataFrame({
        "snr_db": [np.inf, 30.0, 20.0, 10.0, 5.0],
        "macro_f1": [0.95, 0.93, 0.85, 0.7, 0.55],
        "macro_f1_lo": [0.9, 0.88, 0.78, 0.6, 0.45],
        "macro_f1_hi": [1.0, 0.98, 0.92, 0.8, 0.65],
    })


class TestNoiseCurveFigure:
    def test_points_fall_to_the_right_and_as_stored_is_marked(self, tmp_path):
        curve = _curve()
        ax = noise_curve_figure(curve, tmp_path / "n.png", chance=0.5).axes[0]
        line = ax.lines[0]
        x, y = line.get_xdata(), line.get_ydata()
        np.testing.assert_allclose(x, [30, 20, 10, 5])
        np.testing.assert_allclose(y, curve["macro_f1"][1:])
        left, right = ax.get_xlim()
        assert left > right                                  # SNR decreases to the right
        ticks = {t.get_text(): t.get_position()[0] for t in ax.get_xticklabels()}
        assert "as\nstored" in ticks and ticks["as\nstored"] > 30   # left of every level
        star = [ln for ln in ax.lines if ln.get_marker() == "*"]
        assert len(star) == 1 and star[0].get_ydata()[0] == pytest.approx(0.95)
        assert any(ln.get_label() == "chance" and ln.get_ydata()[0] == 0.5
                   for ln in ax.lines)

    def test_interval_band_spans_lo_to_hi(self, tmp_path):
        curve = _curve()
        ax = noise_curve_figure(curve, tmp_path / "n.png").axes[0]
        band = ax.collections[0].get_paths()[0].vertices
        for snr, lo, hi in zip(curve.snr_db[1:], curve.macro_f1_lo[1:], curve.macro_f1_hi[1:],
                               strict=True):
            ys = band[np.isclose(band[:, 0], snr), 1]
            assert ys.min() == pytest.approx(lo) and ys.max() == pytest.approx(hi)

    def test_chance_band_from_the_curve(self, tmp_path):
        curve = _curve().assign(chance_lo=0.3, chance_hi=0.6)
        ax = noise_curve_figure(curve, tmp_path / "n.png").axes[0]
        assert any(p.get_label().startswith("chance") for p in ax.patches)

    def test_refuses_a_table_that_is_not_a_curve(self, tmp_path):
        with pytest.raises(ValueError, match="macro_f1_lo"):
            noise_curve_figure(_curve().drop(columns="macro_f1_lo"), tmp_path / "n.png")


def test_importing_learn_does_not_import_matplotlib():
    import subprocess

    code = "import rubdiag.learn, sys; print('matplotlib' in sys.modules)"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True)
    assert out.stdout.strip() == "False"
