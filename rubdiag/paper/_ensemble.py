"""Start-history ensembles: is a finding robust, or one realisation of a chaotic rub?

Rub-impact is chaotic: two runs whose descriptions differ only in how they start (here the
length of the gap ramp, ±2 %) reach different trajectories, and some spectral lines appear in
one and not in the other. :func:`ensemble` runs such a family for chosen cases and returns
one feature row per run, so a finding can be stated as "in k of n start histories".
"""

from __future__ import annotations

from concurrent.futures import ProcessPoolExecutor, as_completed

import pandas as pd

from rubdiag import _progress

__all__ = ["GAP_RAMPS_S", "ensemble"]

#: Gap-ramp lengths (s) of the default ensemble: the standard 0.1 s ± 2 %.
GAP_RAMPS_S = (0.098, 0.099, 0.1, 0.101, 0.102)


def _features(run) -> dict:
    from rubdiag.runs import run_features
    from rubdiag.simulation import simulate

    return run_features(simulate(run)).iloc[0].to_dict()


def ensemble(cases, gap_ramps_s=GAP_RAMPS_S, jobs: int | None = None, rig=None,
             progress=False, **options) -> pd.DataFrame:
    """Feature rows of paper cases, each run once per gap-ramp length: a start-history
    ensemble (module docstring).

    Parameters
    ----------
    cases : iterable of (int, float)
        ``(case, gap_mm)`` pairs: the study's unbalance case (1 or 2) and the blade-tip /
        casing gap (mm; None: no rub), as :meth:`rubdiag.simulation.Run.paper_case` takes
        them.
    gap_ramps_s : sequence of float
        Gap-ramp lengths (s); one run per case and length. Default :data:`GAP_RAMPS_S`,
        0.1 s ± 2 %.
    jobs : int or None
        Parallel processes; None: every core.
    rig : Rig or None
        The rig; None: the study's.
    progress : bool or bar
        A bar over the runs on stderr, counted as they finish, when stderr is a terminal;
        or an open bar of :mod:`rubdiag._progress` to count on.
    **options
        Passed on to :meth:`rubdiag.simulation.Run.paper_case` (``duration_s``, ``dt_s``,
        ``reduction`` …).

    Returns
    -------
    pandas.DataFrame
        One row per run, in the order of ``cases`` then ``gap_ramps_s``: ``case``,
        ``gap_mm``, ``gap_ramp_s``, then the run's features
        (:func:`rubdiag.runs.run_features`; its ``model`` column says "full" or
        "reduced").

    See Also
    --------
    table2 : The study's four cases, one start history each.
    """
    from rubdiag.simulation import Run

    grid = [(case, gap, ramp) for case, gap in cases for ramp in gap_ramps_s]
    runs = [Run.paper_case(case, gap, rig=rig, gap_ramp_s=ramp, **options)
            for case, gap, ramp in grid]
    with ProcessPoolExecutor(max_workers=jobs) as pool, \
            _progress.shared(progress, len(runs), "ensemble", "run") as bar:
        futures = {pool.submit(_features, run): i for i, run in enumerate(runs)}
        rows = [None] * len(runs)
        for future in as_completed(futures):
            rows[futures[future]] = future.result()
            bar.update()
    table = pd.DataFrame(rows)
    table.insert(0, "case", [g[0] for g in grid])
    table.insert(1, "gap_mm", [g[1] for g in grid])
    table.insert(2, "gap_ramp_s", [g[2] for g in grid])
    return table
