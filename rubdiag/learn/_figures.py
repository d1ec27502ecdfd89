"""Figures of an evaluation and of a noise curve, saved as PNG.

* :func:`confusion_figure` — the confusion matrix normalised by row (recall), each cell
  with its count and percentage;
* :func:`importances_figure` — permutation importances of the features and of the
  channels, with their spread;
* :func:`noise_curve_figure` — macro-F1 against the SNR of added noise
  (:func:`rubdiag.learn._robustness.noise_curve`).

Each draws on the axes ``ax`` (the importances, two panels: the figure ``fig``) when given,
else on a figure of its own, and returns the figure; :func:`save_figure` writes it. The
``path`` argument is kept for calls that draw and save in one (``confusion_figure(evaluation,
"cm.png")``). Matplotlib is imported inside the functions, so that importing
:mod:`rubdiag.learn` does not import it. Figures are built with ``matplotlib.figure.Figure``
and drawn by the Agg canvas, never through pyplot: no global figure list to leak from a long
training loop. The look follows :mod:`rubdiag.plotting` (its colours, ``DPI`` 110, fast PNG
compression), which this layer may not import (it sits above ``rubdiag.learn``).
"""

from __future__ import annotations

import math
import textwrap

import numpy as np

from rubdiag import _check
from rubdiag._figures import figure_and_axes, new_figure, save_figure

__all__ = ["DPI", "confusion_figure", "importances_figure", "noise_curve_figure",
           "save_figure"]

DPI = 110                                  # as rubdiag.plotting._run
_EMPTY_ROWS = 6                            # height of a figure with no bar at all
_TEXT_WIDTH = 40                           # characters per line of words in a panel
_BLUE, _RED, _GREY = "#2471a3", "#c0392b", "0.6"


def _figure(size):
    return new_figure(figsize=size, dpi=DPI, layout="constrained")


def _saved(fig, path):
    """``fig``, written to ``path`` first when one is given."""
    if path is not None:
        save_figure(fig, path, dpi=DPI)
    return fig


def _headline(evaluation) -> str:
    f1 = evaluation.scores["macro_f1"]
    return (f"{evaluation.target}: {evaluation.estimator}, split {evaluation.split}\n"
            f"macro-F1 {f1.value:.3f} (95 % CI {f1.lo:.3f}–{f1.hi:.3f})")


def confusion_figure(evaluation, path=None, *, ax=None):
    """The held-out confusion matrix as a heat map normalised by row.

    Colour is the share of each true class predicted as each class (the diagonal is the
    recall); each cell reads ``count`` over ``percentage of its row``. A class with no
    scored row shows an empty (white) row.

    Parameters
    ----------
    evaluation : Evaluation
        From :func:`rubdiag.learn._evaluate` (``confusion``: rows true, columns predicted).
    path : str or Path, optional
        A PNG to write the figure to (parent folders are made); default none
        (:func:`save_figure` writes it).
    ax : matplotlib.axes.Axes, optional
        Axes to draw on (with its colour bar beside it); default a new figure sized for
        the number of classes.

    Returns
    -------
    matplotlib.figure.Figure
    """
    cm = evaluation.confusion
    counts = cm.to_numpy(dtype=np.int64)
    k = counts.shape[0]
    totals = counts.sum(axis=1, keepdims=True)
    with np.errstate(invalid="ignore", divide="ignore"):
        share = np.where(totals > 0, counts / totals, np.nan)
    labels_true = [str(c) for c in cm.index]
    labels_pred = [str(c) for c in cm.columns]
    side = 1.0 + 0.95 * k
    fig, ax = figure_and_axes(ax, figsize=(side + 2.4, side + 1.4), dpi=DPI,
                              layout="constrained")
    image = ax.imshow(share, cmap="Blues", vmin=0.0, vmax=1.0)
    for i in range(k):
        for j in range(k):
            if not np.isfinite(share[i, j]):
                continue
            ax.text(j, i, f"{counts[i, j]}\n{100 * share[i, j]:.0f} %", ha="center",
                    va="center", fontsize="medium",
                    color="white" if share[i, j] > 0.55 else "black")
    ax.set_xticks(range(k), labels_pred)
    ax.set_yticks(range(k), [f"{c}\n(n = {n})" for c, n in zip(labels_true, totals[:, 0],
                                                                   strict=True)])
    if max(map(len, labels_pred)) > 8:
        ax.tick_params(axis="x", labelrotation=30)
    ax.set(xlabel="predicted", ylabel="true")
    ax.set_title(_headline(evaluation), fontsize="medium")
    fig.colorbar(image, ax=ax, shrink=0.8, label="share of the true class (recall)")
    return _saved(fig, path)


