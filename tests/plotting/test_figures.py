"""The spectrum, Campbell and deflection figures: what their axes and legends say, and that
forward-whirl markers stay visible where backward whirl has the same frequency."""

from types import SimpleNamespace

import numpy as np
import pytest
from matplotlib.colors import to_rgb

from rubdiag.plotting._modal import _BACKWARD, _FORWARD, campbell_figure, deflection_figure
from rubdiag.plotting._spectra import MARKERS, order_spectra_figure


def _row(**extra):
    row = {"speed_rpm": 600.0, "freq_1x_hz": 10.0, "amp_1x": 2e-6, "freq_2x_hz": np.nan,
           "amp_2x": 0.0}
    row.update(extra)
    return row


def test_spectrum_axis_has_its_unit_and_the_legend_names_each_marker_drawn():
    f = np.linspace(0, 100, 1001)
    amp = np.full(f.size, 1e-8)
    amp[100] = 2e-6
    row = _row(sb_4x_delta_hz=2.0, sb_4x_lower=1e-7, sb_4x_upper=2e-7)
    fig = order_spectra_figure([("shaft", f, amp, row)], unit="µm", scale=1e6)
    ax = fig.axes[0]
    assert ax.get_ylabel() == "peak amplitude (µm)"
    texts = [t.get_text() for t in ax.get_legend().get_texts()]
    assert texts == ["shaft", MARKERS["line"][1], MARKERS["sideband"][1]]   # no combination
    # the markers sit on the scaled amplitudes: 1x at 2 µm, the sidebands at 4x ± 0.2x
    marks = {tuple(np.round(np.c_[line.get_xdata(), line.get_ydata()].ravel(), 6))
             for line in ax.lines[1:]}
    assert (1.0, 2.0) in marks and (3.8, 0.1, 4.2, 0.2) in marks
    # the legend has room above the highest line: the top fifth of the (log) axis is free
    low, high = np.log10(ax.get_ylim())
    assert (high - np.log10(2.0)) / (high - low) > 0.2
    fig.clf()


def test_combination_pair_is_named_in_the_legend():
    f = np.linspace(0, 100, 1001)
    row = _row(combo_fa_hz=4.0, combo_fb_hz=16.0, combo_amp_a=1e-7, combo_amp_b=1e-7)
    fig = order_spectra_figure([("blade", f, np.full(f.size, 1e-8), row)])
    texts = [t.get_text() for t in fig.axes[0].get_legend().get_texts()]
    assert MARKERS["combination"][1] in texts
    assert fig.axes[0].get_ylabel() == "peak amplitude (signal unit)"
    fig.clf()


def test_forward_whirl_shows_where_backward_whirl_coincides(tmp_path):
    """Two modes at the same frequency, one forward, one backward: both colours reach the
    PNG."""
    from matplotlib.image import imread

    speeds = np.linspace(0, 800, 9)
    freq = np.full((9, 2), 2 * np.pi * 20.0)
    campbell = SimpleNamespace(speeds=speeds, frequencies=freq,
                               whirl_ratio=np.tile([1.0, -1.0], (9, 1)),
                               shaft_share=np.ones((9, 2)), critical_speeds=np.array([]))
    campbell_figure(campbell).savefig(tmp_path / "c.png", dpi=100)
    image = imread(tmp_path / "c.png")[:, :, :3]
    # (forward markers drawn first, same size, under the backward ones: 29 and 83 pixels)
    for colour, least in ((_FORWARD, 100), (_BACKWARD, 30)):
        close = np.all(np.abs(image - np.asarray(to_rgb(colour))) < 0.05, axis=-1)
        assert close.sum() > least, colour


def test_deflection_legend_names_bearings_and_discs(paper_model):
    from rubdiag.modal import harmonic_response

    rig = paper_model.rig
    shape = harmonic_response(paper_model, 157.0, rig.unbalance(1))
    fig = deflection_figure(paper_model, {"case 1": shape})
    texts = [t.get_text() for t in fig.axes[0].get_legend().get_texts()]
    bearings = ", ".join(str(b.node) for b in rig.bearings)
    discs = ", ".join(str(d.node) for d in rig.discs)
    assert f"bearings (nodes {bearings})" in texts and f"discs (nodes {discs})" in texts
    fig.clf()


@pytest.mark.parametrize("value, text", [(1e-2, "10⁻²"), (1.0, "10⁰"), (1e3, "10³"),
                                         (3e2, ""), (0.0, "")])
def test_decade_labels_are_plain_text(value, text):
    from rubdiag.plotting._ticks import _decade

    assert _decade(value) == text
