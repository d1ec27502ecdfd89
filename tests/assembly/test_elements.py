"""Element matrices against closed forms: beam statics, beam and ring frequencies,
classical matrices, symmetry, definiteness and rigid-body modes."""

import math

import numpy as np
import pytest
import scipy.linalg as sla

from rubdiag.assembly._elements import (
    circular_section,
    disc_matrices,
    frame_element,
    rectangular_section,
    shaft_element,
)

E, NU, RHO = 210e9, 0.3, 7850.0
G_SHEAR = E / (2 * (1 + NU))


def chain_shaft(n_el, length, d):
    """Global (M, K, G) of n_el equal shaft elements on nodes 0..n_el (4 DOF per node)."""
    n = 4 * (n_el + 1)
    M, K, G = np.zeros((n, n)), np.zeros((n, n)), np.zeros((n, n))
    me, ke, ge = shaft_element(length / n_el, d, 0.0, E, NU, RHO)
    for e in range(n_el):
        s = slice(4 * e, 4 * e + 8)
        M[s, s] += me
        K[s, s] += ke
        G[s, s] += ge
    return M, K, G


def chain_frame(n_el, length, width, height, angle):
    n = 3 * (n_el + 1)
    M, K = np.zeros((n, n)), np.zeros((n, n))
    me, ke = frame_element(length / n_el, angle, width, height, E, NU, RHO)
    for e in range(n_el):
        s = slice(3 * e, 3 * e + 6)
        M[s, s] += me
        K[s, s] += ke
    return M, K


def solve_static(K, fixed, load):
    free = np.setdiff1d(np.arange(K.shape[0]), fixed)
    u = np.zeros(K.shape[0])
    u[free] = np.linalg.solve(K[np.ix_(free, free)], load[free])
    return u


# --- statics -------------------------------------------------------------------------
@pytest.mark.parametrize("slender", [True, False])
@pytest.mark.parametrize("direction", ["y", "z"])
def test_shaft_cantilever_tip_deflection(slender, direction):
    L, d, P = (1.0, 0.01, 10.0) if slender else (0.05, 0.02, 1000.0)
    area, inertia, _, kappa = circular_section(d, 0.0, NU)
    expected = P * L**3 / (3 * E * inertia) + P * L / (kappa * G_SHEAR * area)
    _, K, _ = chain_shaft(4, L, d)
    load = np.zeros(K.shape[0])
    tip = 4 * 4 + (0 if direction == "y" else 1)
    load[tip] = P
    u = solve_static(K, fixed=[0, 1, 2, 3], load=load)
    assert u[tip] == pytest.approx(expected, rel=1e-9)
    if slender:   # the Euler-Bernoulli limit
        assert u[tip] == pytest.approx(P * L**3 / (3 * E * inertia), rel=1e-3)
    else:         # shear deformation matters for a stubby beam
        assert u[tip] > 1.05 * P * L**3 / (3 * E * inertia)
    # slope at the tip: θ_z = du_y/dx = PL²/2EI, θ_y = −du_z/dx
    slope = P * L**2 / (2 * E * inertia)
    if direction == "y":
        assert u[4 * 4 + 3] == pytest.approx(slope, rel=1e-9)
    else:
        assert u[4 * 4 + 2] == pytest.approx(-slope, rel=1e-9)


@pytest.mark.parametrize("slender", [True, False])
def test_shaft_simply_supported_central_load(slender):
    L, d, P = (1.0, 0.01, 10.0) if slender else (0.06, 0.02, 1000.0)
    area, inertia, _, kappa = circular_section(d, 0.0, NU)
    expected = P * L**3 / (48 * E * inertia) + P * L / (4 * kappa * G_SHEAR * area)
    _, K, _ = chain_shaft(4, L, d)
    load = np.zeros(K.shape[0])
    load[4 * 2] = P
    u = solve_static(K, fixed=[0, 1, 16, 17], load=load)
    assert u[8] == pytest.approx(expected, rel=1e-9)


@pytest.mark.parametrize("angle", [0.0, 0.3, math.pi / 2, 2.5])
@pytest.mark.parametrize("slender", [True, False])
def test_frame_cantilever_tip_deflection_any_angle(angle, slender):
    L, w, h, P = (0.04, 0.015, 0.002, 1.0) if slender else (0.01, 0.015, 0.005, 100.0)
    area, inertia, kappa = rectangular_section(w, h, NU)
    _, K = chain_frame(4, L, w, h, angle)
    transverse = np.array([-math.sin(angle), math.cos(angle)])
    axial = np.array([math.cos(angle), math.sin(angle)])
    for direction, expected in (
        (transverse, P * L**3 / (3 * E * inertia) + P * L / (kappa * G_SHEAR * area)),
        (axial, P * L / (E * area)),
    ):
        load = np.zeros(K.shape[0])
        load[12:14] = P * direction
        u = solve_static(K, fixed=[0, 1, 2], load=load)
        assert u[12:14] @ direction == pytest.approx(expected, rel=1e-9)


