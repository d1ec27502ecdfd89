"""Run-up and coast-down figures: what each draws is the data it was given — the marked peak is
the track's largest amplitude, order lines lie on k·rpm/60, the dashed linear response and the
polar curve are the input's complex amplitudes, the phase is unwrapped — on synthetic sweeps."""

from __future__ import annotations

import matplotlib.pyplot as plt
import numpy as np
import pandas as pd
import pytest
from matplotlib.image import imread

from rubdiag.plotting._run import DPI
from rubdiag.plotting._runup import (
    RUB_ORDERS,
    bode_figure,
    polar_figure,
    rub_orders_figure,
    save_runup_figures,
)
from rubdiag.plotting._runup_maps import ORDERS, order_map_figure, waterfall_figure
from rubdiag.signal import order_label, order_track

CRITICAL = 1500.0
LAG = np.exp(-1j * np.radians(60.0))    # extra lag: the phase passes -180° and wraps


def _response(rpm, zeta=0.05, critical=CRITICAL):
    """A single-degree-of-freedom unbalance response (m), lagging by 60° more: its phase
    falls from -60° through -150° (at ``critical``) to about -240°."""
    r = np.asarray(rpm, dtype=float) / critical
    return LAG * 1e-3 * r**2 / (1.0 - r**2 + 2j * zeta * r)


def _track(rpm, z) -> pd.DataFrame:
    """An order_track-like table: 1× as given, the rub orders at 1 µm."""
    rpm = np.asarray(rpm, dtype=float)
    columns = {"rev_start": np.arange(rpm.size) * 8, "t_s": np.arange(rpm.size) * 0.1,
               "rpm": rpm, "amp_1x": np.abs(z), "phase_1x_deg": np.angle(z, deg=True)}
    for k in RUB_ORDERS:
        columns[f"amp_{order_label(k)}"] = np.full(rpm.size, 1e-6 * k)
        columns[f"phase_{order_label(k)}_deg"] = np.zeros(rpm.size)
    return pd.DataFrame(columns)


@pytest.fixture(autouse=True)
def _close_figures():
    yield
    plt.close("all")


@pytest.fixture
def sweeps():
    """A run-up whose peak lags to 1540 rpm and a coast-down peaking early, at 1460 rpm, with
    different peak amplitudes; speeds on a 10 rpm grid."""
    up = np.arange(1000.0, 2001.0, 10.0)
    down = up[::-1]
    return {"run-up": _track(up, 0.9 * _response(up, 0.06, 1540.0)),
            "coast-down": _track(down, 0.8 * _response(down, 0.06, 1460.0))}


@pytest.fixture
def linear():
    rpm = np.linspace(900.0, 2100.0, 241)
    return rpm, _response(rpm)


def _gid(ax, gid):
    lines = [line for line in ax.lines if line.get_gid() == gid]
    assert lines, gid
    return lines


