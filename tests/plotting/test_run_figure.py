"""The run figure (Figs. 7-10, ``rubdiag plot``): the contact-status panel (f) shows every
segment of the per-step status log in the PNG the command writes, the spectra and waveform
panels say what they show."""

import dataclasses
import itertools

import numpy as np
import pytest
from matplotlib.colors import to_rgb
from matplotlib.image import imread

from rubdiag.cli import main
from rubdiag.plotting._run import DPI, FIGSIZE, STATUS_COLOURS, ZOOM_REVOLUTIONS, run_figure
from rubdiag.simulation import Run, simulate

LANE = {2: 0.2, 3: -0.2}        # sliding above, sticking below the element's row centre


@pytest.fixture(scope="module")
def result():
    """A short case-2 run with two 2-step episodes added to its status log, each lying
    between two output samples in a quiet stretch of its element's row."""
    res = simulate(Run.paper_case(2, 2.3, duration_s=0.5, discard_s=0.2))
    seg = res.system.status_segments
    dt, out_dt = res.run.dt_s, res.run.output_dt_s
    added = []
    for status in (2, 3):
        element, (a, b) = max(((k, _widest_gap(seg, k, res.run.discard_s, res.t[-1]))
                               for k in range(1, 9) if k not in [e for e, *_ in added]),
                              key=lambda item: item[1][1] - item[1][0])
        start = np.floor(0.5 * (a + b) / out_dt) * out_dt + 3 * dt
        added.append((element, status, start, start + 2 * dt))
    element, status, start, end = (np.array(column) for column in zip(*added, strict=True))
    log = dataclasses.replace(seg, element=np.r_[seg.element, element],
                              status=np.r_[seg.status, status].astype(np.int8),
                              t_start=np.r_[seg.t_start, start], t_end=np.r_[seg.t_end, end])
    res = dataclasses.replace(res, system=dataclasses.replace(res.system, status_segments=log))
    return res, added


@pytest.fixture(scope="module")
def png(result, tmp_path_factory):
    """The PNG ``rubdiag plot`` writes for the result, and where panel (f)'s data lands in
    it (the same figure, laid out at the same size and DPI)."""
    res, _ = result
    folder = tmp_path_factory.mktemp("plot")
    path = res.save(folder / "r.npz")
    assert main(["plot", str(path), "--out", str(folder / "figs")]) == 0
    image = imread(folder / "figs" / "r.png")[:, :, :3]
    fig = run_figure(res)
    fig.draw_without_rendering()
    ax = next(a for a in fig.axes if a.get_title().startswith("(f)"))
    scale = DPI / fig.dpi

    def pixel(t, y):
        x_px, y_px = ax.transData.transform((t, y)) * scale
        return image.shape[0] - y_px, x_px          # (row, column), fractional

    return image, pixel, ax


def _widest_gap(seg, k, t0, t1):
    """The longest interval of [t0, t1] free of element k's segments."""
    mine = seg.element == k
    edges = np.sort(np.r_[t0, seg.t_start[mine], seg.t_end[mine], t1])
    starts, ends = seg.t_start[mine], seg.t_end[mine]
    best = (t0, t0)
    for a, b in itertools.pairwise(edges):
        free = not np.any((starts < b) & (ends > a))
        if free and t0 <= a and b <= t1 and b - a > best[1] - best[0]:
            best = (a, b)
    return best


def _is(colour, pixels):
    return np.all(np.abs(pixels - np.asarray(to_rgb(colour))) < 0.02, axis=-1)


def test_png_has_the_command_size_and_dpi(png):
    image, _, _ = png
    assert image.shape[:2] == (round(FIGSIZE[1] * DPI), round(FIGSIZE[0] * DPI))


