"""The table2 and plot commands."""

import re

import matplotlib.colors
import matplotlib.image as mpimg
import numpy as np
import pandas as pd

from rubdiag.cli import main
from rubdiag.plotting._run import DPI, FIGSIZE, STATUS_COLOURS
from rubdiag.simulation import Run, simulate


def test_table2_short_without_figures(tmp_path, capsys):
    assert main(["table2", "--out", str(tmp_path), "--duration-s", "0.8", "--discard-s", "0.3",
                 "--no-figures", "--jobs", "2"]) == 0
    table = pd.read_csv(tmp_path / "table2.csv")
    assert len(table) == 4 and (table.window_s == 0.5).all()    # 0.8 - 0.3, without noise
    for name in ("table2.csv", "features.csv"):
        assert not FLOAT_NOISE.search((tmp_path / name).read_text()), name
    assert (table.contact1_max_force_n > 0).all()
    assert not list(tmp_path.glob("*.png"))
    captured = capsys.readouterr()
    assert "| case |" in captured.out                       # the Markdown table on stdout
    # off a terminal no bar: a line per finished case, for logs
    assert "\r" not in captured.err and captured.err.count(": done in ") == 4
    assert sorted(p.name for p in (tmp_path / "runs").iterdir()) == [
        "case1_light.npz", "case1_serious.npz", "case2_light.npz", "case2_serious.npz"]


def test_plot_writes_the_six_panel_figure(tmp_path):
    result = simulate(Run.paper_case(2, 2.3, duration_s=0.5, discard_s=0.2))
    path = result.save(tmp_path / "r.npz")
    assert main(["plot", str(path), "--out", str(tmp_path / "figs")]) == 0
    pixels = mpimg.imread(tmp_path / "figs" / "r.png")
    # saved at the documented size and resolution, and the status colours are drawn
    assert pixels.shape[:2] == (round(FIGSIZE[1] * DPI), round(FIGSIZE[0] * DPI))
    for colour in STATUS_COLOURS.values():
        rgb = np.array(matplotlib.colors.to_rgb(colour))
        assert (np.abs(pixels[..., :3] - rgb).max(axis=-1) < 0.02).sum() > 100, colour


# 2.0000000000000004, 18.999999999999996: six or more 0s or 9s before the last digit
FLOAT_NOISE = re.compile(r"\d\.\d*(0{6,}|9{6,})\d")


def test_csv_files_have_no_float_noise(tmp_path):
    """Written tables carry meaningful digits only (0.8 - 0.3 s is 0.5000000000000001 in
    floating point, 19 entries / 0.5 s is 37.99999999999999), and are not over-rounded."""
    from rubdiag.paper._table2 import write_csv

    noisy = pd.DataFrame({"window_s": [0.8 - 0.3, 2.0000000000000004],
                          "entries_per_s": [19 / (0.8 - 0.3), 18.999999999999996],
                          "per_rev": [5 / 12.4999988, 0.1 + 0.2],
                          "force_n": [1110.619235396102, 12.120225168967686],
                          "dt_s": [1e-5, 5e-6], "entries": [38, 21]})
    write_csv(noisy, tmp_path / "t.csv")
    text = (tmp_path / "t.csv").read_text()
    assert not FLOAT_NOISE.search(text), text
    back = pd.read_csv(tmp_path / "t.csv")
    assert list(back.window_s) == [0.5, 2.0] and list(back.entries_per_s) == [38.0, 19.0]
    assert list(back.per_rev) == [0.4, 0.3]
    assert list(back.dt_s) == [1e-5, 5e-6] and list(back.entries) == [38, 21]
    assert list(back.force_n) == [1110.62, 12.1202]            # 6 significant digits