def importances_figure(evaluation, path=None, top: int = 20, *, fig=None):
    """Permutation importances: the ``top`` features (left) and every channel (right).

    A bar is the mean drop of held-out macro-F1 when that feature (in every channel at
    once) or that channel (all its features) is permuted; the error bar its standard
    deviation over folds × repeats. Largest on top; a bar left of zero means permuting
    helped (noise). A panel whose importances are all 0 — no permutation changed the
    score, as for a model that predicts one class whatever its input — says so in words
    instead of drawing bars of length 0.

    Parameters
    ----------
    evaluation : Evaluation
        From :func:`rubdiag.learn._evaluate` with ``importances=True``.
    path : str or Path, optional
        A PNG to write the figure to; default none (:func:`save_figure` writes it).
    top : int
        Features shown (>= 1).
    fig : matplotlib.figure.Figure, optional
        An empty figure to draw the panels on; default a new one sized for the bars.

    Returns
    -------
    matplotlib.figure.Figure
    """
    top = _check.integer("top", top, lo=1)
    features = evaluation.importances
    if features is None or features.empty:
        raise ValueError("evaluation.importances is None: no importances were computed "
                         "(call evaluate(..., importances=True))")
    features = features.sort_values("importance", ascending=False, kind="stable").head(top)
    channels = evaluation.channel_importances
    panels = [(features, f"features (top {len(features)} of "
                         f"{len(evaluation.importances)}, every channel at once)")]
    if channels is not None and not channels.empty:
        channels = channels.sort_values("importance", ascending=False, kind="stable")
        panels.append((channels, "channels (all their features at once)"))
    empty = [_nothing_to_show(frame) for frame, _ in panels]
    # an empty panel lists no rows: the figure is as tall as its drawn panels need
    rows = max([len(p[0]) for p, e in zip(panels, empty, strict=True) if not e],
               default=_EMPTY_ROWS)
    if fig is None:
        fig = _figure((12.0 if len(panels) == 2 else 7.5, 1.6 + 0.3 * rows))
    grid = fig.add_gridspec(1, len(panels), width_ratios=[1.25, 1.0][:len(panels)])
    for n, ((frame, title), nothing) in enumerate(zip(panels, empty, strict=True)):
        ax = fig.add_subplot(grid[0, n])
        ax.set_title(title, fontsize="medium")
        ax.set_xlabel("drop of held-out macro-F1 when permuted")
        if nothing:
            ax.set(xticks=[], yticks=[])
            ax.text(0.5, 0.5, _why_no_bars(evaluation), transform=ax.transAxes,
                    ha="center", va="center", fontsize="medium", linespacing=1.4)
            continue
        y = np.arange(len(frame))
        ax.barh(y, frame["importance"], xerr=frame["std"], color=(_BLUE, _RED)[n],
                height=0.7, error_kw={"ecolor": "0.25", "elinewidth": 0.9, "capsize": 2})
        ax.set_yticks(y, [str(i) for i in frame.index])
        # largest on top; both panels on the same row pitch, so that bars are as thick
        ax.set_ylim(rows - 0.5, -0.5)
        ax.axvline(0.0, color="0.3", lw=0.8)
        ax.grid(axis="x", alpha=0.3)
    fig.suptitle(_headline(evaluation).replace("\n", "; "), fontsize="large")
    return _saved(fig, path)


def _nothing_to_show(frame) -> bool:
    """Every importance and spread exactly 0: no permutation changed the score."""
    values = frame[["importance", "std"]].to_numpy(dtype=float)
    return bool(np.all(values == 0.0))


def _why_no_bars(evaluation) -> str:
    """The words an empty importance panel shows instead of bars of length 0."""
    scored = evaluation.predictions.loc[evaluation.predictions["scored"], "predicted"]
    classes = sorted(set(map(str, scored)))
    what = (f"the model predicts {classes[0]} for every held-out run, whatever its "
            "features." if len(classes) == 1 else
            "the held-out predictions do not depend on these features.")
    paragraphs = ["No bars: every importance is 0.",
                  "No permutation of a feature or a channel changed the held-out macro-F1: "
                  + what, "The model learnt nothing to rank; see the warnings of its report."]
    return "\n\n".join(textwrap.fill(p, _TEXT_WIDTH) for p in paragraphs)


