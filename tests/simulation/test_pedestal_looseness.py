"""Mechanical looseness: a bearing pedestal that lifts off its seat, a kind
of nonlinear element on the seam (rubdiag/_kernels/pedestal.py, rubdiag/simulation/_pedestal.py).

The test system: a Jeffcott disc (10 kg, DOFs 0 y, 1 z) on a shaft spring (2e7 N/m) from a
bearing pedestal (5 kg, DOFs 2 y, 3 z); the far bearing ties the disc to ground (1e6 N/m).
The pedestal sits on a seat of 1e7 N/m vertically (y, lift-off upwards), pressed down by a
200 N preload; laterally (z) it is held by a linear 4e6 N/m. Dashpots of 60 N s/m from disc
and pedestal to ground. Unbalance at the disc (forward, 1e-3 kg m). Seated, the first
vertical mode is at 124.8 Hz; with the pedestal lifted (the disc on the far bearing only, the
pedestal riding on the shaft) at 41.0 Hz — their bilinear frequency 2 f1 f2 / (f1 + f2) is
61.7 Hz, so the ½× subharmonic resonance of the piecewise-linear support lies near 123 Hz.
The tests run at 140 Hz, where the response settles to a period of two revolutions
(measured: ⅓× below 1 % of 1×; the ½×, 1½×, 2×, 3× lines below are the same to 3 digits for
dt = 5e-6 .. 2e-5 s, run lengths 0.4-1 s, unbalance 0.8e-3 .. 1.2e-3 kg m and 135-145 Hz
within a factor 1.4). A run is started from the seated linear steady state.
"""

from __future__ import annotations

import types

import numpy as np
import pytest

from rubdiag._kernels import pedestal as law_module
from rubdiag._kernels import records
from rubdiag.simulation import HarmonicForce, LinearSystem, Solver, TimeGrid, simulate_system
from rubdiag.simulation._pedestal import LoosePedestal, lift_off_fraction

DISC_MASS, PEDESTAL_MASS = 10.0, 5.0         # kg
K_FAR, K_SHAFT, K_SEAT, K_LATERAL = 1e6, 2e7, 1e7, 4e6      # N/m
DAMPING = 60.0                               # N s/m
PRELOAD = 200.0                              # N
SPEED_HZ = 140.0
UNBALANCE = 1e-3                             # kg m
DT = 2e-5                                    # s
#: the seam and K give the same discrete equations below lift-off (round-off only)
LINEAR_RTOL = 1e-9


def rotor(seat_in_k: bool):
    """M, C, K of the disc-and-pedestal test system (module docstring)."""
    M = np.diag([DISC_MASS, DISC_MASS, PEDESTAL_MASS, PEDESTAL_MASS])
    K = np.zeros((4, 4))
    for disc, ped in ((0, 2), (1, 3)):
        K[disc, disc] += K_FAR + K_SHAFT
        K[ped, ped] += K_SHAFT
        K[disc, ped] = K[ped, disc] = -K_SHAFT
    K[3, 3] += K_LATERAL
    if seat_in_k:
        K[2, 2] += K_SEAT
    return M, DAMPING * np.eye(4), K


def pedestal_run(unbalance: float, duration: float, seat_in_k: bool = False,
                 loose_stiffness: float = 0.0, solver: Solver | None = None):
    """A run at SPEED_HZ from the seated linear steady state: the loose pedestal (or its
    seat spring in K, no element)."""
    M, C, K = rotor(seat_in_k)
    omega = 2 * np.pi * SPEED_HZ
    f_u = unbalance * omega**2
    force = HarmonicForce([0, 1], [f_u, -1j * f_u], omega)
    _, _, k_seated = rotor(True)
    load = np.array([f_u, -1j * f_u, 0, 0])
    u = np.linalg.solve(k_seated - omega**2 * M + 1j * omega * C, load)
    system = LinearSystem(M=M, C=C, K=K, force=force, q0=u.real, v0=(1j * omega * u).real,
                          omega=omega)
    elements = None if seat_in_k else [LoosePedestal(dof=2, stiffness=K_SEAT, preload=PRELOAD,
                                                     loose_stiffness=loose_stiffness)]
    return simulate_system(system, elements, TimeGrid(duration=duration, dt=DT),
                           solver=solver or Solver()), u