# --- closed-form matrices --------------------------------------------------------------
def test_shaft_stiffness_equals_classical_timoshenko_matrix():
    L, d = 0.03, 0.012
    area, inertia, _, kappa = circular_section(d, 0.0, NU)
    phi = 12 * E * inertia / (kappa * G_SHEAR * area * L**2)
    k = E * inertia / (L**3 * (1 + phi)) * np.array([
        [12, 6 * L, -12, 6 * L],
        [6 * L, (4 + phi) * L**2, -6 * L, (2 - phi) * L**2],
        [-12, -6 * L, 12, -6 * L],
        [6 * L, (2 - phi) * L**2, -6 * L, (4 + phi) * L**2]])
    _, K, _ = shaft_element(L, d, 0.0, E, NU, RHO)
    xy = [0, 3, 4, 7]          # (u_y, θ_z): θ_z = du_y/dx
    np.testing.assert_allclose(K[np.ix_(xy, xy)], k, rtol=1e-10, atol=1e-6 * k.max())
    xz = [1, 2, 5, 6]          # (u_z, θ_y): θ_y = −du_z/dx flips the coupling signs
    s = np.diag([1, -1, 1, -1])
    np.testing.assert_allclose(K[np.ix_(xz, xz)], s @ k @ s, rtol=1e-10, atol=1e-6 * k.max())
    assert np.allclose(K[np.ix_(xy, xz)], 0.0)   # the planes are uncoupled in K


def test_shaft_mass_equals_classical_timoshenko_matrices():
    # Friswell et al., Dynamics of Rotating Machines (2010), eq. (5.94)-(5.95)
    L, d = 0.03, 0.012
    area, inertia, _, kappa = circular_section(d, 0.0, NU)
    f = 12 * E * inertia / (kappa * G_SHEAR * area * L**2)
    a = RHO * area * L / (840 * (1 + f) ** 2)
    m1, m2 = 312 + 588 * f + 280 * f**2, (44 + 77 * f + 35 * f**2) * L
    m3, m4 = 108 + 252 * f + 140 * f**2, -(26 + 63 * f + 35 * f**2) * L
    m5, m6 = (8 + 14 * f + 7 * f**2) * L**2, -(6 + 14 * f + 7 * f**2) * L**2
    mt = a * np.array([[m1, m2, m3, m4], [m2, m5, -m4, m6],
                       [m3, -m4, m1, -m2], [m4, m6, -m2, m5]])
    b = RHO * inertia / (30 * (1 + f) ** 2 * L)
    r1, r2 = 36, (3 - 15 * f) * L
    r3, r4 = (4 + 5 * f + 10 * f**2) * L**2, (-1 - 5 * f + 5 * f**2) * L**2
    mr = b * np.array([[r1, r2, -r1, r2], [r2, r3, -r2, r4],
                       [-r1, -r2, r1, -r2], [r2, r4, -r2, r3]])
    M, _, G = shaft_element(L, d, 0.0, E, NU, RHO)
    xy = [0, 3, 4, 7]
    np.testing.assert_allclose(M[np.ix_(xy, xy)], mt + mr, rtol=1e-10, atol=1e-12)
    # gyroscopic: the polar inertia (2I) times the rotary-inertia matrix, coupling the planes
    xz = [1, 2, 5, 6]
    s = np.diag([1, -1, 1, -1])
    coupling = G[np.ix_(xz, xy)]
    np.testing.assert_allclose(coupling, -(s @ (2 * mr)), rtol=1e-10, atol=1e-12)


def test_euler_bernoulli_limit_gives_hermite_matrices():
    L, d = 1.0, 1e-3          # φ ≈ 3e-6
    area, _, _, _ = circular_section(d, 0.0, NU)
    M, _, _ = shaft_element(L, d, 0.0, E, NU, RHO)
    hermite = RHO * area * L / 420 * np.array([
        [156, 22 * L, 54, -13 * L], [22 * L, 4 * L**2, 13 * L, -3 * L**2],
        [54, 13 * L, 156, -22 * L], [-13 * L, -3 * L**2, -22 * L, 4 * L**2]])
    xy = [0, 3, 4, 7]
    np.testing.assert_allclose(M[np.ix_(xy, xy)], hermite, rtol=1e-4, atol=1e-6 * hermite.max())


def test_disc_matrices():
    M, G = disc_matrices(2.0, 0.3, 0.16)
    assert np.allclose(np.diag(M), [2.0, 2.0, 0.16, 0.16])
    assert G[2, 3] == 0.3 and G[3, 2] == -0.3 and np.count_nonzero(G) == 2


