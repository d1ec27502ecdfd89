"""A static load: an order-0 "constant" load term f = Re(F) that does not
turn, gravity and side loads on a rig (``Run.static_load``), and runs that start from the
static deflection K⁻¹f added to the harmonic steady state.

The physics checks are linear closed forms: a damped linear system under a constant load
settles at K⁻¹f (Newmark's equilibrium is exactly K q = f), and started there it stays
there — with a harmonic load on top, the difference between the runs with and without the
static load is K⁻¹f at every sample, at constant speed and along a speed ramp.
"""

from __future__ import annotations

import dataclasses
import pickle

import numpy as np
import pytest

import rubdiag
from rubdiag.assembly._assemble import assemble
from rubdiag.dataset import point_id, run_id
from rubdiag.simulation import (
    AnnularContact,
    HarmonicForce,
    LinearSystem,
    Run,
    TimeGrid,
    simulate,
    simulate_system,
)
from rubdiag.simulation._rig_cache import damped_model
from rubdiag.simulation._rig_system import rig_system
from rubdiag.simulation._run_dict import run_from_dict, run_to_dict
from rubdiag.simulation._speed_profile import SpeedProfile
from rubdiag.simulation._static_load import StaticLoad

SPEED = 60.0                          # rad/s
F_STATIC = np.array([25.0, -40.0])    # N


def _two_dof():
    M = np.diag([2.0, 1.5])
    K = np.array([[4e4, -1e4], [-1e4, 3e4]])
    C = 4e-3 * K + 1.0 * M            # ζ ≈ 0.25 on both modes: a transient gone in ~1 s
    return M, C, K


def _static(speed=SPEED) -> HarmonicForce:
    return HarmonicForce([0, 1], F_STATIC, speed, order=0, law="constant")


# --------------------------------------------------------------------------------------------
# the order-0 term
# --------------------------------------------------------------------------------------------
def test_order_zero_is_a_static_load_with_the_constant_law_only():
    force = _static()
    assert force.frequencies.tolist() == [0.0, 0.0]
    assert np.array_equal(force.evaluate(0.123, 2), F_STATIC)
    # Re(F): an imaginary part is a load at phase 90°, which for a load that does not turn
    # is no load
    assert np.array_equal(HarmonicForce([0], [3.0 + 7j], 1.0, order=0, law="constant")
                          .evaluate(5.0, 1), [3.0])
    for law, extra in (("unbalance", {}), ("table", {"table": [[0.0, 1.0]]})):
        with pytest.raises(ValueError, match=rf"force.order\[0\] = 0.0 is out of range "
                           rf"\(allowed: nonzero for the law '{law}' \(0, a static load, "
                           r"only with 'constant'\)"):
            HarmonicForce([0], [1.0], 1.0, order=0, law=law, **extra)
    # one term per law: only the static one may have order 0
    mixed = HarmonicForce([0, 0], [1.0, 2.0], 1.0, order=[0, 1], law=["constant", "unbalance"])
    assert mixed.order.tolist() == [0.0, 1.0]


def test_a_static_load_settles_at_the_static_deflection():
    M, C, K = _two_dof()
    res = simulate_system(LinearSystem(M=M, C=C, K=K, force=_static()), None,
                          TimeGrid(duration=1.5, dt=1e-3, fixed_step=True))
    x_static = np.linalg.solve(K, F_STATIC)
    assert np.abs(res.q[0]).max() == 0.0 and np.abs(res.q[50] - x_static).max() > 1e-4
    # measured 2e-15 relative at 1.5 s: the transient (decay rate ~35 /s) is gone
    assert np.abs(res.q[-1] - x_static).max() < 1e-10 * np.abs(x_static).max()


def test_started_at_the_static_deflection_there_is_no_transient():
    M, C, K = _two_dof()
    x_static = np.linalg.solve(K, F_STATIC)
    res = simulate_system(LinearSystem(M=M, C=C, K=K, force=_static(), q0=x_static), None,
                          TimeGrid(duration=0.2, dt=1e-4, fixed_step=True))
    assert np.abs(res.q - x_static).max() < 1e-12 * np.abs(x_static).max()    # measured 0


