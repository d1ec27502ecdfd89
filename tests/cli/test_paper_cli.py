"""The table2 and plot commands."""

import pandas as pd

from rubdiag.cli import main
from rubdiag.simulate import Run, simulate


def test_table2_short_without_figures(tmp_path, capsys):
    assert main(["table2", "--out", str(tmp_path), "--duration-s", "0.8", "--discard-s", "0.3",
                 "--no-figures", "--jobs", "2"]) == 0
    table = pd.read_csv(tmp_path / "table2.csv")
    assert len(table) == 4 and (table.window_s.round(6) == 0.5).all()
    assert (table.contact1_max_force_n > 0).all()
    assert not list(tmp_path.glob("*.png"))
    assert "| case |" in capsys.readouterr().out            # the Markdown table on stdout
    assert sorted(p.name for p in (tmp_path / "runs").iterdir()) == [
        "case1_light.npz", "case1_serious.npz", "case2_light.npz", "case2_serious.npz"]


def test_plot_writes_the_six_panel_figure(tmp_path):
    result = simulate(Run.paper_case(2, 2.3, duration_s=0.5, discard_s=0.2))
    path = result.save(tmp_path / "r.npz")
    assert main(["plot", str(path), "--out", str(tmp_path / "figs")]) == 0
    assert (tmp_path / "figs" / "r.png").stat().st_size > 50_000