def test_a_two_step_episode_between_two_samples_shows_in_the_png(result, png):
    res, added = result
    image, pixel, _ = png
    for element, status, start, end in added:
        # the sampled status never saw it: the samples on either side are open
        k = np.searchsorted(res.t, start)
        assert res.t[k - 1] < start and end < res.t[k]
        assert res.system.contact_status[k - 1: k + 1, element - 1].tolist() == [1, 1]
        row, col = pixel(0.5 * (start + end), element + LANE[status])
        r, c = int(row), int(col)
        around = image[r - 2: r + 3, c - 1: c + 2]
        assert _is(STATUS_COLOURS[status], around).any(), (element, status, start)
        # and it is that episode: the row is free of that colour a few pixels either side
        for side in (-6, 6):
            assert not _is(STATUS_COLOURS[status], image[r - 2: r + 3, c + side]).any()


def test_every_segment_of_the_log_and_nothing_else_is_drawn(result, png):
    """Row by row and lane by lane: each segment in the window colours at least one pixel in
    its time span, and no pixel is coloured where its element has no such segment."""
    res, _ = result
    image, pixel, ax = png
    seg = res.system.status_segments
    t0, t1 = ax.get_xlim()
    _, c0 = pixel(t0, 1)
    _, c1 = pixel(t1, 1)
    columns = np.arange(int(np.ceil(c0)) + 1, int(c1) - 1)
    for element in range(1, 9):
        for status, colour in STATUS_COLOURS.items():
            mine = (seg.element == element) & (seg.status == status) & (seg.t_end > t0)
            assert mine.sum() > 5                       # case 2: every element rubs
            row, _ = pixel(t0, element + LANE[status])
            band = image[int(row) - 2: int(row) + 3, columns]
            coloured = _is(colour, band).any(axis=0)
            expected = np.zeros(columns.size, bool)
            for a, b in zip(seg.t_start[mine], seg.t_end[mine], strict=True):
                lo, hi = pixel(max(a, t0), 1)[1], pixel(min(b, t1), 1)[1]
                span = (columns >= np.floor(lo) - 1) & (columns <= np.ceil(hi) + 1)
                assert coloured[span].any(), (element, status, a, b)
                expected |= span
            assert not (coloured & ~expected).any(), (element, status)


def test_segments_are_never_narrower_than_a_pixel_at_any_dpi():
    import matplotlib.pyplot as plt

    from rubdiag.plotting._run import SegmentBars

    for dpi in (40, 110, 300):
        fig, ax = plt.subplots(figsize=(4, 2), dpi=dpi)
        ax.set(xlim=(0, 1), ylim=(0, 2))
        bars = SegmentBars([0.3, 0.6], [0.3 + 1e-9, 0.8], [1, 1])
        ax.add_collection(bars)
        fig.draw_without_rendering()
        widths = ax.transData.transform(bars.get_paths()[0].vertices)[:, 0]
        assert np.ptp(widths) == pytest.approx(1.0, rel=1e-6)
        long = ax.transData.transform(bars.get_paths()[1].vertices)[:, 0]
        assert np.ptp(long) == pytest.approx(0.2 * ax.bbox.width, rel=1e-6)   # unchanged
        plt.close(fig)


def test_spectra_and_waveform_panels_say_what_they_show(result):
    res, _ = result
    fig = run_figure(res)
    spectra = [a for a in fig.axes if a.get_ylabel() == "peak amplitude (µm)"]
    assert len(spectra) == 2                            # shaft and blade tip, one axes each
    labels = [[t.get_text() for t in a.get_legend().get_texts()] for a in spectra]
    assert labels[0][0].startswith("shaft") and labels[1][0].startswith("blade tip")
    assert all("order line n× (detected)" in texts for texts in labels)
    zooms = [a for a in fig.axes if a.get_title().startswith(f"last {ZOOM_REVOLUTIONS} rev")]
    assert len(zooms) == 2
    revolution = 60.0 / res.run.speed_rpm
    for ax in zooms:
        assert np.ptp(ax.get_xlim()) == pytest.approx(ZOOM_REVOLUTIONS * revolution)