class TestBode:
    def test_each_peak_is_marked_and_annotated_at_its_track_maximum(self, sweeps, linear):
        fig = bode_figure(sweeps, linear, critical_rpm=CRITICAL)
        ax = fig.axes[0]
        notes = {a.get_gid(): a for a in ax.texts}
        for name, df in sweeps.items():
            j = int(np.argmax(df.amp_1x))
            peak = (df.rpm[j], df.amp_1x[j] * 1e6)
            (marker,) = _gid(ax, f"peak {name}")
            np.testing.assert_allclose(np.c_[marker.get_xdata(), marker.get_ydata()][0], peak)
            note = notes[f"peak {name}"]
            np.testing.assert_allclose(note.xy, peak)
            assert note.get_text() == f"{name}: peak {peak[1]:.0f} µm at {peak[0]:.0f} rpm"
        # the peaks are those of the synthetic sweeps: late going up, early coming down
        assert notes["peak run-up"].xy[0] > CRITICAL > notes["peak coast-down"].xy[0]
        # every annotation lies inside the amplitude axes, above the highest curve
        top = max(np.abs(linear[1]).max(), *(df.amp_1x.max() for df in sweeps.values())) * 1e6
        assert ax.get_ylim()[1] > top

    def test_the_dashed_linear_response_is_the_input(self, sweeps, linear):
        fig = bode_figure(sweeps, linear)
        rpm, z = linear
        (amp,) = _gid(fig.axes[0], "linear")
        (phase,) = _gid(fig.axes[1], "linear")
        assert amp.get_linestyle() == "--" and phase.get_linestyle() == "--"
        np.testing.assert_array_equal(amp.get_xdata(), rpm)
        np.testing.assert_allclose(amp.get_ydata(), np.abs(z) * 1e6, rtol=1e-12)
        np.testing.assert_array_equal(phase.get_xdata(), rpm)
        # unwrapped from the wrapped input: the same angles, whole turns apart
        assert np.abs(np.diff(np.angle(z, deg=True))).max() > 180
        assert np.abs(np.diff(phase.get_ydata())).max() < 180
        turns = (phase.get_ydata() - np.angle(z, deg=True)) / 360.0
        np.testing.assert_allclose(turns, np.round(turns), atol=1e-9)

    def test_the_phase_is_unwrapped_and_the_sweeps_share_their_turns(self, sweeps):
        down = sweeps["coast-down"]
        assert np.abs(np.diff(down.phase_1x_deg)).max() > 180      # the input wraps
        fig = bode_figure(sweeps)               # no linear response: the first track leads
        lines = {name: _gid(fig.axes[1], f"track {name}")[0] for name in sweeps}
        for name, line in lines.items():
            y = line.get_ydata()
            assert np.abs(np.diff(y)).max() < 180
            turns = (y - sweeps[name].phase_1x_deg) / 360.0
            np.testing.assert_allclose(turns, np.round(turns), atol=1e-9)
        up = lines["run-up"].get_ydata()
        assert -180 < up[0] <= 180                  # the lowest speed within ±180°
        # both sweeps at 1000 rpm (its first bin for one, last for the other) within 5°
        assert abs(up[0] - lines["coast-down"].get_ydata()[-1]) < 5

    def test_markers_point_the_way_the_speed_went(self, sweeps):
        fig = bode_figure(sweeps)
        for ax in fig.axes:
            assert _gid(ax, "track run-up")[0].get_marker() == ">"
            assert _gid(ax, "track coast-down")[0].get_marker() == "<"

    def test_the_critical_speed_is_marked_on_both_panels(self, sweeps):
        fig = bode_figure(sweeps, critical_rpm=CRITICAL)
        for ax in fig.axes:
            (line,) = _gid(ax, "critical")
            np.testing.assert_array_equal(line.get_xdata(), [CRITICAL, CRITICAL])
        assert "critical speed" in [t.get_text() for t in fig.axes[0].get_legend().get_texts()]

    def test_contact_spans_are_bars_from_first_to_last_contact(self, sweeps):
        contact = {"run-up": (1362.0, 1988.0), "coast-down": (1706.0, 1348.0)}
        fig = bode_figure(sweeps, contact_rpm=contact)
        ax = fig.axes[0]
        heights = []
        for name, span in contact.items():
            (bar,) = _gid(ax, f"contact {name}")
            np.testing.assert_array_equal(bar.get_xdata(), span)
            heights.append(bar.get_ydata()[0])
            assert f"{name}: contact {span[0]:.0f} → {span[1]:.0f} rpm" in [
                t.get_text() for t in ax.texts]
        assert heights[1] > heights[0]              # one row each
        # a track without contact (NaN) gets no bar
        fig = bode_figure(sweeps, contact_rpm={"run-up": (np.nan, np.nan)})
        gids = [line.get_gid() or "" for line in fig.axes[0].lines]
        assert not [gid for gid in gids if gid.startswith("contact")]

    def test_a_missing_order_is_named(self, sweeps):
        with pytest.raises(ValueError, match=r"'run-up' has no column amp_4x, phase_4x_deg"):
            bode_figure(sweeps, order=4)


