"""Steps longer than the base step, sized by the local error estimate (``TimeGrid.dt_max``,
``Solver.step_error``): the estimate against its definition, the sensor stream filled in
within a long step, a linear oscillator against its closed form, convergence to the
base-step run as the tolerance shrinks, and an impact oscillator whose contacts the long
steps must neither miss nor integrate."""

from __future__ import annotations

import numpy as np
import pytest

from rubdiag._kernels import records
from rubdiag._kernels.recording import interpolate_sensors
from rubdiag._kernels.step_control import local_error
from rubdiag.simulation import (
    HarmonicForce,
    LinearSystem,
    PointContact,
    Recording,
    Solver,
    TimeGrid,
    simulate_system,
)

DT = 1e-5


def oscillator(f_n=60.0, zeta=0.02):
    """A 2-DOF (y, z) mass of 1 kg on springs of natural frequency ``f_n`` (Hz)."""
    k = (2 * np.pi * f_n) ** 2
    c = 2 * zeta * np.sqrt(k)
    return np.eye(2), c * np.eye(2), k * np.eye(2)


def run(force, contacts=None, duration=0.4, step_error=None, dt_max=None, fixed_step=False,
        progress=None, system=None):
    """The oscillator (or ``system``'s M, C, K) from rest, sampled at 10 kHz with both DOFs
    as sensors."""
    M, C, K = oscillator() if system is None else system
    return simulate_system(LinearSystem(M=M, C=C, K=K, force=force), contacts,
                           TimeGrid(duration=duration, dt=DT, output_dt=1e-4, dt_max=dt_max,
                                    fixed_step=fixed_step),
                           Recording(sensor_dofs=[0, 1], progress=progress),
                           solver=Solver(step_error=step_error))


def test_interpolation_is_exact_for_a_cubic_motion():
    """Cubic Hermite in q (from q, v) and in v (from v, a), linear in a: a cubic q(t) is
    reproduced at every sample inside the step."""
    h, n = 4e-5, 4
    t = np.linspace(0.0, h, n + 1)
    c = np.array([1e-4, 3.0, -2e4, 7e8])         # q = c0 + c1 t + c2 t² + c3 t³
    q = c[0] + c[1] * t + c[2] * t**2 + c[3] * t**3
    v = c[1] + 2 * c[2] * t + 3 * c[3] * t**2
    a = 2 * c[2] + 6 * c[3] * t
    sq, sv, sa = (np.zeros((n + 1, 1)) for _ in range(3))
    for out, exact in ((sq, q), (sv, v), (sa, a)):
        out[0, 0], out[n, 0] = exact[0], exact[n]
    interpolate_sensors(0, n, h, sq, sv, sa)
    np.testing.assert_allclose(sq[:, 0], q, rtol=1e-13, atol=0)
    np.testing.assert_allclose(sv[:, 0], v, rtol=1e-12, atol=0)
    np.testing.assert_allclose(sa[:, 0], a, rtol=1e-12, atol=0)


def test_error_estimate_is_zienkiewicz_xie():
    """``(β - 1/6) h² (a_{n+1} - a_n)`` with ``a_{n+1}`` from the Newmark relation, largest
    over the recorded DOFs, the sensor DOFs (through a recovery map) and the impact
    elements' local coordinates (not the others')."""
    rng = np.random.default_rng(3)
    n, h = 6, 3e-5
    for beta in (0.25, 0.3025):
        dq, v, a = rng.standard_normal((3, n)) * [[1e-6], [1e-2], [1e2]]
        a1 = dq / (beta * h * h) - v / (beta * h) - (1 / (2 * beta) - 1) * a
        e = (beta - 1 / 6) * h * h * (a1 - a)
        sen_map = rng.standard_normal((n, 2))
        el = np.zeros(2, records.ELEMENT)
        el["row"], el["n"], el["impact"] = [0, 2], [2, 2], [1, 0]
        rmap = np.array([[4, -1, 0], [5, -1, 0], [0, -1, 1], [1, -1, 1]])
        tmat = np.zeros((4, 8))
        tmat[:, :2] = [[1, 0], [0, 1], [1, 0], [0, 1]]
        expected = max(abs(e[[2]]).max(), abs(sen_map.T @ e).max(), abs(e[[4, 5]]).max())
        got = local_error(beta, h, dq, v, a, np.zeros(n), np.array([2]), np.zeros((0, 0)),
                           np.zeros(0, np.int64), sen_map, el, rmap, tmat, np.zeros((5, 4)))
        assert got == pytest.approx(expected, rel=1e-12)