@pytest.mark.parametrize("ramp", [False, True])
def test_with_a_harmonic_load_the_static_load_adds_its_deflection_at_every_sample(ramp):
    """Linear superposition: (harmonic + static, from x_h0 + K⁻¹f) minus (harmonic, from
    x_h0) is K⁻¹f at every sample, whatever the harmonic part does (its own start is not
    the discrete steady state, and along the ramp the unbalance grows as Ω²): the static
    load does not turn with the shaft."""
    M, C, K = _two_dof()
    profile = SpeedProfile.ramp(600.0, 1600.0, 4000.0, hold_s=0.01) if ramp else None
    speed = profile.start_rad_s if ramp else SPEED
    unbalance = HarmonicForce.unbalance(0, 1, 2e-3, speed)
    x_static = np.linalg.solve(K, F_STATIC)
    grid = TimeGrid(duration=0.4, dt=1e-4, fixed_step=True)
    varying = dict(speed_profile=profile, gyroscopic=np.zeros((2, 2))) if ramp else {}
    q0 = np.array([1e-5, -2e-5])
    plain = simulate_system(LinearSystem(M=M, C=C, K=K, force=unbalance, q0=q0, **varying),
                            None, grid)
    loaded = simulate_system(LinearSystem(M=M, C=C, K=K, force=unbalance + _static(speed),
                                          q0=q0 + x_static, **varying), None, grid)
    assert np.abs(plain.q).max() > 1e-4            # the harmonic part is not small
    diff = loaded.q - plain.q
    # measured 6e-15 (constant speed) and 3e-14 (ramp) of the static deflection
    assert np.abs(diff - x_static).max() < 1e-10 * np.abs(x_static).max()


# --------------------------------------------------------------------------------------------
# the description
# --------------------------------------------------------------------------------------------
@pytest.mark.parametrize(("kwargs", "match"), [
    (dict(direction="x"), r"static_load.direction = 'x' is not allowed \(allowed: y, z\)"),
    (dict(gravity_m_s2=2e3), r"static_load.gravity_m_s2 = 2000.0 is out of range"),
    (dict(gravity_m_s2=np.nan), r"static_load.gravity_m_s2 = nan is out of range"),
    (dict(force_n=10.0), r"static_load.node = None with force_n = 10.0 \(allowed: a node "
                         r"exactly when force_n is nonzero\)"),
    (dict(node=3), r"static_load.node = 3 with force_n = 0.0"),
    (dict(force_n=1.0, node=-1), r"static_load.node = -1 is out of range"),
    (dict(force_n=1.0, node=2.0), r"static_load.node = 2.0 has the wrong type"),
])
def test_bad_static_loads_are_refused(kwargs, match):
    with pytest.raises(ValueError, match=match):
        StaticLoad(**kwargs)


def test_gravity_is_the_weight_of_every_mass_and_a_side_load_one_force():
    rig = rubdiag.paper_rig()
    model = assemble(rig)
    g = StaticLoad(direction="z", gravity_m_s2=-9.81).vector(model.M, model.dofs)
    labels = model.dofs.labels
    along = np.array([lab.endswith(" z") for lab in labels])
    across = np.array([lab.endswith(" y") for lab in labels])
    # the total mass from the parts, written out: shaft (ρ A L per element), discs, blades
    # (ρ w t L), casing ring (ρ b h × chord × n)
    shaft, mat = rig.shaft, rig.material
    area = np.pi / 4 * (np.asarray(shaft.outer_diameters_m) ** 2
                        - np.asarray(shaft.inner_diameters_m) ** 2)
    total = mat.density_kg_m3 * float(np.sum(area * np.asarray(shaft.element_lengths_m)))
    total += sum(d.inertia(mat.density_kg_m3)[0] for d in rig.discs)
    b, c = rig.blades, rig.casing
    total += b.count * mat.density_kg_m3 * b.width_m * b.thickness_m * b.length_m
    chord = 2 * c.radius_m * np.sin(np.pi / c.n_elements)
    total += c.n_elements * mat.density_kg_m3 * c.axial_width_m * c.radial_height_m * chord
    assert g[along].sum() == pytest.approx(-9.81 * total, rel=1e-12)
    assert np.abs(g[across]).max() < 1e-15 * 9.81 * total     # rotated frames: roundoff
    side = StaticLoad(direction="y", force_n=120.0, node="casing 3").vector(model.M, model.dofs)
    assert np.flatnonzero(side).tolist() == [model.dofs.index("casing 3", "y")]
    assert side.sum() == 120.0


@pytest.fixture(scope="module")
def paper():
    # a 50-mm gap: the blades never touch, so the runs are linear
    return Run.paper_case(1, 50.0, speed_rpm=1500.0, duration_s=0.02, discard_s=0.0,
                          gap_ramp_s=0.0)


