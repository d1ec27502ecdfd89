"""Where a design's points fall, and the start histories of its replicates.

:func:`unit_samples` gives ``n`` points in the unit hypercube ``[0, 1)^d`` by Latin hypercube
(``"lhs"``), scrambled Sobol' (``"sobol"``) or independent uniform draws (``"random"``),
deterministic given the seed: the engines of :mod:`scipy.stats.qmc` with ``rng=seed`` and
NumPy's ``default_rng(seed)``. The same seed gives the same points with the same SciPy and
NumPy; a resolved design states its runs, and :mod:`rubdiag.dataset._ids` their identities,
so a change of library shows as different ``run_id`` values, never as silently other runs.

:func:`gap_ramps_s` gives the start histories of replicates, as in
:mod:`rubdiag.paper._ensemble`: the gap-ramp length ±2 % around the standard one.
"""

from __future__ import annotations

import numpy as np

from rubdiag import _check

__all__ = ["MAX_REPLICATES", "METHODS", "gap_ramps_s", "ramp_offsets", "unit_samples"]

METHODS = ("grid", "lhs", "sobol", "random")

#: Relative offsets (of the standard gap-ramp length) of the first five replicates: the
#: standard ramp first, then ±1 %, then ±2 % — the paper's ensemble (GAP_RAMPS_S).
_FIRST_OFFSETS = (0.0, -0.01, 0.01, -0.02, 0.02)

#: The most replicates a design point may have: 1 + 2^6 ramps, spaced 1/16 % apart (62.5 µs
#: for a 0.1 s ramp, six 10 µs time steps). Closer ramps would hardly be other histories.
MAX_REPLICATES = 65
#: Decimal places (s) a replicate's gap-ramp length is rounded to: the products 0.1·(1 ± x)
#: carry float noise (0.09900000000000001); 1 ps removes it and no ramp is that close to
#: another (the closest are 62.5 µs apart).
_RAMP_DECIMALS = 12


def unit_samples(method: str, n: int, d: int, seed: int) -> np.ndarray:
    """``n`` points in ``[0, 1)^d`` (array ``(n, d)``) drawn by ``method`` with ``seed``.

    ``"sobol"`` needs ``n`` a power of 2 (its balance properties hold only then; SciPy
    would only warn, this raises).
    """
    from scipy.stats import qmc

    method = _check.choice("sampling.method", method, METHODS[1:])
    n = _check.integer("sampling.n", n, lo=1)
    d = _check.integer("d", d, lo=1)
    seed = _check.integer("sampling.seed", seed, lo=0)
    if method == "lhs":
        return qmc.LatinHypercube(d, rng=seed).random(n)
    if method == "sobol":
        check_sobol_n(n)
        return qmc.Sobol(d, rng=seed).random(n)
    return np.random.default_rng(seed).random((n, d))


def check_sobol_n(n: int) -> None:
    if n & (n - 1):
        below = 1 << (n.bit_length() - 1)
        raise _check.out_of_range("sampling.n", n, f"a power of 2 for method = 'sobol', "
                                  f"e.g. {below} or {2 * below}")


def ramp_offsets(replicates: int) -> tuple[float, ...]:
    """Relative gap-ramp offsets of replicates ``0 … replicates-1``.

    The first five are 0, -1 %, +1 %, -2 %, +2 %; further ones halve the spacing inside the
    same ±2 % span: ±0.5 %, ±1.5 %, then ±0.25 %, ±0.75 %, ±1.25 %, ±1.75 % and so on, the
    smaller magnitude and the negative sign first. Replicate r of a design with more
    replicates is the same start history as replicate r of a design with fewer.
    """
    replicates = _check.integer("sampling.replicates", replicates, lo=1, hi=MAX_REPLICATES)
    offsets = list(_FIRST_OFFSETS)
    level = 1
    while len(offsets) < replicates:
        step = 0.01 / 2**level
        for m in range(1, 2 ** (level + 1), 2):   # odd multiples of step inside ±2 %
            offsets += [-m * step, m * step]
        level += 1
    return tuple(offsets[:replicates])


def gap_ramps_s(replicates: int, duration_s: float | None = None) -> tuple[float, ...]:
    """Gap-ramp lengths (s) of replicates ``0 … replicates-1`` of a run of ``duration_s``:
    the standard ramp of :class:`~rubdiag.simulation.Run` (0.1 s, or half the duration of a
    run shorter than 0.2 s; None: 0.1 s, as for the runs of a design with a speed ramp,
    whose lengths differ) times ``1 + ramp_offsets(replicates)``, rounded to 1e-12 s (so
    that five replicates of a 2.3 s run are exactly the paper's 0.098 … 0.102 s).

    Parameters
    ----------
    replicates : int
        Number of replicates (>= 1).
    duration_s : float or None
        Length of the run (s).

    Returns
    -------
    tuple of float
        One gap-ramp length per replicate (s).
    """
    standard = 0.1 if duration_s is None else min(
        0.1, 0.5 * _check.positive("duration_s", duration_s, "s"))
    return tuple(round(standard * (1.0 + x), _RAMP_DECIMALS) for x in ramp_offsets(replicates))
