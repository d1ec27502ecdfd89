"""Figures (a leaf layer: nothing else in rubdiag imports it).

Every figure function draws on the axes (``ax=``) or, for a figure of several axes, the
figure (``fig=``) it is given, else on a new ``matplotlib.figure.Figure`` of its own, and
returns the figure; :func:`save_figure` writes it (the figure, then the path). No module
chooses a matplotlib backend: the command line draws with Agg.
"""

from rubdiag._figures import save_figure

__all__ = ["save_figure"]
