"""A reduction keeps named shaft nodes physical (for fault elements: a crack's element, a
misaligned coupling's node): their DOFs are boundary coordinates, where a Craig–Bampton
model's static compliance is exact."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse.linalg as spla

from rubdiag.assembly import assemble
from rubdiag.model import paper_rig
from rubdiag.reduce import Reduction, reduced_model

#: the constraint modes span every static boundary load: exact to round-off
STATIC_RTOL = 1e-8


def test_a_shaft_node_kept_is_physical_and_exact_in_statics():
    rig = paper_rig()
    model = assemble(rig)
    reduced = reduced_model(rig, Reduction(shaft_nodes=(5,)))
    dofs = [model.dofs.index(5, d) for d in ("y", "z", "ry", "rz")]
    index = reduced.basis.boundary_index(dofs)          # raises if they were not kept
    T = reduced.basis.T
    np.testing.assert_array_equal(T[dofs][:, index], np.eye(4))
    f = np.zeros(model.n_dof)
    f[dofs[0]], f[dofs[3]] = 100.0, 3.0                 # a force and a moment at node 5
    full = spla.spsolve(model.K.tocsc(), f)
    red = T @ np.linalg.solve(reduced.K, T.T @ f)
    scale = np.abs(full[dofs]).max()
    np.testing.assert_allclose(red[dofs], full[dofs], rtol=0, atol=STATIC_RTOL * scale)


def test_without_shaft_nodes_the_description_is_what_it_was():
    assert Reduction().description() == {"cutoff_hz": 2000.0, "tip_rotations": True}
    assert Reduction(shaft_nodes=[7, 5, 7]).description()["shaft_nodes"] == [5, 7]


def test_a_node_off_the_shaft_is_refused_by_name():
    with pytest.raises(ValueError, match=r"reduction\.shaft_nodes: 999"):
        reduced_model(paper_rig(), Reduction(shaft_nodes=(999,)))


def test_a_rig_without_contacts_reduces_about_its_fault_nodes():
    """No blade-casing contact (a run with faults only): the named nodes are the boundary;
    with nothing nonlinear at all the reduction says so by name."""
    import dataclasses

    rig = dataclasses.replace(paper_rig(), contact=None)
    model = assemble(rig)
    reduced = reduced_model(rig, Reduction(shaft_nodes=(10, 11), tip_rotations=False))
    expected = sorted(model.dofs.index(n, d) for n in (10, 11) for d in ("y", "z", "ry", "rz"))
    np.testing.assert_array_equal(reduced.basis.boundary, expected)
    with pytest.raises(ValueError, match="has no nonlinear element"):
        reduced_model(rig, Reduction(tip_rotations=False))
