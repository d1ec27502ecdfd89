"""One convention for every figure of rubdiag: a figure function draws on the axes (``ax=``)
or the figure (``fig=``, for figures of several axes) it is given, else on a new figure of
its own, and returns the figure; saving is a separate step, :func:`save_figure` (the figure,
then the path).

New figures are ``matplotlib.figure.Figure`` objects, not pyplot's: drawing them needs and
chooses no backend (the command line picks Agg), and no global list holds them, so a loop
that makes figures frees each one it drops. In a notebook a returned figure shows as any
figure does. Matplotlib is imported inside the functions: importing a module that draws does
not import it.
"""

from __future__ import annotations

from pathlib import Path

#: PNG compression (zlib level 1: 35 % faster to write than the default 6, 15 % larger)
PNG_OPTIONS = {"compress_level": 1}


def new_figure(**options):
    """A new ``matplotlib.figure.Figure`` (``options``: its ``figsize``, ``dpi``,
    ``layout`` …), drawn by the Agg canvas."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    fig = Figure(**options)
    FigureCanvasAgg(fig)
    return fig


def figure_and_axes(ax=None, **options):
    """``(figure, axes)`` to draw one panel on: ``ax`` and its figure when given, else a new
    figure (:func:`new_figure` with ``options``) holding one axes."""
    if ax is not None:
        return ax.figure, ax
    fig = new_figure(**options)
    return fig, fig.add_subplot()


def save_figure(fig, path, *, dpi: float | None = None) -> Path:
    """Write ``fig`` to ``path`` (parent folders are made).

    Parameters
    ----------
    fig : matplotlib.figure.Figure
        The figure a figure function returned.
    path : str or Path
        The file to write, e.g. ``"out/campbell.png"``; its format from the suffix (PNG
        without one). Written whole or not at all.
    dpi : float, optional
        Resolution (dots per inch); default the figure's own.

    Returns
    -------
    Path
        The written file.
    """
    import io

    from rubdiag._atomic import write_bytes

    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    kind = path.suffix.lower().lstrip(".") or "png"
    png = {"pil_kwargs": PNG_OPTIONS} if kind == "png" else {}
    buffer = io.BytesIO()       # drawn first, then written whole: no half-written file
    fig.savefig(buffer, format=kind, dpi=fig.dpi if dpi is None else dpi, **png)
    return write_bytes(path, buffer.getvalue())
