"""The axes helpers the run-up figures share (:mod:`rubdiag.plotting._runup`,
:mod:`rubdiag.plotting._runup_maps`): axes placed by fixed margins, round ticks, plain
decade labels, and the critical speeds as an array.
"""

from __future__ import annotations

import numpy as np
from matplotlib.ticker import FuncFormatter, LogLocator, MaxNLocator, NullFormatter

from rubdiag._figures import new_figure
from rubdiag.plotting._run import DPI

__all__ = ["ROUND_STEPS", "criticals", "figure_axes", "log_labels", "round_ticks"]

ROUND_STEPS = (1, 2, 2.5, 5, 10)    # tick steps: 100, 200, 250, 500 rpm …
_PLAIN = FuncFormatter(lambda v, _pos=None: f"{v:g}")


def figure_axes(size, left, right, bottom, top, fig=None, **subplots):
    """Axes on ``fig`` (default a new figure of ``size`` at ``DPI``), placed by fixed margins
    (inches): constrained layout measures every label again."""
    fig = new_figure(figsize=size, dpi=DPI) if fig is None else fig
    width, height = fig.get_size_inches()
    axes = fig.subplots(**subplots)
    fig.subplots_adjust(left=left / width, right=1 - right / width, bottom=bottom / height,
                        top=1 - top / height)
    return fig, axes


def round_ticks(ax, x: int | None = 8, y: int | None = 6) -> None:
    """At most about ``x``/``y`` ticks at round steps (fewer tick objects draw faster)."""
    for axis, n in ((ax.xaxis, x), (ax.yaxis, y)):
        if n is not None:
            axis.set_major_locator(MaxNLocator(n, steps=ROUND_STEPS))


def log_labels(axis) -> None:
    """Decades of a log axis as plain numbers (0.1, 1, 10 …); no minor labels."""
    axis.set_major_locator(LogLocator(base=10.0))
    axis.set_major_formatter(_PLAIN)
    axis.set_minor_formatter(NullFormatter())


def criticals(critical_rpm) -> np.ndarray:
    """The critical speed(s) (rpm) as a 1-D array; none: empty."""
    return np.atleast_1d(np.asarray([] if critical_rpm is None else critical_rpm, dtype=float))
