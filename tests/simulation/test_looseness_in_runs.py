"""A loose bearing pedestal in a run: ``Faults(looseness=Looseness(...))`` on a rig
whose bearing sits on a :class:`~rubdiag.model._rig.Pedestal`.

The rig: the paper rig with bearing 0 (shaft node 4) on a 20 kg pedestal, support 20 MN/m and
500 N·s/m in y and z. Below lift-off the loose pedestal is the linear support. At twice the
first critical speed with a 2 N preload and a 2 MN/m retaining spring it lifts off (70 % of
the time) in a motion of period two revolutions: a steady ½× line (measured: 0.69 × the 1×
at the pedestal, 1.6 % of 1× at disc node 11, the same over 0.5 and 0.75 s windows), the
reduced model's equal to 2e-5.
Without a retaining spring the lifted pedestal wanders (½× and ⅓× that change with the
window and the preload): not the case tested.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from rubdiag.model import Pedestal, paper_rig
from rubdiag.reduce import Reduction
from rubdiag.simulation import Run, simulate
from rubdiag.simulation._faults import Faults, Looseness
from rubdiag.simulation._pedestal import lift_off_fraction
from rubdiag.simulation._rig_cache import forward_critical_speeds
from rubdiag.simulation._run_dict import run_from_dict, run_to_dict
from rubdiag.simulation._static_load import StaticLoad

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
    """Twice the first critical speed, a 2 MN/m retaining spring: ``run(preload_n)``."""
    rpm = 2.0 * forward_critical_speeds(rig, 1)[0] * 30.0 / math.pi

    def run(preload, **options):
        looseness = Looseness(bearing=0, preload_n=preload, loose_stiffness_n_m=2e6)
        return Run.paper_case(1, gap_mm=50.0, speed_rpm=rpm, duration_s=1.0, discard_s=0.5,
                              rig=rig, faults=Faults(looseness=looseness), **options)
    return run


@pytest.fixture(scope="module")
def lifting(rattling):
    return simulate(rattling(2.0))


def test_a_pedestal_that_lifts_off_makes_a_half_order_line(rattling, lifting):
    tight = simulate(rattling(50.0))
    assert lift_off_fraction(tight.system, tight.n_contacts) == 0.0
    assert lift_off_fraction(lifting.system, lifting.n_contacts) > 0.5     # measured 0.70
    for point, fraction in (("pedestal 0 y", 0.5), ("shaft 11 y", 0.01)):
        assert line(tight, point, 0.5) < 1e-3 * line(tight, point, 1.0), point
        assert line(lifting, point, 0.5) > fraction * line(lifting, point, 1.0), point
    # period 2, not a wandering pedestal: no third order
    assert line(lifting, "pedestal 0 y", 1 / 3) < 0.01 * line(lifting, "pedestal 0 y", 1.0)


def test_the_reduced_model_keeps_the_pedestal_physical_and_the_half_order_line(rattling,
                                                                                 lifting):
    """The pedestal DOFs are boundary coordinates of the reduction, so the support spring
    comes out of the reduced K exactly; the ½× lines agree within 5 % (measured: 2e-5)."""
    reduced = simulate(rattling(2.0, reduction=Reduction()))
    assert reduced.system.extra["model"] == "reduced"
    for point in ("pedestal 0 y", "shaft 11 y"):
        a, b = line(lifting, point, 0.5), line(reduced, point, 0.5)
        assert abs(b - a) <= 0.05 * a, point
