"""One figure convention: a figure function draws on the axes (``ax=``) or figure (``fig=``)
it is given and returns that figure, else returns a new figure that pyplot does not hold;
``save_figure(fig, path)`` writes it; ``save_runup_figures`` takes what it draws, then where
(the earlier order still works)."""

from __future__ import annotations

from types import SimpleNamespace

import matplotlib.pyplot as plt
import numpy as np
import pandas as pd
import pytest
from matplotlib.figure import Figure
from matplotlib.image import imread

from rubdiag.learn._figures import noise_curve_figure
from rubdiag.plotting import save_figure
from rubdiag.plotting._faults import full_spectrum_figure
from rubdiag.plotting._modal import campbell_figure, unbalance_figure
from rubdiag.plotting._runup import (
    RUB_ORDERS,
    bode_figure,
    polar_figure,
    rub_orders_figure,
    save_runup_figures,
)
from rubdiag.plotting._runup_maps import order_map_figure, waterfall_figure
from rubdiag.plotting._spectra import order_spectra_figure
from rubdiag.signal import order_label

RPM = np.linspace(1000.0, 2000.0, 21)
Z = 1e-4 * np.exp(-1j * np.linspace(0.1, 3.0, RPM.size)) / (1.1 - RPM / 2000.0)


def _track() -> pd.DataFrame:
    columns = {"rpm": RPM, "amp_1x": np.abs(Z), "phase_1x_deg": np.angle(Z, deg=True)}
    for k in RUB_ORDERS:
        columns[f"amp_{order_label(k)}"] = np.full(RPM.size, 1e-6)
        columns[f"phase_{order_label(k)}_deg"] = np.zeros(RPM.size)
    return pd.DataFrame(columns)


TRACKS = {"run-up": _track()}
F_HZ = np.arange(0.0, 200.0, 1.0)
MAP = np.ones((F_HZ.size, RPM.size)) * 1e-6
FS = 1024.0
T = np.arange(2048) / FS
ROW = {"speed_rpm": 1500.0}
CAMPBELL = SimpleNamespace(
    speeds=np.linspace(0.0, 600.0, 5), frequencies=np.outer(np.ones(5), [100.0, 400.0]),
    shaft_share=np.ones((5, 2)), whirl_ratio=np.outer(np.ones(5), [1.0, -1.0]),
    critical_speeds=np.array([300.0]))
RESPONSE = SimpleNamespace(speeds=np.linspace(10.0, 600.0, 30),
                           amplitudes=np.linspace(1e-5, 1e-3, 30)[:, None] + 0j)
CURVE = pd.DataFrame({"snr_db": [np.inf, 20.0, 10.0], "macro_f1": [0.9, 0.7, 0.4],
                      "macro_f1_lo": [0.8, 0.6, 0.3], "macro_f1_hi": [1.0, 0.8, 0.5]})

#: name -> (draw(**where), "ax" or "fig")
FIGURES = {
    "campbell": (lambda **w: campbell_figure(CAMPBELL, **w), "ax"),
    "unbalance": (lambda **w: unbalance_figure({"case 1": RESPONSE}, (1500.0,), **w), "ax"),
    "order spectra": (lambda **w: order_spectra_figure(
        [("y", np.linspace(0, 200, 401), np.linspace(1, 2, 401), ROW)], **w), "ax"),
    "polar": (lambda **w: polar_figure(TRACKS, **w), "ax"),
    "noise curve": (lambda **w: noise_curve_figure(CURVE, **w), "ax"),
    "full spectrum": (lambda **w: full_spectrum_figure(
        np.cos(2 * np.pi * 25 * T), np.sin(2 * np.pi * 25 * T), FS, 25.0, **w), "fig"),
    "bode": (lambda **w: bode_figure(TRACKS, **w), "fig"),
    "rub orders": (lambda **w: rub_orders_figure(TRACKS, **w), "fig"),
    "waterfall": (lambda **w: waterfall_figure(F_HZ, RPM, MAP, **w), "fig"),
    "order map": (lambda **w: order_map_figure(F_HZ, RPM, MAP, **w), "fig"),
}


@pytest.mark.parametrize("name", FIGURES)
def test_a_figure_function_draws_where_it_is_told_and_returns_that_figure(name):
    draw, where = FIGURES[name]
    before = plt.get_fignums()
    own = draw()
    assert isinstance(own, Figure) and own.axes
    fig = Figure()
    if where == "ax":
        ax = fig.add_subplot()
        assert draw(ax=ax) is fig
        assert ax.lines or ax.collections or ax.images
    else:
        assert draw(fig=fig) is fig
        assert len(fig.axes) == len(own.axes)
    assert plt.get_fignums() == before          # pyplot holds none of them


def test_save_figure_writes_the_figure_at_its_resolution(tmp_path):
    fig = Figure(figsize=(4.0, 3.0), dpi=50)
    fig.add_subplot().plot([0, 1], [1, 0])
    path = save_figure(fig, tmp_path / "new" / "line.png")
    assert path == tmp_path / "new" / "line.png"
    assert imread(path).shape[:2] == (150, 200)
    assert imread(save_figure(fig, tmp_path / "fine.png", dpi=100)).shape[:2] == (300, 400)


def test_save_runup_figures_takes_what_then_where_and_still_the_earlier_order(tmp_path):
    now = save_runup_figures(TRACKS, tmp_path / "now", stem="s")
    before = save_runup_figures(tmp_path / "before", TRACKS, stem="s")
    assert [p.name for p in now] == [p.name for p in before] == [
        "s_bode.png", "s_polar.png", "s_rub_orders.png"]
    for a, b in zip(now, before, strict=True):
        np.testing.assert_array_equal(imread(a), imread(b))