def noise_curve_figure(curve, path=None, chance=None, *, ax=None):
    """Macro-F1 with its 95 % interval against the SNR of the added noise.

    The SNR falls to the right (more noise); the "as stored" row (``snr_db`` = inf: no
    noise added) is drawn left of the finite levels as a star, on its own tick.

    Parameters
    ----------
    curve : DataFrame
        From :func:`rubdiag.learn._robustness.noise_curve`: ``snr_db``, ``macro_f1``,
        ``macro_f1_lo``, ``macro_f1_hi`` per row.
    path : str or Path, optional
        A PNG to write the figure to; default none (:func:`save_figure` writes it).
    chance : float or (float, float), optional
        Chance level (a line) or chance interval (a band). Default: the curve's
        ``chance_lo``/``chance_hi`` columns (their median over levels) when present.
    ax : matplotlib.axes.Axes, optional
        Axes to draw on; default a new 7.5 × 4.5 in figure.

    Returns
    -------
    matplotlib.figure.Figure
    """
    needed = ["snr_db", "macro_f1", "macro_f1_lo", "macro_f1_hi"]
    missing = [c for c in needed if c not in curve.columns]
    if missing:
        raise ValueError(f"curve: no column {missing[0]!r} (a noise_curve table is needed)")
    snr = curve["snr_db"].to_numpy(dtype=float)
    finite = np.isfinite(snr)
    if np.isnan(snr).any() or not finite.any():
        raise ValueError("curve: snr_db must hold finite levels (and inf for 'as stored')")
    if chance is None and {"chance_lo", "chance_hi"} <= set(curve.columns):
        chance = (float(np.median(curve["chance_lo"])), float(np.median(curve["chance_hi"])))
    order = np.argsort(-snr[finite])
    x = snr[finite][order]
    rows = curve[finite].iloc[order]
    span = max(float(x.max() - x.min()), 10.0)
    stored_x = float(x.max()) + 0.2 * span
    fig, ax = figure_and_axes(ax, figsize=(7.5, 4.5), dpi=DPI, layout="constrained")
    ax.fill_between(x, rows["macro_f1_lo"], rows["macro_f1_hi"], color=_BLUE, alpha=0.2,
                    lw=0, label="95 % interval")
    ax.plot(x, rows["macro_f1"], "o-", color=_BLUE, label="macro-F1 with added noise")
    for _, row in curve[~finite].iterrows():
        ax.errorbar([stored_x], [row["macro_f1"]],
                    yerr=[[row["macro_f1"] - row["macro_f1_lo"]],
                          [row["macro_f1_hi"] - row["macro_f1"]]],
                    fmt="*", ms=13, color=_RED, capsize=3, label="as stored (no noise added)")
    if chance is not None:
        if np.ndim(chance) == 0:
            ax.axhline(float(chance), color=_GREY, ls="--", label="chance")
        else:
            lo, hi = (float(v) for v in chance)
            ax.axhspan(lo, hi, color=_GREY, alpha=0.25, lw=0, label="chance (95 % interval)")
    ticks = list(x) + ([stored_x] if (~finite).any() else [])
    names = [f"{v:g}" for v in x] + (["as\nstored"] if (~finite).any() else [])
    ax.set_xticks(ticks, names)
    ax.set_xlim(stored_x + 0.08 * span if (~finite).any() else x.max() + 0.08 * span,
                x.min() - 0.08 * span)                   # inverted: more noise to the right
    ax.set_ylim(0.0, 1.05)
    ax.set(xlabel="SNR of the added noise (dB, re median channel power over rubbing runs)"
           "  →  more noise", ylabel="held-out macro-F1")
    title = "Noise robustness"
    target = curve.attrs.get("target")
    if target:
        title += (f": {target}, {curve.attrs.get('estimator', '')}, split "
                  f"{curve.attrs.get('split', '')}")
    ax.set_title(title, fontsize="medium")
    ax.grid(alpha=0.3)
    ax.legend(loc="best", fontsize="small")
    if math.isfinite(stored_x) and (~finite).any():
        ax.axvline(float(x.max()) + 0.1 * span, color="0.4", lw=0.8, ls=":")
    return _saved(fig, path)
