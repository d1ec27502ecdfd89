"""A loose bearing pedestal in a run (issue 26): ``Faults(looseness=Looseness(...))`` on a rig
whose bearing sits on a :class:`~rubdiag.model.rig.Pedestal`.

The rig: the paper rig with bearing 0 (shaft node 4) on a 20 kg pedestal, support 20 MN/m and
500 N·s/m in y and z. Below lift-off the loose pedestal is the linear support; at twice the
first critical speed with a 4 N preload and no retaining spring it lifts off and rattles: a
½× line (measured: 1.14 × the 1× at the pedestal, 5.4 % of 1× at disc node 11). The reduced
model shows it too, with another amplitude (not held to 5 %: see the last test).
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from rubdiag.model import Pedestal, paper_rig
from rubdiag.reduce import Reduction
from rubdiag.simulate import Run, simulate
from rubdiag.simulate.faults import Faults, Looseness
from rubdiag.simulate.pedestal import lift_off_fraction
from rubdiag.simulate.rig_cache import forward_critical_speeds
from rubdiag.simulate.simulation import run_from_dict, run_to_dict
from rubdiag.simulate.static_load import StaticLoad

GRAVITY = StaticLoad(direction="y", gravity_m_s2=-9.81)
PEDESTAL = Pedestal(mass_kg=20.0, k_y_n_m=20e6, k_z_n_m=20e6, c_y_ns_m=500.0, c_z_ns_m=500.0)


@pytest.fixture(scope="module")
def rig():
    base = paper_rig()
    bearings = list(base.bearings)
    bearings[0] = dataclasses.replace(bearings[0], pedestal=PEDESTAL)
    return dataclasses.replace(base, bearings=tuple(bearings), name="paper, pedestal 0")


def line(result, point: str, order: float) -> float:
    """The amplitude of the ``order`` line of ``point``'s displacement over the window's
    whole multiple of 6 revolutions (a lock-in average: ½× and ⅓× fit in it)."""
    t = result.t[result.window]
    x = result.displacement(point, windowed=True)
    omega = result.run.speed_rad_s
    revs = math.floor((t[-1] - t[0]) * omega / (2 * math.pi))
    keep = t <= t[0] + (revs - revs % 6) * 2 * math.pi / omega
    phase = np.exp(-1j * order * omega * t[keep])
    return 2 * abs(np.mean((x[keep] - x[keep].mean()) * phase))


def test_looseness_is_validated_and_needs_a_pedestal(rig):
    with pytest.raises(ValueError, match=r"looseness\.preload_n"):
        Looseness(bearing=0, preload_n=-1.0)
    with pytest.raises(ValueError, match=r"looseness\.direction"):
        Looseness(bearing=0, preload_n=1.0, direction="x")
    with pytest.raises(ValueError, match=r"looseness\.clearance_m"):
        Looseness(bearing=0, preload_n=1.0, clearance_m=1e-5)
    with pytest.raises(ValueError, match=r"faults\.looseness\.bearing"):
        Run.paper_case(1, gap_mm=50.0, speed_rpm=750.0,
                       faults=Faults(looseness=Looseness(bearing=0, preload_n=1.0)))
    with pytest.raises(ValueError, match=r"faults\.looseness\.bearing"):
        Run.paper_case(1, gap_mm=50.0, speed_rpm=750.0, rig=rig,
                       faults=Faults(looseness=Looseness(bearing=1, preload_n=1.0)))
    with pytest.raises(ValueError, match=r"loose_stiffness_n_m"):
        Run.paper_case(1, gap_mm=50.0, speed_rpm=750.0, rig=rig, faults=Faults(
            looseness=Looseness(bearing=0, preload_n=1.0, loose_stiffness_n_m=1e9)))


def test_the_looseness_is_in_the_description_only_when_set(rig):
    run = Run.paper_case(1, gap_mm=50.0, speed_rpm=750.0, rig=rig,
                         faults=Faults(looseness=Looseness(bearing=0, preload_n=3.0)))
    data = run_to_dict(run)
    assert data["faults"]["looseness"]["preload_n"] == 3.0
    assert run_from_dict(data) == run
    without = run_to_dict(dataclasses.replace(run, faults=Faults()))
    assert "looseness" not in without["faults"]     # the faults' description as before


def test_below_lift_off_the_run_is_the_linear_support(rig):
    """Under gravity the seat carries ~200 N against a few N of dynamic force: the element is
    the support spring it replaces (measured: equal to 1e-15 m on 4 um)."""
    def run(**options):
        return Run.paper_case(1, gap_mm=50.0, speed_rpm=750.0, duration_s=0.3, discard_s=0.1,
                              rig=rig, static_load=GRAVITY, **options)
    linear = simulate(run())
    loose = simulate(run(faults=Faults(looseness=Looseness(bearing=0, preload_n=0.0))))
    assert lift_off_fraction(loose.system, loose.n_contacts) == 0.0
    for point in ("pedestal 0 y", "shaft 11 y", "shaft 11 z"):
        a, b = linear.displacement(point), loose.displacement(point)
        assert np.abs(a - b).max() <= 1e-9 * np.abs(a).max(), point
    # the seat is loaded: the pedestal sits below its unloaded position by weight / k_s
    assert linear.displacement("pedestal 0 y").mean() < -100.0 / PEDESTAL.k_y_n_m


@pytest.fixture(scope="module")
def rattling(rig):
    """Twice the first critical speed, 4 N preload, no retaining spring: lift-off."""
    rpm = 2.0 * forward_critical_speeds(rig, 1)[0] * 30.0 / math.pi

    def run(preload, **options):
        return Run.paper_case(1, gap_mm=50.0, speed_rpm=rpm, duration_s=1.0, discard_s=0.5,
                              rig=rig, faults=Faults(looseness=Looseness(bearing=0,
                                                                         preload_n=preload)),
                              **options)
    return run


def test_a_pedestal_that_lifts_off_makes_a_half_order_line(rattling):
    tight, loose = simulate(rattling(50.0)), simulate(rattling(4.0))
    assert lift_off_fraction(tight.system, tight.n_contacts) == 0.0
    assert lift_off_fraction(loose.system, loose.n_contacts) > 0.5
    for point, fraction in (("pedestal 0 y", 0.5), ("shaft 11 y", 0.02)):
        assert line(tight, point, 0.5) < 1e-3 * line(tight, point, 1.0), point
        assert line(loose, point, 0.5) > fraction * line(loose, point, 1.0), point


def test_the_reduced_model_keeps_the_pedestal_physical(rattling):
    """The pedestal DOFs are boundary coordinates of the reduction, so the support spring
    comes out of the reduced K exactly. Lifting off, the reduced model shows the ½× line too
    and the 1× at disc node 11 within 5 %; the ½× amplitudes themselves differ (measured at
    the pedestal: 1.8 against 3.7 um, a non-smooth response sensitive to the model): not held
    to 5 % here."""
    full = simulate(rattling(4.0))
    reduced = simulate(rattling(4.0, reduction=Reduction()))
    assert reduced.system.extra["model"] == "reduced"
    for point in ("pedestal 0 y", "shaft 11 y"):
        print(point, [(line(full, point, o), line(reduced, point, o)) for o in (0.5, 1.0)])
    a, b = line(full, "shaft 11 y", 1.0), line(reduced, "shaft 11 y", 1.0)
    assert abs(b - a) <= 0.05 * a
    assert line(reduced, "pedestal 0 y", 0.5) > 0.2 * line(reduced, "pedestal 0 y", 1.0)
