"""Coupling misalignment: the loads of a misaligned double-joint spacer
coupling (rubdiag.simulation._misalignment), a model derived from Hooke's-joint kinematics.

The loads are checked against two joints written in closed form here (each joint's torque
ratio and secondary moment, the spacer's shear from its moment balance) at many shaft
angles — the module builds them from cross products instead — and the loads by order
against those; the 2× line of a run is checked against the closed-form harmonic response
of the linear system at 2Ω.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from rubdiag.assembly._dofs import DofMap
from rubdiag.assembly._elements import shaft_element
from rubdiag.simulation import LinearSystem, Recording, TimeGrid, simulate_system
from rubdiag.simulation._misalignment import Misalignment

NODES = (1, 2, 3, 4, 5)
DOFS = DofMap.build(NODES, 0, 0, 0)


def _joint(T, alpha, theta):
    """One Hooke's joint, in closed form (the module docstring's derivation): a drive
    whose axis is tilted by α towards y' from the driven axis passes, with torque T about
    its own axis, the torque T cos α / D about the driven axis and the transverse moment
    T sin α sin θ (sin θ, −cos θ) / D in (y', z'), D = 1 − sin²α cos²θ, θ the driven arm's
    angle from y'."""
    s = math.sin(alpha)
    D = 1.0 - s * s * np.cos(theta) ** 2
    return (T * math.cos(alpha) / D, T * s * np.sin(theta) ** 2 / D,
            -T * s * np.sin(theta) * np.cos(theta) / D)


def _closed_form(mis, phi):
    """The coupling's loads (F_y, F_z, M_y, M_z) on the rotor from two closed-form joints:
    A (drive → spacer, bend α₀ + γ towards p1) and B (spacer → rotor, bend γ towards −n),
    the spacer's torque from A, and the spacer's shear from its moment balance."""
    T, L = mis.drive_torque_n_m, mis.spacer_length_m
    g = math.asin(mis.offset_m / L)
    x = np.array([1.0, 0.0, 0.0])
    n = np.array([0.0, math.cos(mis.direction_rad), math.sin(mis.direction_rad)])
    e_s = math.cos(g) * x - math.sin(g) * n
    p1 = math.sin(g) * x + math.cos(g) * n         # A's bend direction, ⊥ e_s
    p2 = np.cross(e_s, p1)
    q1 = -n                                        # B's bend direction, ⊥ x
    q2 = np.cross(x, q1)
    v = np.column_stack([np.zeros_like(phi), np.cos(phi), np.sin(phi)])
    u = np.cross(e_s, v)
    u /= np.linalg.norm(u, axis=1)[:, None]        # the spacer's arm, at A and at B
    t_s, ma1, ma2 = _joint(T, mis.angle_rad + g, np.arctan2(u @ p2, u @ p1))
    t_r, mb1, mb2 = _joint(t_s, g, np.arctan2(v @ q2, v @ q1))
    m_a = t_s[:, None] * e_s + ma1[:, None] * p1 + ma2[:, None] * p2
    m_b = t_r[:, None] * x + mb1[:, None] * q1 + mb2[:, None] * q2
    force = -np.cross(e_s, m_a - m_b) / L
    return np.column_stack([force[:, 1], force[:, 2], m_b[:, 1], m_b[:, 2]])


def _evaluate(force, phi, n):
    """The load vector at shaft angles φ at constant speed (t = φ/Ω)."""
    return np.array([force.evaluate(p / force.omega[0], n) for p in phi])


CASES = [(0.01, 0.0, 0.3), (0.0, 2e-3, 0.0), (0.01, 2e-3, 1.0), (0.15, 0.02, -2.0)]