def test_a_run_without_a_static_load_is_described_and_identified_as_before(paper):
    assert paper.static_load is None and "static_load" not in run_to_dict(paper)
    loaded = dataclasses.replace(paper, static_load=StaticLoad(gravity_m_s2=-9.81))
    data = run_to_dict(loaded)
    assert data["static_load"] == {"direction": "y", "gravity_m_s2": -9.81, "force_n": 0.0,
                                   "node": None, "clearances": "loaded"}
    assert run_from_dict(data) == loaded
    assert pickle.loads(pickle.dumps(loaded)) == loaded
    assert run_id(loaded) != run_id(paper) and point_id(loaded) != point_id(paper)
    with pytest.raises(ValueError, match=r"static_load.node = 'shaft 99' is not a node"):
        dataclasses.replace(paper, static_load=StaticLoad(force_n=1.0, node="shaft 99"))
    with pytest.raises(TypeError, match=r"static_load = 'float' has the wrong type"):
        dataclasses.replace(paper, static_load=9.81)


def test_a_rig_run_starts_from_its_static_deflection_and_stays_on_it(paper):
    """The paper rig at 1500 rpm with gravity along -y and a side load on the casing:
    x0 is the harmonic start plus K⁻¹f, the load holds order-0 terms, and the run minus
    the run without the load is the static deflection at every recorded sample."""
    load = StaticLoad(direction="y", gravity_m_s2=-9.81, force_n=50.0, node="casing 1")
    loaded = dataclasses.replace(paper, static_load=load)
    model = damped_model(paper.rig)
    plain_sys, loaded_sys = rig_system(paper, model), rig_system(loaded, model)
    f = load.vector(model.M, model.dofs)
    x_static = loaded_sys.x0 - plain_sys.x0
    assert np.abs(model.K @ x_static - f).max() < 1e-9 * np.abs(f).max()
    static_terms = loaded_sys.force.order == 0
    assert set(loaded_sys.force.law[j] for j in np.flatnonzero(static_terms)) == {"constant"}
    assert np.array_equal(loaded_sys.force.dofs[static_terms], np.flatnonzero(f))
    assert np.array_equal(plain_sys.v0, loaded_sys.v0)
    plain, heavy = simulate(paper), simulate(loaded)
    assert plain.system.contact_fn.max() == 0.0 == heavy.system.contact_fn.max()
    index = [model.dofs.index(*p.rsplit(" ", 1)) for p in plain.points]
    expected = x_static[index]
    diff = heavy.system.q - plain.system.q
    assert np.abs(expected).max() > 1e-6          # the sag is not negligible
    # measured 4.3e-10 of the largest deflection (0.41 mm) over 2000 steps: the roundoff
    # of two 412-DOF runs whose states are ~1 mm (sparse LU of a stiff casing)
    assert np.abs(diff - expected).max() < 5e-9 * np.abs(expected).max()


def test_a_reduced_run_starts_from_the_reduced_static_deflection(paper):
    """The reduced model's start is its own static equilibrium, K_r x = Tᵀ f, which is the
    full model's static deflection to the reduction's accuracy at the response points
    (measured 2.2e-5 of the 0.41-mm sag with the default 2-kHz cutoff)."""
    from rubdiag.reduce import Reduction
    from rubdiag.simulation import response_points

    reduced = dataclasses.replace(paper, reduction=Reduction())
    load = StaticLoad(direction="y", gravity_m_s2=-9.81)
    model = damped_model(paper.rig)
    plain = rig_system(reduced, model)
    loaded = rig_system(dataclasses.replace(reduced, static_load=load), model)
    x_static = loaded.x0 - plain.x0
    f = load.vector(model.M, model.dofs)
    T = plain.recovery
    assert np.abs(loaded.K @ x_static - T.T @ f).max() < 1e-9 * np.abs(T.T @ f).max()
    full = np.linalg.solve(model.K.toarray(), f)
    points = [model.dofs.index(*p.rsplit(" ", 1)) for p in response_points(paper.rig)]
    assert np.abs((T @ x_static - full)[points]).max() < 1e-4 * np.abs(full[points]).max()
    assert sorted(set(loaded.force.order.tolist())) == [0.0, 1.0]


def mean_gaps(result) -> np.ndarray:
    """Each contact's gap averaged over the run's whole revolutions (m): the static part of
    a linear run's gap, the harmonic averaging out."""
    t = result.t
    revolution = 2 * np.pi / result.run.speed_rad_s
    keep = t < t[0] + np.floor((t[-1] - t[0]) / revolution) * revolution
    return result.system.contact_gap[keep].mean(axis=0)


