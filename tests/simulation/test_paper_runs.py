"""Rig-level simulation: the paper rig's two cases, the run description, result files,
the linear limit, a shaft-stator rub and failures that keep what was computed."""

import dataclasses
import math
import pickle

import numpy as np
import pytest

from rubdiag.assembly import assemble
from rubdiag.modal import harmonic_response
from rubdiag.model import Bearing, Disc, Loading, Material, Rig, Shaft, StatorContact
from rubdiag.simulation import Run, SimulationDiverged, load_result, simulate

DURATION, DISCARD = 1.0, 0.3


@pytest.fixture(scope="module")
def case_runs():
    return {case: simulate(Run.paper_case(case, 2.3, duration_s=DURATION, discard_s=DISCARD))
            for case in (1, 2)}


def test_both_cases_rub_and_case2_is_far_more_severe(case_runs):
    s1, s2 = case_runs[1].summary(), case_runs[2].summary()
    for s in (s1, s2):
        assert s["status"] == 0
        assert s["n_episodes"] > 3 and s["contact1_max_force_n"] > 20.0
    assert s2["contact1_max_force_n"] > 3.0 * s1["contact1_max_force_n"]
    assert s2["casing_max_y_m"] > 2.5 * s1["casing_max_y_m"]
    assert s2["max_contact_force_n"] > 3.0 * s1["max_contact_force_n"]
    # the casing limits the rotor: below the linear orbit (3.0 / 2.7 mm), near the gap
    assert 1.5e-3 < s1["shaft_max_y_m"] < 2.9e-3
    assert 1.5e-3 < s2["shaft_max_y_m"] < 2.7e-3


def test_contact_law_holds_on_the_paper_rig(case_runs):
    for result in case_runs.values():
        sys = result.system
        law = result.run.contact_law
        assert sys.max_cone_excess <= 1e-9 * max(1.0, sys.max_normal_force.max())
        open_ = sys.contact_status == 1
        assert np.all(sys.contact_fn[open_] == 0.0)
        closed = ~open_
        assert np.all(np.abs(sys.contact_ft[closed]) <= law.friction_coefficient
                      * sys.contact_fn[closed] * (1 + 1e-9) + 1e-9)
        # pure penalty: the penetration is F_N / k_N
        assert sys.max_penetration.max() == pytest.approx(
            sys.max_normal_force.max() / law.normal_stiffness_n_m, rel=1e-6)
        assert np.all(np.diff(sys.dissipated_friction) >= -1e-12)
        # the event log agrees with the sampled status: every closed sample lies in an episode
        ep = sys.episodes
        t_closed = result.t[closed[:, 0]]
        starts, ends = ep.t_start[ep.element == 1], ep.t_end[ep.element == 1]
        inside = [(np.any((starts <= t + 1e-12) & (ends >= t - 1e-12))) for t in t_closed]
        assert all(inside)


def test_energy_balance_closes_on_the_paper_rig(case_runs):
    # the ledger (kinetic + strain + damping + friction − external work) leaves only the
    # contact's algorithmic energy (penalty contact under Newmark is not exactly energy
    # conserving): that identity to round-off, and that energy within 1e-3 of the largest
    # external work at every sample (measured, 1 s runs: case 1 1.9e-4, case 2 9.9e-4)
    for result in case_runs.values():
        sys = result.system
        scale = np.abs(sys.work_external).max()
        residual = sys.energy_balance_residual
        np.testing.assert_allclose(residual, sys.contact_algorithmic, rtol=0, atol=1e-9 * scale)
        assert np.abs(residual).max() <= 1e-3 * scale


def test_result_file_round_trip(case_runs, tmp_path):
    result = case_runs[1]
    path = result.save(tmp_path / "run")
    assert path.suffix == ".npz" and not list(tmp_path.glob("*.tmp*"))
    back = load_result(path)
    assert back.run == result.run
    assert back.points == result.points and back.version == result.version
    np.testing.assert_array_equal(back.system.q, result.system.q)
    np.testing.assert_array_equal(back.system.contact_status, result.system.contact_status)
    for log in ("episodes", "status_segments"):
        a, b = getattr(back.system, log), getattr(result.system, log)
        for name in ("element", "t_start", "t_end"):
            np.testing.assert_array_equal(getattr(a, name), getattr(b, name))
    assert back.summary() == result.summary()


def test_format_1_files_are_refused_by_name(case_runs, tmp_path):
    """Format 1 numbered contact elements from 0 and had no per-step status log: such a
    file (or one without a format version, which format 1 wrote) is refused, naming its
    format and what to do."""
    import json

    path = case_runs[1].save(tmp_path / "v2.npz")
    with np.load(path) as archive:
        entries = {k: archive[k] for k in archive.files}
    meta = json.loads(str(entries["meta"]))
    for name, version in (("v1", {"format_version": 1}), ("none", {})):
        old = {k: v for k, v in meta.items() if k != "format_version"} | version
        np.savez_compressed(tmp_path / f"{name}.npz",
                            **(entries | {"meta": np.array(json.dumps(old))}))
        with pytest.raises(ValueError, match=rf"{name}\.npz: result format 1 is older than "
                           r"this rubdiag reads \(2.*simulate the run again"):
            load_result(tmp_path / f"{name}.npz")
    assert load_result(path).summary() == case_runs[1].summary()


@pytest.mark.filterwarnings("ignore::rubdiag.simulation.GapRampInWindow")   # no features here
def test_a_run_is_a_pure_function_of_its_picklable_description():
    run = Run.paper_case(2, 1.9, duration_s=0.05, discard_s=0.0, gap_ramp_s=0.01)
    again = pickle.loads(pickle.dumps(run))
    assert again == run
    a, b = simulate(run), simulate(again)
    np.testing.assert_array_equal(a.system.q, b.system.q)
    np.testing.assert_array_equal(a.system.contact_fn, b.system.contact_fn)