def order_amplitudes(t, y, orders):
    """Amplitudes of ``y`` at the given shaft orders (Hann window; the largest bin within
    ±2 bins of each order)."""
    y = y - y.mean()
    window = np.hanning(y.size)
    spectrum = np.abs(np.fft.rfft(y * window)) * 2 / window.sum()
    f = np.fft.rfftfreq(y.size, t[1] - t[0])
    out = []
    for order in orders:
        i = int(np.argmin(np.abs(f - order * SPEED_HZ)))
        out.append(spectrum[max(i - 2, 0):i + 3].max())
    return np.array(out)


# ---- (1) the law against its definition


@pytest.mark.parametrize("k_l", [0.0, 2e5])
def test_law_force_jacobian_and_lift_off(k_l):
    k_s, f_0 = 1e7, 200.0
    x_c = f_0 / k_s
    force = law_module.force
    for x in (-3e-4, -1e-6, 0.0, 1e-5, 1.9e-5):       # seated: the linear pedestal
        p, dp, status, fn = force(x, k_s, k_l, f_0, x_c)
        assert p == pytest.approx(-k_s * x, rel=1e-12, abs=1e-9)
        assert (dp, status) == (-k_s, law_module.SEATED)
        assert fn == pytest.approx(f_0 - k_s * x, rel=1e-12)       # the seat's force
    for x in (2.1e-5, 1e-4, 3e-3):                     # lifted: the dead load (and retainer)
        p, dp, status, fn = force(x, k_s, k_l, f_0, x_c)
        assert p == pytest.approx(-f_0 - k_l * (x - x_c), rel=1e-12)
        assert dp == -k_l and fn == 0.0
        assert status == (records.OPEN if k_l == 0 else law_module.LIFTED)
    # continuous at the seat, Jacobian = central differences away from it
    below = force(x_c * (1 - 1e-12), k_s, k_l, f_0, x_c)[0]
    above = force(x_c * (1 + 1e-12), k_s, k_l, f_0, x_c)[0]
    assert abs(below - above) < 1e-9 * f_0
    for x in (-2e-4, 5e-6, 6e-5, 1e-3):
        h = 1e-9
        fd = (force(x + h, k_s, k_l, f_0, x_c)[0] - force(x - h, k_s, k_l, f_0, x_c)[0]) / 2 / h
        assert force(x, k_s, k_l, f_0, x_c)[1] == pytest.approx(fd, rel=1e-6)


def test_law_on_the_seam_records_and_books():
    """law() and books() on the seam's records: force, Jacobian, record, and the books (the
    engaged spring's energy; the dead load's work F_0 Δx booked as drive work)."""
    ped = LoosePedestal(dof=0, stiffness=1e7, preload=200.0, lift_sign=-1)
    packed = ped.pack(0.0)
    el = records.zeros(records.ELEMENT)
    el[0]["kind"], el[0]["n"] = law_module.KIND, 1
    par = packed.par[None, :].copy()
    es = np.zeros((2, 1, len(law_module.STATE)))
    track, trial = records.zeros(records.TRACK), records.zeros(records.TRIAL)
    prog = records.zeros(records.PROGRESS)
    jac = np.zeros((1, 8))
    xs = np.zeros((3, 1))
    for x, x_n, seated in ((-1e-5, 2e-6, True), (5e-5, 1e-5, False)):
        wc = np.zeros((5, 1))
        wc[records.D_NEW, 0] = x
        xs[records.X_N, 0] = x_n
        status = law_module.law(0, el, wc, xs, par, es, track, trial, prog, jac)
        law_module.books(0, el, par, es, track, trial, prog)
        gap = x - 2e-5
        assert status == trial[0]["status"] == (law_module.SEATED if seated else records.OPEN)
        assert wc[records.P_NEW, 0] == pytest.approx(-1e7 * x if seated else -200.0)
        assert jac[0, 0] == (-1e7 if seated else 0.0)
        assert trial[0]["gap"] == pytest.approx(gap)
        assert trial[0]["elastic"] == pytest.approx(0.5 * 1e7 * gap**2 if seated else 0.0)
        assert trial[0]["w_ramp"] == pytest.approx(200.0 * (x - x_n))
    # the description packs the DOF's sign as T: x = -q[0]
    assert packed.tmat.tolist() == [[-1.0]] and packed.rows.tolist() == [[0, -1]]


