"""Figs. 5-10 of the reproduction: drawn in parallel workers, they are the figures drawn one
after the other here, pixel for pixel, each run in its own file."""

import numpy as np
from matplotlib.image import imread

from rubdiag.paper._figures import write_figures
from rubdiag.plotting._run import save_run_figures
from rubdiag.runs import run_features
from rubdiag.simulation import Run, simulate


def test_parallel_figures_are_the_sequential_ones(tmp_path):
    results = {f"case{c}_light": simulate(Run.paper_case(c, 2.3, duration_s=0.65,
                                                          discard_s=0.2, label=f"case {c}"))
               for c in (1, 2)}
    feats = run_features(list(results.values()))
    one = write_figures(results, feats, tmp_path / "one", jobs=1)
    two = write_figures(results, feats, tmp_path / "two", jobs=2)
    names = ["fig5_unbalance.png", "fig6_deflection.png", "fig7_case1_light.png",
             "fig8_case2_light.png"]
    assert [p.name for p in one] == [p.name for p in two] == names
    for a, b in zip(one, two, strict=True):
        np.testing.assert_array_equal(imread(a), imread(b), err_msg=a.name)
    # each run figure shows its own run: fig8 is case 2's, drawn directly
    run = results["case2_light"]
    direct = save_run_figures(run, tmp_path, stem="direct", row=feats.iloc[1].to_dict(),
                              title=f"Fig. 8: case 2, {run.run.speed_rpm:.0f} rpm")[0]
    np.testing.assert_array_equal(imread(direct), imread(two[3]))
    assert not np.array_equal(imread(two[2]), imread(two[3]))