class TestPolar:
    def test_the_curves_are_the_complex_amplitudes(self, sweeps, linear):
        fig = polar_figure(sweeps, linear, critical_rpm=CRITICAL)
        ax = fig.axes[0]
        for name, df in sweeps.items():
            (line,) = _gid(ax, f"track {name}")
            z = df.amp_1x * np.exp(1j * np.radians(df.phase_1x_deg)) * 1e6
            np.testing.assert_allclose(line.get_xdata() + 1j * line.get_ydata(), z,
                                       rtol=1e-12, atol=1e-9)
        (lin,) = _gid(ax, "linear")
        np.testing.assert_allclose(lin.get_xdata() + 1j * lin.get_ydata(), linear[1] * 1e6)
        (critical,) = _gid(ax, "critical")      # on the linear response, at 1500 rpm
        j = int(np.flatnonzero(linear[0] == CRITICAL)[0])
        np.testing.assert_allclose(critical.get_xdata()[0] + 1j * critical.get_ydata()[0],
                                   linear[1][j] * 1e6)

    def test_round_speeds_are_labelled_on_the_curve(self, sweeps):
        fig = polar_figure(sweeps)
        ax = fig.axes[0]
        df = sweeps["run-up"]
        (dots,) = _gid(ax, "speeds run-up")
        labels = [float(t.get_text()) for t in ax.texts if t.get_color() == dots.get_color()]
        assert len(labels) >= 4 and all(r % 100 == 0 for r in labels)
        rows = df.set_index("rpm").loc[labels]
        z = rows.amp_1x * np.exp(1j * np.radians(rows.phase_1x_deg)) * 1e6
        np.testing.assert_allclose(dots.get_xdata() + 1j * dots.get_ydata(), z, rtol=1e-9)

    def test_a_simulated_sweep_lies_on_its_response(self):
        """End to end through the signal layer: x = Re(z(Ω) e^{iφ}) swept at 100 rpm/s,
        order-tracked; the polar curve lies on z at the bins' speeds (the convention of
        order_track, harmonic_response and the figure is one)."""
        fs, rate = 2000.0, 100.0
        t = np.arange(0.0, 10.0, 1.0 / fs)
        rpm = 1000.0 + rate * t
        phi = 2 * np.pi * (1000.0 * t + 0.5 * rate * t**2) / 60.0
        x = np.real(_response(rpm, zeta=0.2) * np.exp(1j * phi))
        track = order_track(x, fs, phi, orders=(1,), revs_per_bin=4)
        fig = polar_figure({"run-up": track})
        (line,) = _gid(fig.axes[0], "track run-up")
        expected = _response(track.rpm, zeta=0.2) * 1e6
        drawn = line.get_xdata() + 1j * line.get_ydata()
        assert np.abs(drawn - expected).max() < 0.01 * np.abs(expected).max()


class TestColourMaps:
    @pytest.mark.parametrize("step", [25.0, -25.0], ids=["run-up", "coast-down"])
    def test_waterfall_order_lines_lie_on_k_rpm_over_60(self, step):
        rpm = np.arange(1000.0, 2001.0, 25.0)[:: int(np.sign(step))]
        f = np.arange(0.0, 500.0, 0.5)
        amp = np.full((f.size, rpm.size), 1e-9)
        amp[np.rint(rpm / 60.0 / 0.5).astype(int), np.arange(rpm.size)] = 1e-4     # 1×
        fig = waterfall_figure(f, rpm, amp, critical_rpm=CRITICAL)
        ax = fig.axes[0]
        y0, y1 = ax.get_ylim()
        for k in ORDERS:
            (line,) = _gid(ax, f"order {order_label(k)}")
            np.testing.assert_array_equal(line.get_ydata(), [y0, y1])
            np.testing.assert_allclose(line.get_xdata(), k * np.array([y0, y1]) / 60.0,
                                       rtol=1e-15)
        assert {f"{k:g}×" for k in ORDERS} <= {t.get_text() for t in ax.texts}
        # the map covers every segment's speed, drawn in speed order, 60 dB below the top
        assert y0 <= rpm.min() and y1 >= rpm.max()
        (mesh,) = ax.collections
        kept = (f > 0) & (f <= 1.05 * 4 * 2000 / 60)
        drawn = mesh.get_array().reshape(rpm.size, kept.sum())
        order = np.argsort(rpm)
        np.testing.assert_allclose(drawn, np.maximum(amp[kept][:, order].T * 1e6, 0.1))
        assert mesh.norm.vmax == pytest.approx(100.0) and mesh.norm.vmin == pytest.approx(0.1)
        (critical,) = _gid(ax, "critical")
        np.testing.assert_array_equal(critical.get_ydata(), [CRITICAL, CRITICAL])

    def test_order_map_guides_stand_at_their_orders(self):
        orders = np.arange(0.0, 25.01, 0.125)
        rpm = np.linspace(1000.0, 2000.0, 30)
        amp = np.full((orders.size, rpm.size), 1e-8)
        amp[8] = 1e-4
        fig = order_map_figure(orders, rpm, amp)
        ax = fig.axes[0]
        for k in ORDERS:
            (line,) = _gid(ax, f"order {order_label(k)}")
            np.testing.assert_array_equal(line.get_xdata(), [k, k])
            np.testing.assert_array_equal(line.get_ydata(), ax.get_ylim())
        x0, x1 = ax.get_xlim()
        assert 0 < x0 < 0.125 and 10.0 <= x1 < 10.125      # order 0 left out; up to 2.5 × 4
        assert ax.get_ylim()[0] <= 1000.0 and ax.get_ylim()[1] >= 2000.0

    def test_a_map_of_the_wrong_shape_is_refused(self):
        with pytest.raises(ValueError, match=r"allowed: \(5, 3\)"):
            waterfall_figure(np.arange(5.0), np.arange(3.0) + 1000, np.ones((3, 5)))