def test_without_contact_the_response_is_the_harmonic_solution(paper_rig):
    rig = dataclasses.replace(paper_rig, contact=None)
    speed = 1200 * math.pi / 30
    run = Run(rig=rig, speed_rad_s=speed, unbalance=rig.unbalance(1), duration_s=0.2,
              discard_s=0.0)
    result = simulate(run)
    linear = harmonic_response(assemble(rig), speed, rig.unbalance(1))
    expected = np.real(linear.amplitude(11, "y") * np.exp(1j * speed * result.t))
    y = result.displacement("shaft 11 y")
    assert np.abs(y - expected).max() < 0.005 * np.abs(expected).max()


def test_shaft_stator_rub_limits_the_orbit():
    """A Jeffcott-like rotor without blades rubs on a seal: the orbit stays near the
    clearance instead of reaching its linear amplitude."""
    n_el = 8
    rig = Rig(shaft=Shaft((0.075,) * n_el, 0.012, first_node=0),
              bearings=(Bearing(0, 1e9, 1e9, 100.0, 100.0), Bearing(n_el, 1e9, 1e9, 100.0, 100.0)),
              discs=(Disc(4, 0.06, 0.02),), material=Material(),
              loading=Loading((2e-4,)),
              stator_contacts=(StatorContact(node=4, clearance_m=0.3e-3, stiffness_n_m=2e7,
                                             friction_coefficient=0.1),))
    model = assemble(rig)
    from rubdiag.modal import critical_speeds

    speed = 0.95 * critical_speeds(model, n=1)[0]
    linear = harmonic_response(model, speed, rig.unbalance(1)).orbit_semi_major(4)
    assert linear > 2 * 0.3e-3
    result = simulate(Run(rig=rig, speed_rad_s=speed, unbalance=rig.unbalance(1),
                          duration_s=0.5, discard_s=0.2, gap_ramp_s=0.05))
    y = result.displacement("shaft 4 y", windowed=True)
    z = result.displacement("shaft 4 z", windowed=True)
    radius = np.hypot(y, z)
    assert result.success and len(result.window_episodes()) > 0
    assert radius.max() < 0.6 * linear
    assert radius.max() > 0.3e-3          # it does reach the seal


@pytest.mark.parametrize("kwargs,match", [
    (dict(gap_mm=-0.1), r"gap_mm = -0.1 is out of range"),
    (dict(gap_mm=2.3, dt_s=0.0), r"dt_s = 0.0 is out of range \(allowed: > 0\)"),
    (dict(gap_mm=2.3, dt_s=1e-5, dt_min_s=2e-5), r"dt_min_s = 2e-05 is out of range"),
    (dict(gap_mm=2.3, duration_s=1e-6), r"duration_s = 1e-06 is out of range"),
    (dict(gap_mm=float("nan")), r"gap_mm = nan"),
    (dict(gap_mm=2.3, speed_rpm=float("nan")), r"speed_rpm = nan"),
    (dict(gap_mm=2.3, output_rate_hz=3000.0), r"output_rate_hz = 3000.0 is out of range"),
    (dict(gap_mm=2.3, discard_s=3.0), r"discard_s = 3.0 is out of range"),
])
def test_bad_run_input(kwargs, match):
    with pytest.raises(ValueError, match=match):
        Run.paper_case(1, **kwargs)


def test_negative_friction_is_refused():
    from rubdiag.model import BladeContact

    with pytest.raises(ValueError, match=r"friction_coefficient = -0\.2"):
        BladeContact(friction_coefficient=-0.2)


def test_failure_says_when_and_where_and_keeps_the_partial_result(tmp_path):
    # fixed steps of 0.1 ms are too coarse for the stick/slip iteration in case 2
    run = Run.paper_case(2, 1.9, duration_s=0.3, discard_s=0.1, dt_s=1e-4, fixed_step=True)
    with pytest.raises(SimulationDiverged, match=r"did not converge .* at t = .* s, contact "
                                                 r"element \d,") as info:
        simulate(run)
    partial = info.value.result
    assert partial.status == 1 and not partial.success
    assert 0.0 < partial.t[-1] < 0.3
    assert partial.system.q.shape[0] == partial.t.size
    assert np.all(np.isfinite(partial.system.q))
    back = load_result(partial.save(tmp_path / "partial.npz"))
    assert back.status == 1 and back.message == partial.message
    assert math.isfinite(back.system.failure_time)


@pytest.mark.filterwarnings("ignore::rubdiag.simulation.GapRampInWindow")   # no features here
def test_fixed_step_at_the_default_dt_gets_through_stick_slip_cycles():
    # the semi-smooth Newton iteration used to cycle between stick and slip here (t ≈ 16 ms)
    run = Run.paper_case(2, 1.9, duration_s=0.08, discard_s=0.0, fixed_step=True,
                         gap_ramp_s=0.05)
    result = simulate(run)
    assert result.success and result.system.n_steps == 8000
    assert len(result.system.episodes) > 0
    assert result.system.newton_iterations_max <= 25


def test_divergence_error_pickles_with_its_partial_result():
    run = Run.paper_case(2, 1.9, duration_s=0.05, discard_s=0.0, dt_s=1e-4, fixed_step=True,
                         gap_ramp_s=0.0)
    with pytest.raises(SimulationDiverged) as info:
        simulate(run)
    again = pickle.loads(pickle.dumps(info.value))
    assert str(again) == str(info.value)
    np.testing.assert_array_equal(again.result.system.q, info.value.result.system.q)
