"""The element seam: a kind added outside rubdiag, the element descriptions, and the call of
simulate_system on described objects (the deprecated Contacts arrays convert to them)."""

from __future__ import annotations

import dataclasses
from unittest import mock

import ground_spring_kind
import numpy as np
import pytest
import scipy.sparse as sp
from ground_spring_kind import GroundSpring
from testsystems import linear_response, tip_casing_system

from rubdiag._kernels import extend
from rubdiag.simulation import (
    AnnularContact,
    Contacts,
    HarmonicForce,
    LinearSystem,
    PointContact,
    Recording,
    Solver,
    TimeGrid,
    simulate_system,
)
from rubdiag.simulation import _system as system_module

#: the seam and K give the same discrete equations: they differ by round-off only
SEAM_RTOL = 1e-12


def chain(n=4, k=4e4, m=1.5, damping=0.8):
    """A chain of n masses on springs, the first tied to ground."""
    K = np.zeros((n, n))
    for i in range(n):
        K[i, i] += k
        if i + 1 < n:
            K[i, i] += k
            K[i + 1, i + 1] += 0.0
            K[i, i + 1] = K[i + 1, i] = -k
    M = np.eye(n) * m
    return M, damping * np.eye(n) + 1e-4 * K, K


@pytest.mark.parametrize("solver", ["sparse", "dense"])
def test_spring_and_dashpot_through_the_seam_equal_them_in_k_and_c(solver):
    """A kind defined only in the tests (tests/ground_spring_kind.py), velocity
    dependent through the Newmark relation, gives the run that the same spring in K and
    dashpot in C give, to round-off; its books close the energy ledger."""
    M, C, K = chain()
    dof, k, c = 2, 2.5e4, 3.0
    force = HarmonicForce([3], [5.0], 40.0)
    q0 = np.array([1e-4, -2e-4, 3e-4, 0.0])
    v0 = np.array([0.0, 1e-2, -2e-2, 5e-3])
    grid = TimeGrid(duration=0.2, dt=2e-4)
    in_k = K.copy()
    in_k[dof, dof] += k
    in_c = C.copy()
    in_c[dof, dof] += c
    reference = simulate_system(LinearSystem(M=M, C=in_c, K=in_k, force=force, q0=q0, v0=v0),
                                None, grid, solver=Solver(linear_solver=solver))
    seam = simulate_system(LinearSystem(M=M, C=C, K=K, force=force, q0=q0, v0=v0),
                           [GroundSpring(dof=dof, stiffness=k, damping=c)], grid,
                           solver=Solver(linear_solver=solver))
    scale = np.abs(reference.q).max()
    np.testing.assert_allclose(seam.q, reference.q, rtol=0, atol=SEAM_RTOL * scale)
    np.testing.assert_allclose(seam.v_final, reference.v_final, rtol=0,
                               atol=SEAM_RTOL * np.abs(reference.v_final).max())
    # the spring's energy is the seam's elastic energy, the dashpot's work its dissipation
    x = seam.q[:, dof]
    np.testing.assert_allclose(seam.contact_elastic, 0.5 * k * x**2, rtol=1e-12, atol=0)
    work = seam.work_external[-1]
    assert abs(seam.contact_algorithmic[-1]) < 1e-9 * work
    balance = (seam.kinetic + seam.strain + seam.contact_elastic + seam.dissipated_viscous
               + seam.dissipated_friction - seam.work_external - seam.work_drive)
    assert np.abs(balance - balance[0]).max() < 1e-9 * work
    assert seam.dissipated_friction[-1] > 0.01 * work     # the dashpot took its share


def test_extended_kernel_runs_the_builtin_kinds_bit_for_bit():
    """The kernel compiled with an extra kind gives a contact run the bits of the cached
    kernel: extending adds a kind, it changes none."""
    ts = tip_casing_system(gap=30e-6)
    u = linear_response(ts.M, ts.C, ts.K, ts.force)
    system = LinearSystem(M=ts.M, C=ts.C, K=ts.K, force=ts.force, q0=u.real,
                          v0=(1j * ts.speed * u).real, omega=ts.speed)
    grid = TimeGrid(duration=0.02, dt=1e-5)
    builtin = simulate_system(system, ts.contacts, grid)
    extended = extend.kernel_with((ground_spring_kind,))
    with mock.patch.object(system_module, "kernel_for", lambda elements: extended):
        other = simulate_system(system, ts.contacts, grid)
    assert builtin.max_normal_force.max() > 0
    for field in ("q", "contact_fn", "contact_ft", "contact_status", "dissipated_friction"):
        assert np.array_equal(getattr(builtin, field), getattr(other, field)), field


def test_kind_code_of_a_builtin_kind_is_refused():
    clash = mock.Mock(KIND=1, N_LOCAL=1, __name__="clash")
    with pytest.raises(ValueError, match=r"clash.KIND = 1 .*allowed: a code no other kind"):
        extend.kernel_with((clash,))


