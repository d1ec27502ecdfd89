"""A rig on plain journal bearings in a run: its films are
elements, the run starts from the static state they carry, and oil whirl sets in above the
threshold the linear analysis gives.

The rig is tests/journal_rig.py's: a 20 kg disc on a stiff shaft on two
short bearings carrying 98.1 N each (threshold 1122.2 rad/s, root at 0.52 x).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from journal_rig import FILM, LOAD, rig

from rubdiag import _fluidfilm as ff
from rubdiag.assembly import assemble
from rubdiag.modal import stability_threshold
from rubdiag.simulation import Run, simulate
from rubdiag.simulation._films import film_equilibrium
from rubdiag.simulation._static_load import StaticLoad

GRAVITY = StaticLoad(direction="y", gravity_m_s2=-9.81)


@pytest.fixture(scope="module")
def threshold() -> float:
    return stability_threshold(assemble(rig()), 300.0, 3000.0).speed_rad_s


def run(speed: float, **options) -> Run:
    journal_rig = rig()
    return Run(rig=journal_rig, speed_rad_s=speed, unbalance=journal_rig.unbalance(1),
               gap_m=None, duration_s=1.5, discard_s=0.5, **{"static_load": GRAVITY,
                                                            **options})


def subsynchronous(result, point: str = "shaft 3 y"):
    """The strongest line between 0.3x and 0.7x of the window's spectrum and its order."""
    t = result.t[result.window]
    x = result.displacement(point, True)
    x = x - x.mean()
    f = np.fft.rfftfreq(t.size, t[1] - t[0])
    amplitude = np.abs(np.fft.rfft(x * np.hanning(t.size))) / (0.25 * t.size)
    order = f / (result.run.speed_rad_s / (2 * math.pi))
    band = (order > 0.3) & (order < 0.7)
    k = np.argmax(amplitude[band])
    return amplitude[band][k], order[band][k]


def test_a_journal_rig_needs_a_static_load():
    with pytest.raises(ValueError, match="static_load is None on a rig on journal bearings"):
        run(800.0, static_load=None)


def test_the_static_state_puts_each_journal_where_the_closed_form_does():
    """Each bearing carries half the weight: its journal sits at the closed-form
    eccentricity and attitude angle for 98.1 N (the shaft's own weight is ~1e-5 of it)."""
    model = assemble(rig())
    speed = 800.0
    x = film_equilibrium(model, GRAVITY.vector(model.M, model.dofs), speed)
    eps = ff.eccentricity_for_load(LOAD, speed, *FILM.values())
    for node in (0, 6):
        journal = x[[model.dofs.index(node, "y"), model.dofs.index(node, "z")]]
        assert np.hypot(*journal) == pytest.approx(eps * FILM["clearance_m"], rel=1e-5)
        angle = math.atan2(-journal[1], -journal[0])     # from -y, in the sense of rotation
        assert angle == pytest.approx(ff.attitude_angle(eps), abs=1e-5)


@pytest.mark.parametrize(("ratio", "whirls"), [(0.9, False), (1.1, True)])
def test_oil_whirl_sets_in_above_the_threshold(threshold, ratio, whirls):
    """Measured at the disc over 1 s: 1e-6 um of sub-synchronous motion at 0.9 of the
    threshold; at 1.1 a 32-um line at 0.48x (oil whirl: forward, near half the speed)."""
    result = simulate(run(ratio * threshold))
    amplitude, order = subsynchronous(result)
    if whirls:
        assert amplitude > 10e-6 and 0.42 <= order <= 0.5
    else:
        assert amplitude < 1e-9
    assert result.system.contact_gap.min() > 0.0        # the journals inside their clearance
    assert result.n_contacts == 0