def closed_form(t, f_n=60.0, zeta=0.02, f=40.0, amp=1.0):
    """y(t) of the 1-kg oscillator from rest under amp cos(2π f t): steady state plus the
    free transient that starts it at rest."""
    wn, w = 2 * np.pi * f_n, 2 * np.pi * f
    wd = wn * np.sqrt(1 - zeta**2)
    H = amp / (wn**2 - w**2 + 2j * zeta * wn * w)
    y0, v0 = -H.real, -(1j * w * H).real          # the transient cancels the steady state
    s = zeta * wn
    free = np.exp(-s * t) * (y0 * np.cos(wd * t) + (v0 + s * y0) / wd * np.sin(wd * t))
    return (H * np.exp(1j * w * t)).real + free


def test_linear_oscillator_against_its_closed_form():
    """Long steps (here 40 µs, with 20 µs to reach the 100-µs samples) at a tolerance of
    1e-5: the sensor stream, filled in between step ends, stays within 0.5 % of the
    amplitude of the closed form, as the base-step run does; and the recorded samples are
    step ends, equal to the sensor stream's samples at the same times."""
    force = HarmonicForce([0], [1.0], 2 * np.pi * 40.0)
    base = run(force)
    long = run(force, step_error=1e-5, dt_max=4 * DT)
    assert long.steps_per_level[0] > 0.6 * long.n_steps       # mostly 40-µs steps
    assert long.n_steps < 0.4 * base.n_steps
    t = np.arange(long.sensor_q.shape[0]) * long.sensor_dt
    exact = closed_form(t)
    scale = np.abs(exact).max()
    err_long = np.abs(long.sensor_q[:, 0] - exact).max() / scale
    err_base = np.abs(base.sensor_q[:, 0] - exact).max() / scale
    assert err_base < 1e-3
    assert err_long < 5e-3
    every = round(long.output_dt / long.sensor_dt)
    np.testing.assert_array_equal(long.q[:, 0], long.sensor_q[::every, 0])


def test_converges_to_the_base_step_run_as_the_tolerance_shrinks():
    """A higher-frequency response (a 300-Hz mode excited at start) makes the tolerance
    matter: the difference to the base-step run falls with it, and a tolerance too tight
    for any long step gives the base-step run itself, bit for bit."""
    M, C, K = oscillator()
    K = np.diag([K[0, 0], (2 * np.pi * 300.0) ** 2])
    force = HarmonicForce([0, 1], [1.0, 50.0], 2 * np.pi * 40.0)

    def go(tol):
        return run(force, duration=0.3, step_error=tol, dt_max=None if tol is None else 8 * DT,
                   system=(M, C, K))

    base = go(None)
    diffs = []
    for tol in (1e-3, 1e-4, 1e-5):
        r = go(tol)
        diffs.append(np.abs(r.sensor_q - base.sensor_q).max() / np.abs(base.sensor_q).max())
    assert diffs[0] > diffs[1] > diffs[2]
    tight = go(1e-14)
    assert tight.steps_per_level[:3].sum() == 0
    np.testing.assert_array_equal(tight.sensor_q, base.sensor_q)


def impact_oscillator(gap=1.0e-5):
    """The oscillator against a wall at ``gap`` along y (a point contact to ground)."""
    return [PointContact(dof_a=(0, 1), normal=(1.0, 0.0), tangent=(0.0, 1.0), gap=gap,
                         k_n=1e7, mu=0.0)]


