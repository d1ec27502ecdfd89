"""What order tracking itself puts beside a line whose amplitude or phase changes.

:func:`~rubdiag.signal.order_track` reads each order in bins of whole revolutions; a steady
line on its bin leaks into no other order (with the Hann window, into its two neighbouring
bins only). But a 1× that changes within a bin — a run-up through a critical speed, where
amplitude and phase turn within a few revolutions — is a modulated line, and its window
spreads it onto the orders beside it: with 4-revolution bins, 0.5× and 1.5× read about 1 %
of 1× on a 300 rpm/s run-up of the paper rig *without any contact* (documentation: "Run-up and
coast-down"). :func:`tracking_leakage` computes that level from the track itself, so that a
figure can say where an order stands above the tracking's own leakage and where it does not.
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from rubdiag import _check
from rubdiag._tolerances import ON_LEVEL
from rubdiag.signal._orders import order_label
from rubdiag.signal._spectrum import _spectra


def tracking_leakage(track: pd.DataFrame, revs_per_bin: int, orders=(0.5, 1.5, 2.0, 3.0), *,
                     source: float = 1.0, samples_per_rev: int = 64,
                     window="hann") -> pd.DataFrame:
    """The amplitudes at ``orders`` that tracking the ``source`` order's line alone gives.

    The source's complex amplitude ``amp · e^{i phase}`` of each bin of ``track`` is taken
    at the bin's centre revolution and interpolated linearly (real and imaginary parts)
    between centres (extrapolated over the outer halves of the first and last bins); the
    line ``Re(z(φ) e^{i·source·φ})`` so rebuilt on ``samples_per_rev`` points per
    revolution is cut into the track's bins and read as
    :func:`~rubdiag.signal.order_track` reads them (mean removed, ``window``, the order's
    bin). A steady source gives 0 beside it; a changing one, its leakage.

    Parameters
    ----------
    track : pandas.DataFrame
        An :func:`~rubdiag.signal.order_track` table with ``rev_start``, ``rpm`` and
        ``amp_<source>``, ``phase_<source>_deg``.
    revs_per_bin : int
        The bins' length in revolutions, as tracked.
    orders : sequence of float
        Orders to read; each times ``revs_per_bin`` a whole number below
        ``revs_per_bin · samples_per_rev / 2``.
    source, samples_per_rev, window
        The changing order (1×), the angle resolution and the window of the tracking.

    Returns
    -------
    pandas.DataFrame
        ``rev_start``, ``rpm`` and ``amp_<k>`` (unit of the track) for every order, one row
        per row of ``track``.
    """
    n_rev = _check.integer("revs_per_bin", revs_per_bin, lo=1)
    spr = _check.integer("samples_per_rev", samples_per_rev, lo=4)
    label = order_label(source)
    missing = [c for c in ("rev_start", "rpm", f"amp_{label}", f"phase_{label}_deg")
               if c not in track]
    if missing:
        raise ValueError(f"track has no column {', '.join(missing)} (allowed: an order_track "
                         f"table holding order {source:g})")
    bins = np.asarray(orders, dtype=np.float64) * n_rev
    j = np.rint(bins).astype(np.int64)
    if np.any(np.abs(bins - j) > ON_LEVEL) or np.any(j < 1) or np.any(j >= n_rev * spr // 2):
        raise ValueError(f"orders = {list(orders)}: each times revs_per_bin = {n_rev} must be "
                         f"a whole number from 1 to below {n_rev * spr // 2}")
    start = track["rev_start"].to_numpy(dtype=np.float64)
    z = (track[f"amp_{label}"].to_numpy(dtype=np.float64)
         * np.exp(1j * np.radians(track[f"phase_{label}_deg"].to_numpy(dtype=np.float64))))
    order = np.argsort(start, kind="stable")                 # np.interp wants them rising
    centre, z = _extended(start[order] + 0.5 * n_rev, z[order], 0.5 * n_rev)
    rev = start[:, np.newaxis] + np.arange(n_rev * spr) / spr
    zr = np.interp(rev, centre, z.real) + 1j * np.interp(rev, centre, z.imag)
    line = np.real(zr * np.exp(2j * np.pi * source * rev))
    spec = _spectra(line, float(spr), window, None, None, None, "constant")
    out = {"rev_start": start, "rpm": track["rpm"].to_numpy(dtype=np.float64)}
    for k, jk in zip(orders, j, strict=True):
        out[f"amp_{order_label(k)}"] = np.abs(spec.first[:, jk])
    return pd.DataFrame(out)


def _extended(centre: np.ndarray, z: np.ndarray, reach: float):
    """``centre`` and ``z`` with one point ``reach`` beyond each end, on the straight line
    through the two nearest: the first and last bins' outer halves lie beyond their centres,
    and a line changing there keeps changing as it did."""
    if centre.size < 2:
        return centre, z
    slope = (z[[1, -1]] - z[[0, -2]]) / (centre[[1, -1]] - centre[[0, -2]])
    ends = centre[[0, -1]] + np.array([-reach, reach])
    z_ends = z[[0, -1]] + slope * (ends - centre[[0, -1]])
    return (np.concatenate([ends[:1], centre, ends[1:]]),
            np.concatenate([z_ends[:1], z, z_ends[1:]]))