@pytest.mark.parametrize(("field", "value"), [
    ("dof", -1), ("dof", 1.0), ("stiffness", 0.0), ("stiffness", np.inf), ("preload", -1.0),
    ("clearance", -1e-6), ("clearance", 1e-5), ("loose_stiffness", 2e7),
    ("loose_stiffness", -1.0), ("lift_sign", 0), ("base_dof", -2), ("base_dof", 2),
])
def test_description_refuses_bad_values_by_name(field, value):
    good = {"dof": 2, "stiffness": 1e7, "preload": 200.0}
    with pytest.raises(ValueError, match=rf"LoosePedestal\.{field} ="):
        LoosePedestal(**{**good, field: value})


def test_description_seat_position_step_requirement_and_dofs():
    ped = LoosePedestal(dof=2, stiffness=1e7, preload=200.0, base_dof=5)
    assert ped.seat_position == pytest.approx(2e-5)
    assert LoosePedestal(dof=2, stiffness=1e7, clearance=1e-4).seat_position == -1e-4
    assert ped.stiffness_ratio(np.array([[3e-8]])) == pytest.approx(0.3)
    assert ped.multiplier_stiffness(np.array([[3e-8]]), 1.0) == 0.0
    assert ped.dofs().tolist() == [2, 5]
    assert LoosePedestal(dof=2, stiffness=1e7).dofs().tolist() == [2]


def test_lift_off_fraction_from_time_in_status():
    result = types.SimpleNamespace(time_in_status=np.array([[0.1, 0.3, 0.0],
                                                            [0.05, 0.15, 0.2]]))
    assert lift_off_fraction(result) == pytest.approx(0.25)
    assert lift_off_fraction(result, 1) == pytest.approx(0.625)     # open and retained
    with pytest.raises(ValueError, match="element = 2"):
        lift_off_fraction(result, 2)


# ---- (2) below the lift-off threshold: the linear pedestal


def test_below_lift_off_equals_the_linear_pedestal():
    """Unbalance 5e-5 kg m: the seated steady state's seat force amplitude is 0.72 of the
    preload, so the pedestal never lifts; the run equals the seat spring in K. (Newton
    tolerance 1e-14 m: at the default 1e-12 m, steps whose predictor lands within it keep the
    predictor's seat force, 9.3e-10 of the response here — 8e-12 at 1e-14 m.)"""
    unbalance = 5e-5
    loose, u = pedestal_run(unbalance, 0.2, solver=Solver(newton_tol=1e-14))
    linear, _ = pedestal_run(unbalance, 0.2, seat_in_k=True)
    assert K_SEAT * abs(u[2]) / PRELOAD == pytest.approx(0.72, abs=0.01)
    assert lift_off_fraction(loose) == 0.0 and loose.n_steps == linear.n_steps
    scale = np.abs(linear.q).max()
    np.testing.assert_allclose(loose.q, linear.q, rtol=0, atol=LINEAR_RTOL * scale)
    # the seat's energy is its spring's, about the unloaded seat
    gap = loose.contact_gap[:, 0]
    np.testing.assert_allclose(loose.contact_elastic, 0.5 * K_SEAT * gap**2, rtol=1e-12)
    np.testing.assert_allclose(loose.contact_fn[:, 0], -K_SEAT * gap, rtol=1e-12)


# ---- (3), (4) above it: subharmonic, harmonics, a truncated orbit, the ledger


@pytest.fixture(scope="module")
def loose_run():
    result, u = pedestal_run(UNBALANCE, 0.6)
    return result, u


