"""Rotor-level checks against analytic values: Jeffcott rotor, overhung disc with
gyroscopic splitting, harmonic response, Rayleigh damping, and the paper rig."""

import dataclasses
import math

import numpy as np
import pytest

from rubdiag.assembly import assemble, rayleigh_coefficients
from rubdiag.assembly._elements import circular_section
from rubdiag.modal import (
    calibrate,
    campbell,
    critical_speeds,
    harmonic_response,
    modes,
    unbalance_response,
    with_rayleigh,
)
from rubdiag.model import Bearing, Damping, Disc, Loading, Material, Rig, Shaft, Unbalance

E, NU = 210e9, 0.3
G_SHEAR = E / (2 * (1 + NU))
RPM = math.pi / 30
LIGHT = Material(E, NU, 1e-6)        # a practically massless shaft
NO_DAMPING = Damping(0.0, 0.0, (1.0, 2.0))
RIGID = 1e13


def jeffcott(mass=5.0, L=0.6, d=0.012, n_el=8):
    shaft = Shaft((L / n_el,) * n_el, d, first_node=0)
    disc = Disc(n_el // 2, mass_kg=mass, polar_inertia_kg_m2=1e-3, diametral_inertia_kg_m2=5e-4)
    rig = Rig(shaft=shaft, bearings=(Bearing(0, RIGID, RIGID), Bearing(n_el, RIGID, RIGID)),
              discs=(disc,), material=LIGHT, damping=NO_DAMPING,
              loading=Loading((1e-4,)))
    area, inertia, _, kappa = circular_section(d, 0.0, NU)
    k = 1.0 / (L**3 / (48 * E * inertia) + L / (4 * kappa * G_SHEAR * area))
    return rig, k


def test_jeffcott_critical_speed():
    rig, k = jeffcott()
    crit = critical_speeds(assemble(rig), n=1)
    assert crit[0] == pytest.approx(math.sqrt(k / 5.0), rel=1e-3)


def test_jeffcott_unbalance_response_is_forward_circular_with_analytic_amplitude():
    rig, k = jeffcott()
    model = assemble(rig)
    w_n = math.sqrt(k / 5.0)
    for ratio in (0.5, 1.7):
        speed = ratio * w_n
        resp = harmonic_response(model, speed, rig.unbalance(1))
        a, b = resp.amplitude(4, "y"), resp.amplitude(4, "z")
        expected = 1e-4 * speed**2 / (k - 5.0 * speed**2)
        assert a.real == pytest.approx(expected, rel=2e-3)
        assert b == pytest.approx(-1j * a, rel=1e-9)         # z lags y by 90°: forward
        assert resp.orbit_semi_major(4) == pytest.approx(abs(expected), rel=2e-3)
        # the time history satisfies q(t + T/4) = rotation of q(t) by 90°
        q0 = resp.displacement(0.0)
        assert resp.velocity(0.0)[model.dofs.index(4, "y")] == pytest.approx(
            -speed * a.imag, rel=1e-9, abs=1e-15)
        assert q0[model.dofs.index(4, "y")] == pytest.approx(a.real)


def overhung(speed):
    """Disc at the tip of a massless cantilever: analytic forward/backward whirl."""
    L, d, m, ip, idm = 0.25, 0.015, 2.0, 4e-3, 2.5e-3
    n_el = 6
    # a clamp: two rigid bearings 20 mm apart on a very thick first element
    lengths = (0.02,) + (L / n_el,) * n_el
    rig = Rig(shaft=Shaft(lengths, (0.2,) + (d,) * n_el, first_node=0),
              bearings=(Bearing(0, RIGID, RIGID), Bearing(1, RIGID, RIGID)),
              discs=(Disc(n_el + 1, mass_kg=m, polar_inertia_kg_m2=ip,
                          diametral_inertia_kg_m2=idm),),
              material=LIGHT, damping=NO_DAMPING)
    area, inertia, _, kappa = circular_section(d, 0.0, NU)
    ei, ks = E * inertia, kappa * G_SHEAR * area
    flex = np.array([[L**3 / (3 * ei) + L / ks, L**2 / (2 * ei)],
                     [L**2 / (2 * ei), L / ei]])
    (k11, k12), (_, k22) = np.linalg.inv(flex)

    def whirl_frequencies(sign):
        # (k11 − mω²)(k22 − I_d ω² + sign·I_p Ω ω) − k12² = 0, sign +1 forward
        poly = np.polymul([-m, 0, k11], [-idm, sign * ip * speed, k22])
        poly = np.polyadd(poly, [-k12**2])
        roots = np.roots(poly)
        return np.sort(roots[(abs(roots.imag) < 1e-6) & (roots.real > 0)].real)

    return rig, whirl_frequencies(+1), whirl_frequencies(-1), (m, ip, idm, k11, k12, k22)


@pytest.mark.parametrize("speed_rpm", [0.0, 3000.0, 12000.0])
def test_overhung_disc_gyroscopic_split(speed_rpm):
    speed = speed_rpm * RPM
    rig, forward, backward, _ = overhung(speed)
    result = modes(assemble(rig), speed, n_modes=4, damped=False)
    freqs, whirl = result.damped_frequencies, result.whirl
    if speed == 0:
        np.testing.assert_allclose(np.sort(freqs), np.repeat(forward, 2), rtol=2e-3)
        return
    np.testing.assert_allclose(np.sort(freqs[whirl == "forward"]), forward, rtol=2e-3)
    np.testing.assert_allclose(np.sort(freqs[whirl == "backward"]), backward, rtol=2e-3)
    assert forward[1] > backward[1] * 1.05     # the conical mode splits


def test_overhung_forward_critical_speed_and_campbell_crossing():
    rig, _, _, (m, ip, idm, k11, k12, k22) = overhung(0.0)
    # synchronous forward whirl: (k11 − mΩ²)(k22 − (I_d − I_p)Ω²) − k12² = 0
    roots = np.roots(np.polyadd(np.polymul([-m, 0, k11], [-(idm - ip), 0, k22]), [-k12**2]))
    expected = np.sort(roots[(abs(roots.imag) < 1e-9) & (roots.real > 0)].real)
    model = assemble(rig)
    crit = critical_speeds(model, n=2)
    # I_p > I_d: the conical forward mode never crosses 1×, so only one critical speed
    # (besides the model's near-massless shaft modes, far above)
    assert len(expected) == 1
    assert len(crit) == 1 or crit[1] > 100 * crit[0]
    assert crit[0] == pytest.approx(expected[0], rel=2e-3)
    # the forward branch of the Campbell diagram crosses 1× at the same speed
    speeds = np.linspace(0.8, 1.2, 9) * crit[0]
    diagram = campbell(model, speeds, n_modes=4, damped=False)
    lowest_forward = np.array([f[w > 0].min() for f, w in
                               zip(diagram.frequencies, diagram.whirl_ratio, strict=True)])
    crossing = np.interp(0.0, (speeds - lowest_forward), speeds)   # increasing in speed
    assert crossing == pytest.approx(crit[0], rel=2e-3)


def test_rayleigh_coefficients_give_the_requested_ratios():
    w1, w2 = 1500 * RPM, 5700 * RPM
    alpha, beta = rayleigh_coefficients(w1, w2, 0.04, 0.04)
    assert alpha / (2 * w1) + beta * w1 / 2 == pytest.approx(0.04)
    assert alpha / (2 * w2) + beta * w2 / 2 == pytest.approx(0.04)
    assert alpha == pytest.approx(9.948, rel=1e-3) and beta == pytest.approx(1.061e-4, rel=1e-3)
    # the study's eqs (5)-(6) taken literally (speeds in rpm) overdamp the first mode
    n1, n2 = 1500.0, 5700.0
    a_paper = 60 * (n2 * 0.04 - n1 * 0.04) * n1 * n2 / (math.pi * (n2**2 - n1**2))
    b_paper = math.pi * (n2 * 0.04 - n1 * 0.04) / (15 * (n2**2 - n1**2))
    assert a_paper == pytest.approx(907, rel=1e-3) and b_paper == pytest.approx(1.16e-6, rel=1e-2)
    assert a_paper / (2 * w1) + b_paper * w1 / 2 > 2.5


def test_rayleigh_damping_ratios_of_paper_modes(paper_model):
    # ξ(ω) = α/2ω + βω/2 equals 0.04 at the criticals: modes near them carry ξ ≈ 0.04
    result = modes(paper_model, 0.0, n_modes=4)
    rotor = result.shaft_share > 0.5
    np.testing.assert_allclose(result.damping_ratios[rotor], 0.04, rtol=0.03)


def test_rayleigh_reference_speeds_default_to_the_critical_speeds(paper_rig, paper_model):
    # a rig without reference speeds: assembly leaves α, β open, the modal layer takes
    # the first two forward critical speeds, where the damping ratio is then ξ exactly
    rig = dataclasses.replace(paper_rig, damping=Damping(0.03, 0.05))
    model = assemble(rig)
    assert model.rayleigh is None
    with pytest.raises(ValueError, match="with_rayleigh"):
        _ = model.C
    damped = with_rayleigh(model)
    w1, w2 = critical_speeds(model, n=2)
    alpha, beta = damped.rayleigh
    assert alpha / (2 * w1) + beta * w1 / 2 == pytest.approx(0.03, rel=1e-9)
    assert alpha / (2 * w2) + beta * w2 / 2 == pytest.approx(0.05, rel=1e-9)
    assert with_rayleigh(paper_model) is paper_model   # reference speeds given: unchanged
    # modes() and the harmonic response fill it in themselves
    assert modes(model, 0.0, n_modes=2).damping_ratios[0] > 0


# --- the paper rig -------------------------------------------------------------------
def test_paper_rig_critical_speeds(paper_model):
    crit = critical_speeds(paper_model, n=2) / RPM
    np.testing.assert_allclose(crit, [1500.0, 5700.0], rtol=0.005)


@pytest.mark.parametrize("case,critical_index", [(1, 0), (2, 1)])
def test_paper_unbalance_peaks_and_rub(paper_rig, paper_model, case, critical_index):
    crit = critical_speeds(paper_model, n=2)
    speeds = np.linspace(300, 8000, 300) * RPM
    resp = unbalance_response(paper_model, speeds, paper_rig.unbalance(case))
    amp = np.abs(resp.amplitudes[:, 0])
    peak = resp.peak_speed()
    assert peak == pytest.approx(crit[critical_index], rel=0.02)
    other = crit[1 - critical_index]
    assert np.interp(other, speeds, amp) < 0.2 * amp.max()   # the other resonance is minor
    # at its running speed the disc-1 orbit exceeds both gaps: both rub
    at_speed = harmonic_response(paper_model, crit[critical_index], paper_rig.unbalance(case))
    assert at_speed.orbit_semi_major(11) > 2.3e-3 + 0.3e-3
    # mode shape: case 1 (first mode) moves both discs together, case 2 against each other
    y11, y19 = at_speed.amplitude(11, "y"), at_speed.amplitude(19, "y")
    same_sign = (y11 * np.conj(y19)).real > 0
    assert same_sign == (case == 1)


def test_unbalance_superposes_linearly(paper_model, paper_rig):
    speed = 3000 * RPM
    both = harmonic_response(paper_model, speed, paper_rig.unbalance(2)).amplitudes
    first = harmonic_response(paper_model, speed, Unbalance((1.56e-4, 0.0), (0.0, 0.0)))
    second = harmonic_response(paper_model, speed, Unbalance((0.0, 1.56e-4), (0.0, math.pi)))
    np.testing.assert_allclose(both, first.amplitudes + second.amplitudes, atol=1e-15)


def test_calibration_recovers_targets_from_a_perturbed_rig(paper_rig):
    lengths = list(paper_rig.shaft.element_lengths_m)
    perturbed = dataclasses.replace(paper_rig, shaft=dataclasses.replace(
        paper_rig.shaft, element_lengths_m=tuple(x * 1.06 for x in lengths)))
    assert critical_speeds(assemble(perturbed), n=1)[0] < 1450 * RPM
    result = calibrate(perturbed, (1500 * RPM, 5700 * RPM))
    np.testing.assert_allclose(np.array(result.speeds) / RPM, [1500, 5700], rtol=1e-4)
    np.testing.assert_allclose(critical_speeds(assemble(result.rig), n=2) / RPM,
                               [1500, 5700], rtol=1e-4)
    assert all(abs(s - 1 / 1.06) < 0.05 for s in result.scales)


def test_calibration_rejects_unknown_knob(paper_rig):
    with pytest.raises(ValueError, match="knob 'spin'"):
        calibrate(paper_rig, (100.0, 200.0), knobs=("spin",))


def test_critical_speeds_are_reproducible_to_the_last_bit(paper_rig):
    # run descriptions hold the computed speed: it must not depend on a random start vector
    a = critical_speeds(assemble(paper_rig), n=2)
    b = critical_speeds(assemble(paper_rig), n=2)
    assert a.tolist() == b.tolist()
