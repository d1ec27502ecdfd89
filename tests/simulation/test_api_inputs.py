"""The simulation API refuses nonsense with a clear error and accepts numpy numbers."""

import warnings

import numpy as np
import pytest
from testsystems import tip_casing_system

from rubdiag import _check
from rubdiag.model import paper_rig
from rubdiag.simulation import GapRampInWindow, HarmonicForce, PointContact, Run, simulate


@pytest.mark.parametrize("run", ["x", None, 3.0])
def test_simulate_wants_a_run(run):
    with pytest.raises(TypeError, match=r"run = .* has the wrong type \(expected a Run"):
        simulate(run)


@pytest.mark.parametrize("case", ["1", 1.0, True])
def test_paper_case_number_has_a_type(case):
    with pytest.raises(TypeError, match=r"case = .* has the wrong type"):
        Run.paper_case(case, 2.0, speed_rpm=1500.0)


def test_numpy_scalars_are_numbers():
    run = Run.paper_case(np.int64(1), np.float32(2.3), speed_rpm=np.float64(1500.0),
                         duration_s=np.float32(0.5), discard_s=np.int64(0), gap_ramp_s=0)
    plain = Run.paper_case(1, float(np.float32(2.3)), speed_rpm=1500.0, duration_s=0.5,
                           discard_s=0, gap_ramp_s=0)
    assert run.gap_m == pytest.approx(plain.gap_m)
    assert run.speed_rad_s == plain.speed_rad_s


def test_messages_print_plain_numbers():
    with pytest.raises(ValueError) as info:
        Run.paper_case(1, np.float64(-1.0), speed_rpm=1500.0)
    assert "np." not in str(info.value) and "gap_mm = -1.0 is out of range" in str(info.value)
    assert _check.plain(np.float64(0.0)) == "0.0" and _check.plain(np.int64(3)) == "3"
    assert _check.plain(np.array([1, 2])) == "[1, 2]"
    assert _check.plain(0.1 + 0.2) == "0.3"


@pytest.mark.parametrize("dofs", [[1.0], np.array([2.5]), [True]])
def test_float_or_bool_dof_indices_are_refused(dofs):
    s = tip_casing_system(k_n=1e7, mu=0.3, gap=50e-6)
    with pytest.raises(TypeError, match="integer indices"):
        HarmonicForce(dofs, [1.0], s.speed)
    with pytest.raises(TypeError, match="integer indices"):
        PointContact(dof_a=dofs * 2, normal=(1.0, 0.0), tangent=(0.0, 1.0), gap=1e-4, k_n=1e7)


def test_a_gap_ramp_reaching_into_the_analysis_window_is_warned_about():
    with pytest.warns(GapRampInWindow, match="gap_ramp_s = 0.2 s is longer than discard_s"):
        Run.paper_case(1, 2.0, speed_rpm=1500.0, duration_s=1.0, discard_s=0.1,
                       gap_ramp_s=0.2)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        Run.paper_case(1, 2.0, speed_rpm=1500.0, duration_s=1.0, discard_s=0.3,
                       gap_ramp_s=0.2)
        # no contact, no ramp to warn about
        rig = paper_rig()
        Run(rig=rig.__class__(**{**rig.__dict__, "contact": None}), speed_rad_s=100.0,
            unbalance=rig.unbalance(1), duration_s=1.0, discard_s=0.0, gap_ramp_s=0.5)