def test_deprecated_contacts_run_as_their_elements_bit_for_bit():
    """A Contacts warns that it is deprecated, and simulate_system runs it as the element
    descriptions it converts to: the same arrays, bit for bit."""
    ts = tip_casing_system(gap=30e-6)
    with pytest.warns(DeprecationWarning, match="Contacts is deprecated .*PointContact"):
        arrays = Contacts.point(ts.tip_dofs, ts.casing_dofs,
                                [c.normal for c in ts.contacts],
                                [c.tangent for c in ts.contacts], 30e-6, 1e7)
    u = linear_response(ts.M, ts.C, ts.K, ts.force)
    system = LinearSystem(M=ts.M, C=ts.C, K=ts.K, force=ts.force, q0=u.real,
                          v0=(1j * ts.speed * u).real, omega=ts.speed)
    grid = TimeGrid(duration=0.01, dt=1e-5, output_dt=1e-4)
    options = {"solver": Solver(gamma=0.6), "gap_ramp": (0.005, 60e-6)}
    old = simulate_system(system, arrays, grid, Recording(sensor_dofs=[0]), **options)
    new = simulate_system(system, ts.contacts, grid, Recording(sensor_dofs=[0]), **options)
    assert new.max_normal_force.max() > 0       # the contacts close
    for field in dataclasses.fields(old):
        a, b = getattr(old, field.name), getattr(new, field.name)
        if isinstance(a, np.ndarray):
            assert np.array_equal(a, b), field.name


def test_the_call_refuses_what_is_not_its_described_objects():
    ts = tip_casing_system()
    system = LinearSystem(M=ts.M, C=ts.C, K=ts.K)
    grid = TimeGrid(duration=0.01, dt=1e-5)
    with pytest.raises(ValueError, match=r"system = .*wrong type .*LinearSystem"):
        simulate_system(ts.M, ts.contacts, grid)
    with pytest.raises(ValueError, match=r"grid = .*wrong type .*TimeGrid"):
        simulate_system(system, ts.contacts, {"duration": 0.01, "dt": 1e-5})
    with pytest.raises(ValueError, match=r"outputs = .*wrong type .*Recording"):
        simulate_system(system, ts.contacts, grid, Solver())
    with pytest.raises(ValueError, match=r"solver = .*wrong type .*Solver"):
        simulate_system(system, ts.contacts, grid, solver=Recording())
    with pytest.raises(TypeError, match="positional"):
        simulate_system(system, ts.contacts, grid, Recording(), Solver())


@pytest.mark.filterwarnings("ignore::DeprecationWarning")
def test_contacts_convert_to_one_description_per_element_in_order():
    point = Contacts.point([[0, 1]], [[2, 3]], [[0.0, 1.0]], [[-1.0, 0.0]], 1e-4, 1e7, mu=0.2)
    ring = Contacts.annular([[4, 5]], 2e-4, 0.05, 3e7, mu=0.1, augmented=True, eps=1e-6)
    elements = (ring + point + ring).elements()
    assert [type(e) for e in elements] == [AnnularContact, PointContact, AnnularContact]
    assert elements[1] == PointContact(dof_a=(0, 1), dof_b=(2, 3), normal=(0.0, 1.0),
                                       tangent=(-1.0, 0.0), gap=1e-4, k_n=1e7, mu=0.2)
    assert elements[0].augmented and elements[0].eps == 1e-6 and elements[0].k_t == 3e7
    # B of the elements: the point contact's rows are its normal and tangent on a - b
    B = (point + ring).b_matrix(6)
    np.testing.assert_array_equal(B[:2, :4], [[0, 1, 0, -1], [-1, 0, 1, 0]])
    np.testing.assert_array_equal(B[2:, 4:], np.eye(2))


@pytest.mark.parametrize(("make", "message"), [
    (lambda: PointContact(dof_a=(0, 1), normal=(1.0, 0.0), tangent=(1.0, 0.0), gap=0.0,
                          k_n=1e6), "PointContact.normal/tangent"),
    (lambda: PointContact(dof_a=(0, 1), normal=(2.0, 0.0), tangent=(0.0, 1.0), gap=0.0,
                          k_n=1e6), "PointContact.normal"),
    (lambda: PointContact(dof_a=(0, 1), normal=(1.0, 0.0), tangent=(0.0, 1.0),
                          gap=float("nan"), k_n=1e6), "PointContact.gap"),
    (lambda: AnnularContact(dof_a=(0, 1), clearance=1e-4, k_n=0.0), "AnnularContact.k_n"),
    (lambda: AnnularContact(dof_a=(0, 1), clearance=1e-4, k_n=1e6, mu=-0.1),
     "AnnularContact.mu"),
    (lambda: AnnularContact(dof_a=(0, 1, 2), clearance=1e-4, k_n=1e6), "AnnularContact.dof_a"),
    (lambda: AnnularContact(dof_a=(0, 1), dof_b=(-2, 1), clearance=1e-4, k_n=1e6),
     "AnnularContact.dof_b"),
    (lambda: AnnularContact(dof_a=(0, 1), clearance=1e-4, k_n=1e6, augmented=True, eps=0.0),
     "AnnularContact.eps"),
])
def test_descriptions_refuse_bad_values_by_name(make, message):
    with pytest.raises(ValueError, match=message.replace(".", r"\.")):
        make()


def test_element_dofs_outside_the_system_are_refused():
    M, C, K = chain()
    with pytest.raises(ValueError, match=r"elements\[0\] DOFs"):
        simulate_system(LinearSystem(M=M, C=C, K=K), [GroundSpring(dof=9, stiffness=1.0)],
                        TimeGrid(duration=0.01, dt=1e-3))


def test_sparse_and_dense_matrices_give_the_same_run():
    """LinearSystem takes dense and sparse matrices alike."""
    M, C, K = chain()
    a = simulate_system(LinearSystem(M=M, C=C, K=K, q0=np.ones(4) * 1e-4), None,
                        TimeGrid(duration=0.01, dt=1e-3))
    b = simulate_system(LinearSystem(M=sp.csr_matrix(M), C=sp.csr_matrix(C),
                                     K=sp.csr_matrix(K), q0=np.ones(4) * 1e-4), None,
                        TimeGrid(duration=0.01, dt=1e-3))
    assert np.array_equal(a.q, b.q)