def test_impacts_are_neither_missed_nor_taken_in_long_steps():
    """A periodic impact oscillator: the long-step run has the base-step run's episodes
    (start times within one base step, peak forces within 2 %); every closed step is at the
    base step or shorter; and long steps are taken between the impacts."""
    force = HarmonicForce([0], [1.0], 2 * np.pi * 40.0)
    contacts = impact_oscillator()
    base = run(force, contacts, duration=0.5)
    long = run(force, contacts, duration=0.5, step_error=1e-5, dt_max=4 * DT)
    eb, el = base.episodes, long.episodes
    assert eb.t_start.size >= 10 and el.t_start.size == eb.t_start.size
    np.testing.assert_allclose(el.t_start, eb.t_start, atol=DT, rtol=0)
    np.testing.assert_allclose(el.peak_normal_force, eb.peak_normal_force, rtol=0.02)
    assert long.steps_per_level[:2].sum() > 0.3 * long.n_steps
    # closed steps: their time is counted in time_in_status; at most one base step each
    closed_steps = int(np.sum(el.n_steps))
    closed_time = float(long.time_in_status[0, 1:].sum())
    assert closed_time <= closed_steps * DT * (1 + 1e-9)


def test_bad_settings_are_refused():
    force = HarmonicForce([0], [1.0], 2 * np.pi * 40.0)
    with pytest.raises(ValueError, match=r"^dt_max = 3e-05 is out of range \(allowed: dt"):
        run(force, step_error=1e-5, dt_max=3 * DT)
    with pytest.raises(ValueError, match=r"^dt_max = 4e-05 .*without a step_error"):
        run(force, dt_max=4 * DT)
    with pytest.raises(ValueError, match=r"^dt_max = 4e-05 .*fixed_step"):
        run(force, step_error=1e-5, dt_max=4 * DT, fixed_step=True)
    with pytest.raises(ValueError, match=r"^step_error = -1"):
        run(force, step_error=-1.0, dt_max=4 * DT)


def test_a_run_in_chunks_is_the_run_in_one_call():
    """A progress callback runs the kernel in chunks of about 1 % of the run, which end on
    any tick: long steps end at recorded samples, never at a chunk's end, so the bits are
    those of one call."""
    force = HarmonicForce([0], [1.0], 2 * np.pi * 40.0)
    contacts = impact_oscillator()
    one = run(force, contacts, duration=0.2, step_error=1e-5, dt_max=4 * DT)
    seen = []
    chunked = run(force, contacts, duration=0.2, step_error=1e-5, dt_max=4 * DT,
                  progress=lambda t, total: seen.append(t))
    assert len(seen) >= 50
    assert one.steps_per_level[0] > 0
    np.testing.assert_array_equal(chunked.sensor_q, one.sensor_q)
    np.testing.assert_array_equal(chunked.q, one.q)
    np.testing.assert_array_equal(chunked.steps_per_level, one.steps_per_level)


def test_a_run_up_with_long_steps_follows_the_base_step_run():
    """Along a speed profile the step operators change stretch by stretch: a long step
    ends at each stretch's end. A run-up from 30 to 50 Hz through the 60-Hz oscillator's
    flank: long steps taken, the sensor stream within 0.5 % of the 10-µs run's amplitude."""
    from rubdiag.simulation._speed_profile import SpeedProfile

    M, C, K = oscillator()
    w0 = 2 * np.pi * 30.0
    profile = SpeedProfile((0.0, 0.3), (w0, 2 * np.pi * 50.0))
    force = HarmonicForce([0, 1], [1.0, -1j], w0)

    def go(tol):
        return simulate_system(
            LinearSystem(M=M, C=C, K=K, force=force, omega=w0, gyroscopic=np.zeros((2, 2)),
                         speed_profile=profile),
            None, TimeGrid(duration=0.3, dt=DT, output_dt=1e-4,
                           dt_max=None if tol is None else 4 * DT),
            Recording(sensor_dofs=[0, 1]), solver=Solver(step_error=tol))

    base, long = go(None), go(1e-5)
    assert long.extra["speed_stretches"] > 1
    assert long.steps_per_level[:2].sum() > 0.5 * long.n_steps
    scale = np.abs(base.sensor_q).max()
    assert np.abs(long.sensor_q - base.sensor_q).max() < 5e-3 * scale