@pytest.mark.parametrize(("angle", "offset", "beta"), CASES)
def test_the_loads_are_the_two_closed_form_joints_at_every_shaft_angle(angle, offset, beta):
    mis = Misalignment(node=5, drive_torque_n_m=80.0, spacer_length_m=0.12, offset_m=offset,
                       angle_rad=angle, direction_rad=beta)
    phi = np.linspace(0.0, 2 * np.pi, 97)
    expected = _closed_form(mis, phi)
    # measured 4e-16 to 6e-15 of the largest load
    assert np.abs(mis.loads_at(phi) - expected).max() < 1e-12 * np.abs(expected).max()
    # the loads by order rebuild them but for the orders left out (6, 8, ...): ~r² of the
    # 2× line, r = tan²(α/2) of the larger joint angle
    force = mis.forces(DOFS, 150.0)
    got = _evaluate(force, phi, DOFS.n_dof)
    cols = [DOFS.index(5, d) for d in ("y", "z", "ry", "rz")]
    r = math.tan((angle + math.asin(offset / 0.12)) / 2) ** 2
    line_2x = np.abs(mis.lines()[2]).max()
    # measured 6e-10, 1e-14, 1.2e-8, 3.5e-4 of the 2× line (the last at r = 0.025)
    assert np.abs(got[:, cols] - expected).max() <= (2 * r * r + 1e-12) * line_2x
    assert np.abs(np.delete(got, cols, axis=1)).max() == 0.0


def test_pure_angular_misalignment_is_a_shear_force_pure_offset_a_moment():
    """δ = 0: joint B is straight, so the rotor gets no bending moment, only the shear
    that joint A's secondary moment puts through the spacer, ≈ Tα₀/(2L) static and at 2×.
    α₀ = 0 (the Z-shaped spacer): the two joints' secondary moments are equal and the
    spacer passes no shear; the rotor gets joint B's moment, ≈ Tγ/2 static and at 2×."""
    T, L = 80.0, 0.12
    angular = Misalignment(node=5, drive_torque_n_m=T, spacer_length_m=L, angle_rad=0.01)
    lines = angular.lines()
    assert np.abs(lines[0][2:]).max() < 1e-15 * T and np.abs(lines[2][2:]).max() < 1e-15 * T
    assert np.abs(lines[2][:2]) == pytest.approx([T * 0.01 / (2 * L)] * 2, rel=1e-4)
    offset = Misalignment(node=5, drive_torque_n_m=T, spacer_length_m=L, offset_m=2e-3)
    lines = offset.lines()
    gamma = math.asin(2e-3 / L)
    assert np.abs(lines[2][:2]).max() < 1e-12 * T
    assert np.abs(lines[2][2:]) == pytest.approx([T * gamma / 2] * 2, rel=1e-4)
    # T tan(γ/2) for a steady torque; the spacer's torque beats at 2× (joint A) and its
    # product with B's 2× adds ~γ²/4 (measured 7e-5)
    assert abs(lines[0][2]) == pytest.approx(T * math.tan(gamma / 2), rel=2e-4)


def test_the_lines_static_2x_dominant_then_1x_3x_4x():
    mis = Misalignment(node=5, drive_torque_n_m=50.0, spacer_length_m=0.1, offset_m=5e-4,
                       angle_rad=1e-3, ratio_1x=0.4, ratio_3x=0.15)
    force = mis.forces(DOFS, 100.0)
    assert set(force.law) == {"constant"}
    size = {int(k): np.abs(force.amplitudes[force.order == k]).max()
            for k in np.unique(force.order)}
    assert sorted(size) == [0, 1, 2, 3, 4]
    assert size[2] > size[1] > size[3] > size[4]
    assert size[1] == pytest.approx(0.4 * size[2], rel=1e-14)
    assert size[3] == pytest.approx(0.15 * size[2], rel=1e-14)
    # 4× is r ≈ α²/4 of 2×, α = 6 mrad the larger joint angle
    assert size[4] < 1e-4 * size[2]
    # the derived model alone has no odd lines
    plain = Misalignment(node=5, drive_torque_n_m=50.0, spacer_length_m=0.1, offset_m=5e-4)
    assert sorted(set(plain.forces(DOFS, 100.0).order.tolist())) == [0.0, 2.0, 4.0]


@pytest.mark.parametrize("angle", [0.0, 2e-3])
def test_the_2x_grows_linearly_with_the_offset(angle):
    """2× scales with T × (joint angles), γ = asin(δ/L): doubling a small offset doubles
    the 2× added by the offset (to (δ/L)² = 6e-5 at the largest; measured 5.6e-5)."""
    offsets = np.array([0.0, 1e-4, 2e-4, 4e-4, 8e-4])
    line = np.array([np.abs(Misalignment(node=5, drive_torque_n_m=30.0, spacer_length_m=0.1,
                                         offset_m=d, angle_rad=angle).lines().get(
                                             2, np.zeros(4))) for d in offsets])
    moment = line[:, 2]                 # joint B's 2× moment: T γ / 2 with any α₀
    assert np.allclose(moment[1:], 30.0 * np.arcsin(offsets[1:] / 0.1) / 2, rtol=1e-4)
    assert np.allclose(moment[2:] / moment[1:-1], 2.0, rtol=1e-4)
    assert np.all(np.diff(line.max(axis=1)) > 0)
    # no torque, no misalignment: no load
    assert Misalignment(node=5, drive_torque_n_m=0.0, spacer_length_m=0.1, offset_m=1e-3) \
        .forces(DOFS, 100.0).dofs.size == 0
    assert Misalignment(node=5, drive_torque_n_m=30.0, spacer_length_m=0.1) \
        .forces(DOFS, 100.0).dofs.size == 0


