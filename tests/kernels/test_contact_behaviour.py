"""The contact law as seen in whole runs: definition, friction cone, stick, energy, logs."""

import itertools

import numpy as np
import pytest
import scipy.sparse as sp

from rubdiag.simulation import (
    AnnularContact,
    HarmonicForce,
    LinearSystem,
    PointContact,
    Recording,
    Solver,
    TimeGrid,
    simulate_system,
)

OPEN, SLIDING, STICKING = 1, 2, 3


def test_run_rubs_with_both_statuses(penalty_run):
    _, res = penalty_run
    st = res.contact_status
    assert (st == SLIDING).sum() > 20 and (st == STICKING).sum() > 20
    assert len(res.episodes) >= 4


def test_no_force_while_open_and_eq1_when_closed(penalty_run):
    s, res = penalty_run
    st, fn, ft, gap = res.contact_status, res.contact_fn, res.contact_ft, res.contact_gap
    assert np.all(fn[st == OPEN] == 0.0) and np.all(ft[st == OPEN] == 0.0)
    assert np.all(fn[gap > 0] == 0.0)
    closed = st != OPEN
    assert np.all(gap[closed] <= 0.0)
    kn = s.contacts[0].k_n
    np.testing.assert_allclose(fn[closed], -kn * gap[closed], rtol=1e-12)


def test_friction_cone_at_every_sample_and_every_step(penalty_run):
    s, res = penalty_run
    mu = s.contacts[0].mu
    assert np.all(np.abs(res.contact_ft) <= mu * res.contact_fn * (1 + 1e-12) + 1e-12)
    slide = res.contact_status == SLIDING
    np.testing.assert_allclose(np.abs(res.contact_ft[slide]), mu * res.contact_fn[slide],
                               rtol=1e-12)
    # the kernel's own running check over every step (not only samples)
    assert res.max_cone_excess <= 1e-9 * res.max_normal_force.max()


def test_sticking_freezes_relative_tangential_displacement(penalty_run):
    s, res = penalty_run
    kt = s.contacts[0].k_t
    # output_dt = dt: consecutive samples are consecutive steps
    both = (res.contact_status[1:] == STICKING) & (res.contact_status[:-1] == STICKING)
    assert both.sum() > 20
    anchor = res.contact_slip + res.contact_ft / kt  # s - e: the stick anchor
    jump = np.abs(np.diff(anchor, axis=0))[both]
    moved = np.abs(np.diff(res.contact_slip, axis=0))[both]
    assert jump.max() < 1e-12  # frozen up to round-off
    # and the slip that did happen is only the elastic stick deformation F_T / k_T
    assert np.all(moved <= np.abs(np.diff(res.contact_ft, axis=0))[both] / kt + 1e-12)
    assert moved.max() > 0  # it is not trivially frozen


def test_friction_dissipation_never_negative(penalty_run):
    _, res = penalty_run
    d = res.dissipated_friction
    assert d[0] == 0.0 and d[-1] > 0.0
    assert np.all(np.diff(d) >= 0.0)


def test_energy_balance_closes(penalty_run):
    _, res = penalty_run
    r = res.energy_balance_residual
    scale = res.mechanical_energy.max()
    assert np.abs(r).max() < 5e-3 * scale
    np.testing.assert_allclose(r, res.contact_algorithmic, atol=1e-10 * scale)