def test_loaded_clearances_are_the_gap_at_the_static_state_and_unloaded_ones_close():
    """Under gravity the paper rig's discs sag 0.41 mm. "loaded" (default): every blade sees
    the run's gap at the static state; "unloaded": the casing stays where it was, so each
    blade's mean gap is the run's gap less its tip's static approach, computed here from
    K⁻¹f. At 0.45 mm and half the critical speed (linear orbit 80 um) the loaded rig does
    not rub; the unloaded one rubs on its sag."""
    def run(gap_mm, clearances):
        return Run.paper_case(1, gap_mm, speed_rpm=750.0, duration_s=0.16, discard_s=0.0,
                              gap_ramp_s=0.0, static_load=StaticLoad(
                                  gravity_m_s2=-9.81, clearances=clearances))
    model = damped_model(run(0.6, "loaded").rig)
    f = run(0.6, "loaded").static_load.vector(model.M, model.dofs)
    sag = np.linalg.solve(model.K.toarray(), f)
    geo = model.blade_contacts
    approach = np.sum((sag[geo.tip_dofs] - sag[geo.casing_dofs]) * geo.normal, axis=1)
    assert approach.max() > 0.4e-3                  # the bottom blades: the sag
    for clearances, expected in (("loaded", 0.6e-3), ("unloaded", 0.6e-3 - approach)):
        result = simulate(run(0.6, clearances))     # linear: no blade touches
        assert result.system.contact_fn.max() == 0.0
        assert np.abs(mean_gaps(result) - expected).max() < 1e-3 * 0.6e-3, clearances
    assert simulate(run(0.45, "loaded")).system.contact_fn.max() == 0.0
    assert simulate(run(0.45, "unloaded")).system.contact_fn.max() > 0.0


def test_the_loaded_gaps_hold_in_the_reduced_model_and_the_ramp_starts_above_the_orbit():
    from rubdiag.reduce import Reduction

    run = Run.paper_case(1, 0.45, speed_rpm=750.0, duration_s=0.16, discard_s=0.08,
                         static_load=StaticLoad(gravity_m_s2=-9.81), reduction=Reduction())
    model = damped_model(run.rig)
    system = rig_system(run, model)
    gaps = np.array([c.gap for c in system.contacts])
    assert np.abs(gaps - system.gap_shift - 0.45e-3).max() < 1e-15
    assert 60e-6 < system.approach < 100e-6          # the harmonic orbit alone, not the sag
    result = simulate(run)                            # with the default gap ramp
    assert result.system.contact_fn.max() == 0.0
    late = result.t > run.gap_ramp_s
    assert np.abs(result.system.contact_gap[late].mean(axis=0) - 0.45e-3).max() < 2e-6


def test_a_seal_aligned_on_the_loaded_rotor_is_centred_on_its_sag():
    """Gravity sags the paper rig about 0.4 mm at its disc: a 0.2 mm seal there, aligned on
    the loaded rotor ("loaded"), is centred on the sag and never touched by the 1x orbit;
    the same seal about the bearing line ("unloaded") is closed by the sag itself."""
    from rubdiag.model import StatorContact, paper_rig

    rig = dataclasses.replace(paper_rig(), stator_contacts=(StatorContact(
        node=11, clearance_m=0.2e-3, stiffness_n_m=1e7),))
    gravity = StaticLoad(gravity_m_s2=-9.81)
    run = Run.paper_case(1, 50.0, speed_rpm=750.0, duration_s=0.1, discard_s=0.0, rig=rig,
                         static_load=gravity)
    model = damped_model(rig)
    system = rig_system(run, model)
    seal = np.array([isinstance(c, AnnularContact) for c in system.contacts])
    sag = _sag(model, gravity, 11)
    assert sag[0] < -0.3e-3                                    # downwards, beyond the seal
    np.testing.assert_allclose(system.contacts[np.flatnonzero(seal)[0]].centre, sag,
                               rtol=1e-9)
    assert system.approach < 0.1e-3          # the orbit alone: the sag is not an approach
    loaded = simulate(run)
    assert loaded.system.contact_fn[:, seal].max() == 0.0
    unloaded = simulate(dataclasses.replace(run, static_load=StaticLoad(
        gravity_m_s2=-9.81, clearances="unloaded")))
    late = unloaded.t > 0.05
    assert unloaded.system.contact_fn[late][:, seal].min() > 0.0    # resting on the seal


def _sag(model, load, node):
    """The static deflection (y, z) of ``node`` under ``load`` (K⁻¹ f, bearings rigid)."""
    import scipy.sparse.linalg as spla

    q = spla.spsolve(model.K.tocsc(), load.vector(model.M, model.dofs))
    return q[[model.dofs.index(node, "y"), model.dofs.index(node, "z")]]