# --- structure of the matrices ---------------------------------------------------------
def test_element_symmetry_definiteness_and_rigid_modes():
    M, K, G = shaft_element(0.05, 0.01, 0.004, E, NU, RHO)
    np.testing.assert_allclose(M, M.T, atol=1e-15)
    np.testing.assert_allclose(K, K.T, rtol=1e-12, atol=1e-6)
    np.testing.assert_allclose(G, -G.T, atol=1e-15)
    assert np.linalg.eigvalsh(M).min() > 0
    k = np.linalg.eigvalsh(K)
    assert np.sum(k < 1e-9 * k.max()) == 4          # 2 translations + 2 rotations
    Mf, Kf = frame_element(0.02, 1.0, 0.015, 0.002, E, NU, RHO)
    kf = np.linalg.eigvalsh(Kf)
    assert np.linalg.eigvalsh(Mf).min() > 0
    assert np.sum(kf < 1e-9 * kf.max()) == 3        # 2 translations + in-plane rotation


def test_rigid_body_modes_of_free_beam_are_exactly_zero():
    M, K, _ = chain_shaft(10, 0.5, 0.01)
    w2 = sla.eigh(K, M, eigvals_only=True)
    assert np.sum(np.abs(w2) < 1e-6 * w2.max()) == 4
    assert np.sort(np.abs(w2))[4] > 1e3                 # the first elastic mode is clearly not
    # a rigid translation and a rigid rotation produce no elastic force
    x = np.linspace(0, 0.5, 11)
    rigid = np.zeros(M.shape[0])
    rigid[0::4] = 0.3 * x      # u_y = θ_z x
    rigid[3::4] = 0.3          # θ_z
    assert np.abs(K @ rigid).max() < 1e-6 * np.abs(K).max() * 1e-6


# --- natural frequencies ---------------------------------------------------------------
@pytest.mark.parametrize("slender", [True, False])
def test_simply_supported_shaft_frequencies(slender):
    L, d = (1.0, 0.01) if slender else (0.1, 0.02)     # L/d = 100 and 5
    area, inertia, _, kappa = circular_section(d, 0.0, NU)
    M, K, _ = chain_shaft(20, L, d)
    end = 4 * 20
    fixed = [0, 1, end, end + 1]         # pinned: translations held, rotations free
    free = np.setdiff1d(np.arange(M.shape[0]), fixed)
    w2 = sla.eigh(K[np.ix_(free, free)], M[np.ix_(free, free)], eigvals_only=True)
    numerical = np.sqrt(w2[::2][:3])    # each frequency appears in y and in z
    for n, w in enumerate(numerical, start=1):
        k = n * math.pi / L
        # Timoshenko: EI k⁴ − ρAω² − ρI(1 + E/κG) k²ω² + (ρ²I/κG) ω⁴ = 0
        a = RHO**2 * inertia / (kappa * G_SHEAR)
        b = -(RHO * area + RHO * inertia * (1 + E / (kappa * G_SHEAR)) * k**2)
        c = E * inertia * k**4
        exact = math.sqrt((-b - math.sqrt(b * b - 4 * a * c)) / (2 * a))
        assert w == pytest.approx(exact, rel=0.01)
        if slender:
            assert w == pytest.approx(k**2 * math.sqrt(E * inertia / (RHO * area)), rel=0.01)


@pytest.mark.parametrize("n", [2, 3])
def test_free_ring_in_plane_bending_frequencies(n):
    from rubdiag.assembly import assemble
    from rubdiag.model import Bearing, Casing, Rig, Shaft

    R, w, h = 0.08, 0.015, 0.002
    rig = Rig(shaft=Shaft((0.1,), 0.01), bearings=(Bearing(3, 1e6, 1e6),),
              casing=Casing(radius_m=R, axial_width_m=w, radial_height_m=h, n_elements=72,
                            support_k_y_n_m=0.0, support_k_z_n_m=0.0, support_c_y_ns_m=0.0,
                            support_c_z_ns_m=0.0))
    model = assemble(rig)
    idx = model.dofs.component("casing")
    K = model.K[np.ix_(idx, idx)].toarray()
    M = model.M[np.ix_(idx, idx)].toarray()
    w2 = np.sort(sla.eigh(K, M, eigvals_only=True))
    assert np.sum(np.abs(w2) < 1e-9 * w2.max()) == 3       # free ring: 3 rigid modes
    area, inertia, _ = rectangular_section(w, h, NU)
    exact = math.sqrt(E * inertia / (RHO * area * R**4)) * n * (n * n - 1) / math.sqrt(n * n + 1)
    numerical = np.sqrt(w2[3 + 2 * (n - 2)])               # modes come in pairs
    assert numerical == pytest.approx(exact, rel=0.01)


def test_assembled_paper_matrices_structure(paper_model):
    M, K, G = paper_model.M, paper_model.K, paper_model.G
    assert abs(M - M.T).max() <= 1e-12 * abs(M).max()
    assert abs(K - K.T).max() <= 1e-12 * abs(K).max()
    assert abs(G + G.T).max() == 0.0
    m = np.linalg.eigvalsh(M.toarray())
    k = sla.eigh(K.toarray(), M.toarray(), eigvals_only=True)
    assert m.min() > 0
    assert k.min() > 0         # bearings, disc ties and casing supports leave no rigid mode
    assert paper_model.n_dof == 412 and len(paper_model.dofs.labels) == 412