def test_episode_log_matches_the_per_step_samples(penalty_run):
    _, res = penalty_run
    ep = res.episodes
    for e in range(res.contact_status.shape[1]):
        closed = res.contact_status[:, e] != OPEN
        edges = np.diff(np.r_[0, closed.astype(int), 0])
        starts, ends = np.flatnonzero(edges == 1), np.flatnonzero(edges == -1)
        mine = ep.element == e + 1
        assert mine.sum() == starts.size
        np.testing.assert_array_equal(ep.n_steps[mine], ends - starts)
        peaks = [res.contact_fn[a:b, e].max() for a, b in zip(starts, ends, strict=True)]
        np.testing.assert_allclose(ep.peak_normal_force[mine], peaks, rtol=1e-14)
        # interpolated start/end lie inside the bracketing steps
        assert np.all(ep.t_start[mine] <= res.t[starts] + 1e-15)
        assert np.all(ep.t_start[mine] >= res.t[starts] - res.dt - 1e-15)
        n_stick_entries = [
            np.sum(np.diff(np.r_[0, (res.contact_status[a:b, e] == STICKING).astype(int)]) == 1)
            for a, b in zip(starts, ends, strict=True)
        ]
        np.testing.assert_array_equal(ep.n_stick_entries[mine], n_stick_entries)
    # per-status totals: every step attributed once
    np.testing.assert_allclose(res.time_in_status.sum(axis=1), res.t_final, rtol=1e-12)
    counts = np.stack([(res.contact_status[1:] == k).sum(axis=0) for k in (1, 2, 3)], axis=1)
    np.testing.assert_allclose(res.time_in_status, counts * res.dt, rtol=1e-9)
    np.testing.assert_allclose(res.normal_impulse[:, 1:].sum(axis=1),
                               res.contact_fn[1:].sum(axis=0) * res.dt, rtol=1e-9)


@pytest.mark.parametrize("boost", [0.0, 0.9])
def test_augmentation_keeps_penetration_within_eps(boost):
    """A free mass hits a penalty stop whose penalty penetration would be v0/ω_c = 160 µm;
    with the augmented Lagrangian at ε = 80 µm the penetration stays below ε at every step.
    (The rebound is then a rigid-wall impact at depth ε resolved by the trapezoidal rule:
    bounded, but not exactly elastic — see ``augment_boost`` in simulate_system.)"""
    m, kn, v_in, g0 = 0.2, 5e6, 0.8, 1e-3
    wc = np.sqrt(kn / m)
    T_c = np.pi / wc
    eps = 0.5 * v_in / wc
    M = sp.diags([m, m]).tocsr()
    K = sp.diags([0.0, 1e3]).tocsr()
    C = sp.csr_matrix((2, 2))
    runs = {}
    for aug in (False, True):
        ct = [PointContact(dof_a=(0, 1), normal=(1.0, 0.0), tangent=(0.0, 1.0), gap=g0,
                           k_n=kn, mu=0.0, augmented=aug, eps=eps)]
        runs[aug] = simulate_system(LinearSystem(M=M, C=C, K=K, v0=np.array([v_in, 0.0])),
                                    ct, TimeGrid(duration=g0 / v_in + 2 * T_c, dt=T_c / 100,
                                                 output_dt=T_c / 100),
                                    solver=Solver(augment_boost=boost))
    pen, aug = runs[False], runs[True]
    assert pen.max_penetration[0] > 1.9 * eps
    assert aug.max_penetration[0] <= eps
    assert aug.augment_iterations > 0
    closed = aug.contact_status[:, 0] != OPEN
    assert np.all(aug.contact_gap[closed, 0] > -eps)
    # F_N = k_N (-g) + λ with λ >= 0: never below the penalty force
    assert np.all(aug.contact_fn[closed, 0] >= -kn * aug.contact_gap[closed, 0] * (1 - 1e-12))
    assert len(aug.episodes) == 1 and aug.episodes.complete[0]
    assert -2 * v_in < aug.v_final[0] < -0.5 * v_in  # rebounds, bounded


def test_episode_log_growth_and_progress_do_not_change_results(penalty_run, make_rub_run):
    _, ref = penalty_run
    calls = []
    _, res = make_rub_run(outputs=Recording(progress=lambda t, T: calls.append((t, T))),
                          solver=Solver(episode_capacity=1))
    assert len(res.episodes) == len(ref.episodes)
    np.testing.assert_array_equal(res.episodes.t_start, ref.episodes.t_start)
    np.testing.assert_array_equal(res.q, ref.q)
    assert len(calls) >= 50 and calls[-1][0] == pytest.approx(calls[-1][1])
    assert all(b[0] >= a[0] for a, b in itertools.pairwise(calls))


