"""The study's Figures 5-10 for the reproduction."""

from __future__ import annotations

from pathlib import Path

import numpy as np

__all__ = ["write_figures"]


def write_figures(results: dict, feats, out: str | Path) -> list[Path]:
    """Fig. 5 (unbalance responses), Fig. 6 (deflected shapes) and one six-panel figure per
    case (Figs. 7-10) as PNG files in ``out``; returns their paths."""
    import matplotlib.pyplot as plt

    from rubdiag.assembly import assemble
    from rubdiag.modal import critical_speeds, harmonic_response, unbalance_response
    from rubdiag.plotting.modal import deflection_figure, unbalance_figure
    from rubdiag.plotting.run import run_figure

    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    rig = next(iter(results.values())).run.rig
    model = assemble(rig)
    crit = critical_speeds(model, n=2)
    rpm = 30 / np.pi
    speeds = np.linspace(100, 8000, 400) / rpm
    curves = {f"case {c} ({'in' if c == 1 else 'out of'} phase)":
              unbalance_response(model, speeds, rig.unbalance(c)) for c in (1, 2)}
    paths = []

    def save(fig, name):
        fig.savefig(out / name, dpi=120)
        plt.close(fig)
        paths.append(out / name)

    save(unbalance_figure(curves, crit * rpm, "Fig. 5: unbalance response of disc 1 "
                          "(node 11, y), no rub"), "fig5_unbalance.png")
    shapes = {f"case {c} at {crit[c - 1] * rpm:.0f} rpm":
              harmonic_response(model, crit[c - 1], rig.unbalance(c)) for c in (1, 2)}
    save(deflection_figure(model, shapes, "Fig. 6: deflected shaft at the two critical "
                           "speeds, no rub"), "fig6_deflection.png")
    rows = feats.to_dict("records")
    for number, (stem, result) in enumerate(results.items(), start=7):
        title = f"Fig. {number}: {result.run.label}, {result.run.speed_rpm:.0f} rpm"
        save(run_figure(result, row=rows[number - 7], title=title), f"fig{number}_{stem}.png")
    return paths