def test_above_lift_off_half_order_and_harmonics(loose_run):
    """At 140 Hz (about twice the bilinear frequency of the first vertical mode) the disc's
    vertical spectrum over the last 0.3 s has a ½× line above 1× (measured 3.57), 1½× (0.195),
    2× (0.075) and 3× (0.043); its lateral spectrum (the linear side) has none."""
    result, u = loose_run
    assert K_SEAT * abs(u[2]) / PRELOAD > 10        # the seated solution would lift off
    late = result.t >= 0.3
    t = result.t[late]
    orders = (1.0, 0.5, 1.5, 2.0, 3.0, 1 / 3)
    one, half, one_half, two, three, third = order_amplitudes(t, result.q[late, 0], orders)
    assert half > 2.0 * one
    assert one_half > 0.1 * one and two > 0.04 * one and three > 0.02 * one
    assert third < 0.05 * one             # period two revolutions, not three
    lateral = order_amplitudes(t, result.q[late, 1], orders)
    assert np.all(lateral[1:] < 1e-3 * lateral[0])
    # period-two: the pedestal repeats after two revolutions, not after one
    x = result.q[late, 2]
    start = t[t <= t[-1] - 2 / SPEED_HZ]
    once, twice = (np.abs(np.interp(start + k / SPEED_HZ, t, x) - x[:start.size]).max()
                   for k in (1, 2))
    assert twice < 0.05 * once                   # measured 0.026 (still settling)
    frac = lift_off_fraction(result)
    assert 0.6 < frac < 0.9                      # measured 0.743


def test_above_lift_off_the_orbit_is_truncated_on_the_seat_side(loose_run):
    """The seat stops the pedestal's downward swing: its compression below the unloaded seat
    is the largest seat force over k_s (never more), and the pedestal rises above the seat
    more than twice as far as it sinks into it (measured 0.79 mm and 0.30 mm); the disc's
    vertical waveform is lopsided (it swings 1.7 times farther below its mean than above,
    thrown down when the pedestal lands) while its lateral one stays symmetric."""
    result, _ = loose_run
    late = result.t >= 0.3
    x = result.q[late, 2]
    seat = PRELOAD / K_SEAT
    assert result.max_penetration[0] == pytest.approx(result.max_normal_force[0] / K_SEAT,
                                                      rel=1e-9)
    assert seat - x.min() <= result.max_penetration[0] * (1 + 1e-9)
    assert x.max() - seat > 2 * (seat - x.min())
    y = result.q[late, 0]
    z = result.q[late, 1]
    assert (y.mean() - y.min()) > 1.4 * (y.max() - y.mean())
    assert (z.max() - z.mean()) == pytest.approx(z.mean() - z.min(), rel=0.01)


def test_above_lift_off_the_energy_ledger_closes(loose_run):
    """The books (the seat's spring energy, the dead load's work as drive work) close the
    ledger: what the penalty/trapezoid switching leaves is small against the external work."""
    result, _ = loose_run
    work = result.work_external[-1]
    assert result.status == 0
    assert abs(result.contact_algorithmic[-1]) < 1e-3 * work
    assert np.abs(result.contact_algorithmic).max() < 1e-3 * work
    # the dead load's work is -F_0 times the pedestal's rise since t = 0
    rise = result.q[:, 2] - result.q[0, 2]
    # (the books use the element's x, within the Newton tolerance of q at each step)
    np.testing.assert_allclose(result.work_drive, -PRELOAD * rise, rtol=0,
                               atol=PRELOAD * 1e-12 * result.n_steps)


def test_retaining_stiffness_lifts_in_status_3_and_closes_the_ledger():
    """With loose bolts (a retaining stiffness of 2e6 N/m once lifted) the lifted pedestal is
    engaged in status 3, never open; the lift-off fraction counts it and the ledger closes."""
    result, _ = pedestal_run(UNBALANCE, 0.2, loose_stiffness=2e6)
    open_, _, lifted = result.time_in_status[0]
    assert open_ == 0.0 and lifted > 0.1 * result.t_final
    assert lift_off_fraction(result) == pytest.approx(lifted / result.t_final, rel=1e-9)
    assert abs(result.contact_algorithmic[-1]) < 1e-3 * result.work_external[-1]