def test_output_samples_are_exact_step_states(penalty_run, make_rub_run):
    _, ref = penalty_run
    _, res = make_rub_run(output_dt=10 * ref.dt)
    np.testing.assert_allclose(res.t, ref.t[::10], rtol=1e-15, atol=0)
    np.testing.assert_array_equal(res.q, ref.q[::10])
    np.testing.assert_array_equal(res.contact_status, ref.contact_status[::10])
    # the event log does not depend on the output rate
    np.testing.assert_array_equal(res.episodes.peak_normal_force, ref.episodes.peak_normal_force)


def test_annular_rub_slides_against_surface_speed_and_balances_energy():
    """Jeffcott disc (y, z) in an annular stator clearance, driven beyond it by unbalance."""
    m, k, c = 1.0, 4e4, 4.0
    M = sp.diags([m, m]).tocsr()
    K = sp.diags([k, k]).tocsr()
    C = sp.diags([c, c]).tocsr()
    omega = 220.0  # above the critical sqrt(k/m) = 200 rad/s
    force = HarmonicForce.unbalance(0, 1, 2e-4, omega)
    ct = [AnnularContact(dof_a=(0, 1), clearance=1e-3, radius=0.05, k_n=2e6, mu=0.2)]
    res = simulate_system(LinearSystem(M=M, C=C, K=K, force=force, omega=omega), ct,
                          TimeGrid(duration=0.3, dt=2e-5, output_dt=2e-5))
    st = res.contact_status[:, 0]
    closed = st != OPEN
    assert closed.sum() > 100
    assert np.all(st[closed] == SLIDING)  # Ω R = 11 m/s: never sticks
    fn, ft = res.contact_fn[closed, 0], res.contact_ft[closed, 0]
    np.testing.assert_allclose(ft, -0.2 * fn, rtol=1e-12)  # opposes the surface speed
    np.testing.assert_allclose(res.contact_gap[closed, 0], -fn / 2e6, rtol=1e-9)
    r = np.hypot(res.q[:, 0], res.q[:, 1])
    np.testing.assert_allclose(res.contact_gap[:, 0], 1e-3 - r, rtol=0, atol=3e-12)
    assert res.work_drive[-1] > 0
    assert np.all(np.diff(res.dissipated_friction) >= 0)
    scale = res.mechanical_energy.max() + res.work_drive[-1]
    assert np.abs(res.energy_balance_residual).max() < 1e-2 * scale


def test_episode_status_times_add_up_to_the_per_element_totals(penalty_run):
    """Per-episode sliding/sticking times and impulses sum to the kernel's per-element totals
    (both gathered at every step)."""
    _, res = penalty_run
    ep = res.episodes
    for e in range(res.contact_fn.shape[1]):
        mine = ep.element == e + 1
        np.testing.assert_allclose(ep.slide_time[mine].sum(), res.time_in_status[e, 1],
                                   rtol=1e-9, atol=1e-15)
        np.testing.assert_allclose(ep.stick_time[mine].sum(), res.time_in_status[e, 2],
                                   rtol=1e-9, atol=1e-15)
        np.testing.assert_allclose(ep.slide_impulse[mine].sum(), res.normal_impulse[e, 1],
                                   rtol=1e-9, atol=1e-15)
        np.testing.assert_allclose(ep.stick_impulse[mine].sum(), res.normal_impulse[e, 2],
                                   rtol=1e-9, atol=1e-15)
    assert np.all(ep.slide_time + ep.stick_time <= ep.duration + res.dt)
    assert res.time_in_status[:, 1:].sum() > 0
