"""Figures (a leaf layer: nothing else in rubdiag imports it).

Every figure function draws on the axes (``ax=``) or, for a figure of several axes, the
figure (``fig=``) it is given, else on a new ``matplotlib.figure.Figure`` of its own, and
returns the figure; :func:`save_figure` writes it (the figure, then the path). No module
chooses a matplotlib backend: the command line draws with Agg.

* the rig's linear behaviour: :func:`campbell_figure`, :func:`unbalance_figure`,
  :func:`deflection_figure`;
* a simulated run: :func:`run_figure` (and :func:`save_run_figures`, its figures as files);
* spectra: :func:`order_spectra_figure`, :func:`full_spectrum_figure`;
* faults beside rub: :func:`faults_figure`;
* run-ups: :func:`waterfall_figure`, :func:`order_map_figure`, :func:`bode_figure`,
  :func:`polar_figure`, :func:`rub_orders_figure` (and :func:`runup_figures`,
  :func:`save_runup_figures`, all of them).
"""

from rubdiag._figures import save_figure
from rubdiag.plotting._faults import faults_figure, full_spectrum_figure
from rubdiag.plotting._modal import campbell_figure, deflection_figure, unbalance_figure
from rubdiag.plotting._run import run_figure, save_run_figures
from rubdiag.plotting._runup import (
    bode_figure,
    polar_figure,
    rub_orders_figure,
    runup_figures,
    save_runup_figures,
)
from rubdiag.plotting._runup_maps import order_map_figure, waterfall_figure
from rubdiag.plotting._spectra import order_spectra_figure

__all__ = [
    "bode_figure",
    "campbell_figure",
    "deflection_figure",
    "faults_figure",
    "full_spectrum_figure",
    "order_map_figure",
    "order_spectra_figure",
    "polar_figure",
    "rub_orders_figure",
    "run_figure",
    "runup_figures",
    "save_figure",
    "save_run_figures",
    "save_runup_figures",
    "unbalance_figure",
    "waterfall_figure",
]
