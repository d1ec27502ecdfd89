"""The study's Figures 5-10 for the reproduction.

The six figures are independent, so they are drawn in parallel processes, one task each:
drawing, not computing, is what they cost. Each worker limits BLAS to one thread (two
processes on two cores with two BLAS threads each made a 0.06-s eigenvalue solve take
1.5 s), and gets the runs from its parent once, when it starts (with the fork start method:
without copying them).
"""

from __future__ import annotations

import os
from concurrent.futures import ProcessPoolExecutor, as_completed
from pathlib import Path

import numpy as np

from rubdiag import _progress

__all__ = ["write_figures"]

_LINEAR_DPI = 120
_RPM = 30 / np.pi
_RESULTS: dict = {}        # a worker's runs, by stem


def write_figures(results: dict, feats, out: str | Path, jobs: int | None = None,
                  progress=False) -> list[Path]:
    """Fig. 5 (unbalance responses), Fig. 6 (deflected shapes) and one six-panel figure per
    case (Figs. 7-10) as PNG files in ``out``; returns their paths.

    ``jobs``: processes drawing the figures (default: the CPU count; 1 draws them here).
    ``progress``: a bar over the figures on stderr when it is a terminal (or an open bar of
    :mod:`rubdiag._progress` to count them on).
    """
    # imported before the pool starts: forked workers inherit them
    import rubdiag.plotting  # noqa: F401

    try:
        import threadpoolctl  # noqa: F401
    except ImportError:
        pass

    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    rig = next(iter(results.values())).run.rig
    runs = []
    for number, ((stem, result), row) in enumerate(
            zip(results.items(), feats.to_dict("records"), strict=True), start=7):
        title = f"Fig. {number}: {result.run.label}, {result.run.speed_rpm:.0f} rpm"
        runs.append((_run_figure, stem, row, title, out / f"fig{number}_{stem}.png"))
    # the longest first, so that no long task starts last: a run figure's cost grows with
    # its contact segments; Fig. 5 solves 322 linear systems; Fig. 6 is the shortest
    runs.sort(key=lambda task: -len(results[task[1]].system.status_segments))
    tasks = [runs[0], (_unbalance_figure, rig, out / "fig5_unbalance.png"), *runs[1:],
             (_deflection_figure, rig, out / "fig6_deflection.png")]
    jobs = min(len(tasks), jobs or os.cpu_count() or 1)
    written = []
    if jobs == 1:
        _RESULTS.update(results)
        try:
            with _progress.shared(progress, len(tasks), "figures", "figure") as bar:
                for task, *args in tasks:
                    written.append(task(*args))
                    bar.update()
        finally:
            _RESULTS.clear()
    else:
        _warm_up()
        with ProcessPoolExecutor(max_workers=jobs, initializer=_start_worker,
                                 initargs=(results,)) as pool, \
                _progress.shared(progress, len(tasks), "figures", "figure") as bar:
            for future in as_completed([pool.submit(task, *args) for task, *args in tasks]):
                written.append(future.result())
                bar.update()
    return sorted(written)


def _warm_up() -> None:
    """Draw a little text once here, so that forked workers inherit loaded fonts and glyph
    caches (0.05 s here, 0.1 s less in each worker's first figure)."""
    from rubdiag._figures import new_figure
    from rubdiag.plotting._run import DPI

    fig = new_figure(figsize=(2, 1), dpi=DPI)
    ax = fig.add_subplot()
    ax.set(title="0.5 µm ×", xlabel="time (s)")
    ax.legend(handles=ax.plot([0, 1], [0, 1], label="10⁻²"), fontsize="small")
    fig.canvas.draw()


def _start_worker(results: dict) -> None:
    _RESULTS.update(results)
    try:
        from threadpoolctl import threadpool_limits  # installed with scikit-learn
    except ImportError:
        return
    threadpool_limits(limits=1)


def _critical_speeds(rig):
    from rubdiag.assembly import assemble
    from rubdiag.modal import critical_speeds

    model = assemble(rig)
    return model, critical_speeds(model, n=2)


def _unbalance_figure(rig, path: Path) -> Path:
    """Fig. 5: the unbalance responses of cases 1 and 2, no rub."""
    from rubdiag._figures import save_figure
    from rubdiag.modal import unbalance_response
    from rubdiag.plotting import unbalance_figure

    model, crit = _critical_speeds(rig)
    curves = {f"case {c} ({'in' if c == 1 else 'out of'} phase)":
              unbalance_response(model, _speeds(crit), rig.unbalance(c)) for c in (1, 2)}
    return save_figure(unbalance_figure(curves, crit * _RPM, "Fig. 5: unbalance response of "
                                        "disc 1 (node 11, y), no rub"), path, dpi=_LINEAR_DPI)


def _deflection_figure(rig, path: Path) -> Path:
    """Fig. 6: the deflected shaft at the two critical speeds, no rub."""
    from rubdiag._figures import save_figure
    from rubdiag.modal import harmonic_response
    from rubdiag.plotting import deflection_figure

    model, crit = _critical_speeds(rig)
    shapes = {f"case {c} at {crit[c - 1] * _RPM:.0f} rpm":
              harmonic_response(model, crit[c - 1], rig.unbalance(c)) for c in (1, 2)}
    return save_figure(deflection_figure(model, shapes, "Fig. 6: deflected shaft at the two "
                                         "critical speeds, no rub"), path, dpi=_LINEAR_DPI)


def _speeds(critical: np.ndarray, low_rpm: float = 100.0, high_rpm: float = 8000.0):
    """Speeds (rad/s) for Fig. 5: every 80 rpm, 20 more spaced evenly on the log scale below
    1000 rpm (the steep rise from rest) and 31 within ±5 % of each critical speed (the
    critical speed among them), so the narrow resonance peaks are drawn to their top with
    half the solves of a uniform 20-rpm grid."""
    rpm = [np.arange(low_rpm, high_rpm, 80.0), [high_rpm], np.geomspace(low_rpm, 1000.0, 20)]
    for c in np.asarray(critical) * _RPM:
        rpm.append(np.linspace(0.95 * c, 1.05 * c, 31))
    rpm = np.unique(np.concatenate(rpm))
    return rpm[(rpm >= low_rpm) & (rpm <= high_rpm)] / _RPM


def _run_figure(stem: str, row, title: str, path: Path) -> Path:
    from rubdiag.plotting import save_run_figures

    return save_run_figures(_RESULTS[stem], path.parent, stem=path.stem, row=row,
                            title=title)[0]