def test_the_reduced_model_carries_the_films_like_the_full_one(threshold):
    """The journals are boundary coordinates of the Craig–Bampton basis: the reduced run
    starts from its own static state and whirls like the full one above the threshold (its
    sub-synchronous line within 5 %, the reduced model's band; measured 31.6 against 32.0 um,
    the same order 0.48)."""
    from rubdiag.reduce import Reduction

    full = simulate(run(1.1 * threshold))
    reduced = simulate(run(1.1 * threshold, reduction=Reduction()))
    a, order_a = subsynchronous(full)
    b, order_b = subsynchronous(reduced)
    assert b == pytest.approx(a, rel=0.05) and order_b == pytest.approx(order_a, rel=0.01)
    below = simulate(run(0.9 * threshold, reduction=Reduction()))
    assert subsynchronous(below)[0] < 1e-9


def test_well_above_the_threshold_the_whirl_locks_at_the_first_natural_frequency():
    """Oil whip: on the 25-mm shaft (first critical of the film map 484 rad/s, threshold
    1.64 x that) at 2.5 and 4 times the first critical speed, the sub-synchronous line stays
    at the rotor's first natural frequency on rigid bearings (the whip orbit fills the
    clearance, where the film is stiff; measured 578 and 591 rad/s against 590: 2 %), while
    its order falls from 0.48 to 0.31. Against the film map's first critical the line is
    1.2 times higher: the map linearises the film at the static load's eccentricity."""
    import dataclasses

    from journal_rig import whip_rig

    from rubdiag.modal import critical_speeds, with_rayleigh
    from rubdiag.model import Bearing

    journal_rig = whip_rig()
    first = critical_speeds(with_rayleigh(assemble(journal_rig)), n=1)[0]
    rigid = dataclasses.replace(journal_rig, bearings=tuple(
        Bearing(b.node, 1e13, 1e13) for b in journal_rig.bearings))
    natural = critical_speeds(assemble(rigid), n=1)[0]
    lines = []
    for ratio in (2.5, 4.0):
        speed = ratio * first
        result = simulate(Run(rig=journal_rig, speed_rad_s=speed,
                              unbalance=journal_rig.unbalance(1), gap_m=None, duration_s=1.0,
                              discard_s=0.5, static_load=GRAVITY))
        amplitude, order = subsynchronous(result)
        assert amplitude > 100e-6 and result.system.contact_gap.min() > 0.0
        lines.append(order * speed)
        assert order * speed == pytest.approx(natural, rel=0.05), (ratio, order)
    assert lines[1] == pytest.approx(lines[0], rel=0.05)       # locked while the speed grows


def test_the_subsynchronous_share_of_the_journal_orbit_measures_whirl(threshold):
    """The whirl label's raw measure, from the journal's own orbit relative to its housing:
    none below the threshold (the orbit is the unbalance's 1x; measured 6e-9 at 0.9 and 0.95
    of it), nearly all above it (0.984 at 1.05, 0.991 at 1.1)."""
    from rubdiag.runs import subsynchronous_share

    below = simulate(run(0.9 * threshold))
    above = simulate(run(1.1 * threshold))
    assert "shaft 0 y" in above.points and "shaft 6 z" in above.points
    assert subsynchronous_share(below, 0) < 1e-6
    assert subsynchronous_share(above, 0) > 0.99 and subsynchronous_share(above, 1) > 0.99
    with pytest.raises(ValueError, match="bearing = 5"):
        subsynchronous_share(above, 5)


def test_a_start_outside_the_clearance_is_refused_by_name():
    """An unbalance whose linear orbit reaches beyond the clearance at the start: refused
    before the integrator meets a film with no meaning (1000 times the rig's unbalance at
    800 rad/s puts the journals at several clearances)."""
    import dataclasses

    from rubdiag.model import Unbalance

    heavy = dataclasses.replace(run(800.0), unbalance=Unbalance((1e-2,), (0.0,)))
    with pytest.raises(ValueError, match=r"linear start puts journal bearing 0 .* clearances "
                                         r"from its centre"):
        simulate(heavy)
