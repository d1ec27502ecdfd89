"""The threshold of instability's grid walk takes each point's sign from the cheapest source
that decides it (the rotor projected on its first point's roots, else roots to 1e-8), yet
finds the threshold of the plain search — every grid point's roots to machine precision,
Brent's method on the first sign change — to the last bit."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.optimize import brentq

from rubdiag._blas import one_thread
from rubdiag.assembly import assemble
from rubdiag.modal import _stability as stability
from rubdiag.modal import critical_speeds, modes, with_rayleigh
from rubdiag.model import preset_rig


def plain_threshold(model, low, high, n_grid=33, n_modes=6):
    def growth(w):
        return float(modes(model, w, n_modes=n_modes).eigenvalues.real.max())

    speeds = np.linspace(low, high, n_grid)
    signs = [growth(w) >= 0.0 for w in speeds]
    k = signs.index(True)
    return brentq(growth, speeds[k - 1], speeds[k], xtol=1e-9 * speeds[k], rtol=1e-12)


@pytest.fixture(scope="module")
def journal():
    """The journal rig's model, its search range and its threshold (on one BLAS thread,
    as a design's workers compute it: many threads only spin on a busy machine)."""
    with one_thread():
        model = with_rayleigh(assemble(preset_rig("paper-journal")))
        low, high = stability.whirl_range(critical_speeds(model, n=2))
        yield model, low, high, stability.threshold_speed(model, low, high)


def test_the_walk_finds_the_plain_searchs_threshold_to_the_bit(journal, monkeypatch):
    model, low, high, found = journal
    decided = []
    unstable = stability._Reduced.unstable
    monkeypatch.setattr(stability._Reduced, "unstable",
                        lambda self, w: decided.append(unstable(self, w)) or decided[-1])
    with one_thread():
        assert stability.threshold_speed(model, low, high) == found
        assert found == plain_threshold(model, low, high)
    assert sum(d is not None for d in decided) >= 10      # the reduced model did the walk


def test_a_reduced_model_that_errs_at_the_bracket_is_overruled(journal, monkeypatch):
    """Were the reduced model to call every point unstable, the bracket's exact ends would
    show it, and the walk is made again without it: the same threshold."""
    model, low, high, found = journal
    monkeypatch.setattr(stability._Reduced, "unstable", lambda self, w: True)
    with one_thread():
        assert stability.threshold_speed(model, low, high) == found