@pytest.mark.parametrize(("kwargs", "match"), [
    (dict(node=-1), r"misalignment.node = -1 is out of range"),
    (dict(node=2.0), r"misalignment.node = 2.0 has the wrong type"),
    (dict(spacer_length_m=0.0), r"misalignment.spacer_length_m = 0.0 is out of range "
                                r"\(allowed: > 0 and <= 10 m\)"),
    (dict(offset_m=-1e-4), r"misalignment.offset_m = -0.0001 is out of range"),
    (dict(offset_m=0.03), r"misalignment.offset_m = 0.03 is out of range \(allowed: <= "
                          r"spacer_length_m / 4 = 0.025 m\)"),
    (dict(angle_rad=0.3), r"misalignment.angle_rad = 0.3 is out of range"),
    (dict(drive_torque_n_m=np.inf), r"misalignment.drive_torque_n_m = inf is out of range"),
    (dict(ratio_1x=1.0), r"misalignment.ratio_1x = 1.0 is out of range \(allowed: >= 0 and "
                         r"< 1\)"),
])
def test_bad_misalignments_are_refused(kwargs, match):
    args = dict(node=5, drive_torque_n_m=10.0, spacer_length_m=0.1) | kwargs
    with pytest.raises(ValueError, match=match):
        Misalignment(**args)


def test_a_node_the_model_lacks_and_a_bad_speed_are_refused():
    mis = Misalignment(node=9, drive_torque_n_m=10.0, spacer_length_m=0.1, angle_rad=1e-3)
    with pytest.raises(ValueError, match=r"misalignment.node = 9 is not a shaft node"):
        mis.forces(DOFS, 100.0)
    with pytest.raises(ValueError, match=r"speed_rad_s = 0.0 is out of range"):
        Misalignment(node=5, drive_torque_n_m=10.0, spacer_length_m=0.1).forces(DOFS, 0.0)


def _shaft():
    """A 0.4-m, 20-mm steel shaft of four Timoshenko elements on springs at both ends
    (1e6 N/m), Rayleigh damped: first bending-bounce mode near 1400 rad/s."""
    n = DOFS.n_dof
    M, K, G = np.zeros((n, n)), np.zeros((n, n)), np.zeros((n, n))
    me, ke, ge = shaft_element(0.1, 0.02, 0.0, 2.1e11, 0.3, 7850.0)
    for e in range(4):
        idx = [DOFS.index(NODES[e + j], d) for j in (0, 1) for d in ("y", "z", "ry", "rz")]
        M[np.ix_(idx, idx)] += me
        K[np.ix_(idx, idx)] += ke
        G[np.ix_(idx, idx)] += ge
    for node in (1, 5):
        for d in ("y", "z"):
            K[DOFS.index(node, d), DOFS.index(node, d)] += 1e6
    C = 2.0 * M + 2e-5 * K
    return M, C, K, G


