"""The loose pedestal's signature against its sources, on the multi-fault rig.

What the sources say (in our words): Muszynska & Goldman (1995, "Chaotic responses of
unbalanced rotor/bearing/stator systems with looseness or rubs", Chaos, Solitons & Fractals
5(9), 1683-1704) and Muszynska (2005, "Rotordynamics", the chapters on looseness and rub):
a support that lifts off its seat once a revolution, or every other one, makes
sub-harmonics, ½x first and ⅓x, with their harmonics (1½x, 2x ...); a support that stays
seated is linear and adds none.

Checked: the drive-end pedestal of ``paper-journal`` loose across gravity (z), case 1 at
half the first critical speed, where its seat carries a 1x force of about 0.13 N: with
0.05 N left on the seat it lifts; with 5 N it stays seated. On this rig the oil film
stands between the pedestal and the shaft: the pedestal shows the textbook ½x, the journal
on it about a third of that, the disc a tenth.
"""

import pytest
from fault_signatures import fault_run, lines

from rubdiag.simulation._faults import Looseness

ORDERS = (1 / 3, 1 / 2, 1, 3 / 2, 2)


def _run(preload_n):
    result = fault_run(0.5, looseness=Looseness(bearing=0, preload_n=preload_n,
                                                direction="z"))
    return {p: lines(result, p, ORDERS) for p in ("pedestal 0", "shaft 4")}


@pytest.fixture(scope="module")
def loose():
    return _run(0.05)


@pytest.fixture(scope="module")
def seated():
    return _run(5.0)


def _rel(measured, point, axis, k):
    return measured[point][axis][k] / measured[point][axis][2]


def test_a_pedestal_that_lifts_shows_half_order_and_harmonics(loose):
    assert _rel(loose, "pedestal 0", "z", 1) >= 0.2     # ½x, measured 0.38
    assert _rel(loose, "pedestal 0", "z", 3) >= 0.03    # 1½x, measured 0.12
    assert _rel(loose, "pedestal 0", "z", 4) >= 0.03    # 2x, measured 0.11
    assert _rel(loose, "shaft 4", "z", 1) >= 0.05       # the journal on it: 0.14


def test_the_half_order_is_along_the_loose_direction(loose):
    """The pedestal moves along z alone: across it (y) no ½x, and in the full spectrum a
    line motion, forward and reverse alike."""
    assert loose["pedestal 0"]["y"][1] < 0.05 * loose["pedestal 0"]["z"][1]
    forward, reverse = loose["pedestal 0"]["forward"][1], loose["pedestal 0"]["reverse"][1]
    assert forward == pytest.approx(reverse, rel=0.1)


def test_a_seated_pedestal_adds_no_subharmonic(seated):
    for point in ("pedestal 0", "shaft 4"):
        assert _rel(seated, point, "z", 1) < 1e-3
        assert _rel(seated, point, "z", 0) < 1e-3