def test_rub_orders_one_log_panel_per_order(sweeps):
    fig = rub_orders_figure(sweeps, critical_rpm=CRITICAL)
    assert len(fig.axes) == len(RUB_ORDERS)
    for ax, k in zip(fig.axes, RUB_ORDERS, strict=True):
        assert ax.get_yscale() == "log" and ax.get_ylabel() == f"{k:g}× (µm)"
        for name, df in sweeps.items():
            (line,) = _gid(ax, f"track {name}")
            np.testing.assert_allclose(line.get_ydata(), df[f"amp_{order_label(k)}"] * 1e6)
        _gid(ax, "critical")


def test_rub_orders_draw_the_trackings_leakage(sweeps):
    """Dashed in each track's colour: what its changing 1× leaks into each order
    (tracking_leakage, tested against the analytic level in tests/signal/test_leakage.py),
    named in the legend; only where the bin length is known."""
    from rubdiag.signal._leakage import tracking_leakage

    fig = rub_orders_figure(sweeps, revs_per_bin=8)
    for ax, k in zip(fig.axes, RUB_ORDERS, strict=True):
        for name, df in sweeps.items():
            (line,) = _gid(ax, f"leakage {name}")
            (track,) = _gid(ax, f"track {name}")
            leak = tracking_leakage(df, 8, RUB_ORDERS)[f"amp_{order_label(k)}"] * 1e6
            np.testing.assert_allclose(line.get_ydata(), leak)
            assert line.get_linestyle() == "--" and line.get_color() == track.get_color()
    texts = [t.get_text() for t in fig.axes[0].get_legend().get_texts()]
    assert texts[-1] == "1× leakage of the tracking (8-rev bins): not rub"

    def leakage_lines(figure):
        return [ln for ax in figure.axes for ln in ax.lines
                if str(ln.get_gid()).startswith("leakage")]

    assert not leakage_lines(rub_orders_figure(sweeps))     # a table read back from CSV
    for df in sweeps.values():                              # order_track's own tables
        df.attrs["revs_per_bin"] = 8
    assert len(leakage_lines(rub_orders_figure(sweeps))) == 2 * len(RUB_ORDERS)


def test_save_writes_every_figure(tmp_path, sweeps, linear):
    f = np.arange(0.0, 200.0, 1.0)
    rpm = np.linspace(1000.0, 2000.0, 12)
    maps = {"run-up": (f, rpm, np.ones((f.size, rpm.size)) * 1e-6)}
    paths = save_runup_figures(tmp_path, sweeps, stem="case1", linear=linear,
                               critical_rpm=CRITICAL, contact_rpm={"run-up": (1400, 1600)},
                               waterfalls=maps, order_maps=maps)
    names = [p.name for p in paths]
    assert names == ["case1_bode.png", "case1_polar.png", "case1_rub_orders.png",
                     "case1_waterfall_run_up.png", "case1_order_map_run_up.png"]
    height, width = imread(paths[0]).shape[:2]
    assert (width, height) == (round(8.5 * DPI), round(7.0 * DPI))
    assert not plt.get_fignums()                # saved figures are closed