def test_a_run_shows_2x_at_the_linear_response_to_the_2x_moment():
    """50 rev/s (modes at 1088 and 2352 rad/s): the probe (node 3, y and z) after 0.1 s,
    over 5 revolutions sampled at every step; its 2× line (a Fourier coefficient over
    whole periods) against the closed-form response (K − (2Ω)²M + i2Ω(C + ΩG))⁻¹ F₂."""
    M, C, K, G = _shaft()
    omega = 2 * np.pi * 50.0
    D = C + omega * G
    mis = Misalignment(node=5, drive_torque_n_m=200.0, spacer_length_m=0.1, offset_m=1e-3,
                       angle_rad=2e-3, direction_rad=0.4, ratio_1x=0.3, ratio_3x=0.1)
    force = mis.forces(DOFS, omega)
    n = DOFS.n_dof

    def harmonic(k):
        rows = force.order == k
        F = np.zeros(n, complex)
        np.add.at(F, force.dofs[rows], force.amplitudes[rows])
        w = k * omega
        return np.linalg.solve(K - w * w * M + 1j * w * D, F)

    lines = {k: harmonic(k) for k in (0, 1, 2, 3, 4)}
    q0 = sum(x.real for x in lines.values())
    v0 = sum((1j * k * omega * x).real for k, x in lines.items())
    dt = 1e-5
    res = simulate_system(LinearSystem(M=M, C=D, K=K, force=force, q0=q0, v0=v0), None,
                          TimeGrid(duration=0.2, dt=dt, fixed_step=True))
    probe = [DOFS.index(3, "y"), DOFS.index(3, "z")]
    steps = round(5 * 0.02 / dt)       # 5 revolutions of 2000 steps
    t, q = res.t[-steps:], res.q[-steps:, probe]
    measured = {k: 2.0 / steps * (q * np.exp(-1j * k * omega * t)[:, None]).sum(axis=0)
                for k in (1, 2, 3, 4)}
    predicted = lines[2][probe]
    # measured 2.9e-6 of the 7.1-µm line: the trapezoidal rule's period error at 2Ω,
    # (2Ωh)²/12 = 3e-6
    assert np.abs(measured[2] - predicted).max() < 1e-4 * np.abs(predicted).max()
    # every line is the linear response to its own term (the 3× is close to the 1088-rad/s
    # mode: amplified 4×, it passes the 1×), and 2× dominates the spectrum
    for k in (1, 3, 4):
        assert np.abs(measured[k] - lines[k][probe]).max() < 1e-4 * np.abs(predicted).max()
    size = {k: np.abs(v).max() for k, v in measured.items()}
    assert size[2] > 3 * max(size[1], size[3], size[4])
    # the static loads (preload) set the mean deflection
    mean = q.mean(axis=0)
    assert np.abs(mean - lines[0][probe].real).max() < 1e-4 * np.abs(lines[0][probe]).max()


def test_on_the_paper_rig_the_2x_at_the_discs_is_the_linear_response():
    """The study's rig (its coupling, left out of the model, sits before shaft node 3) at
    1500 rpm with a misaligned coupling at node 3: 0.1 s, and the 2× line of both discs
    (nodes 11 and 19) over the last two revolutions against the closed-form response."""
    import scipy.sparse.linalg as spla

    import rubdiag
    from rubdiag.simulation._rig_cache import damped_model

    model = damped_model(rubdiag.paper_rig())
    omega = 1500.0 * np.pi / 30.0
    D = (model.C + omega * model.G).tocsc()
    mis = Misalignment(node=3, drive_torque_n_m=100.0, spacer_length_m=0.1, offset_m=5e-4,
                       angle_rad=1e-3)
    force = mis.forces(model, omega)
    n = model.n_dof

    def harmonic(k):
        rows = force.order == k
        F = np.zeros(n, complex)
        np.add.at(F, force.dofs[rows], force.amplitudes[rows])
        w = k * omega
        return spla.spsolve((model.K - w * w * model.M + 1j * w * D).tocsc(), F)

    lines = {k: harmonic(k) for k in (0, 2, 4)}
    q0 = sum(x.real for x in lines.values())
    v0 = sum((1j * k * omega * x).real for k, x in lines.items())
    probe = [model.dofs.index(node, d) for node in (11, 19) for d in ("y", "z")]
    dt = 1e-5
    res = simulate_system(LinearSystem(M=model.M, C=D, K=model.K, force=force, q0=q0, v0=v0),
                          None, TimeGrid(duration=0.1, dt=dt, fixed_step=True),
                          Recording(record_dofs=probe))
    steps = round(2 * 0.04 / dt)          # two revolutions at 25 rev/s
    t, q = res.t[-steps:], res.q[-steps:]
    measured = 2.0 / steps * (q * np.exp(-2j * omega * t)[:, None]).sum(axis=0)
    predicted = lines[2][probe]
    assert np.abs(predicted).max() > 1e-8
    # measured 1.6e-6 of the 2× lines (9.4 µm at disc 11, 22.6 µm at disc 19)
    assert np.abs(measured - predicted).max() < 1e-4 * np.abs(predicted).max()
