"""Designs: the TOML as written, what each sampling method guarantees (grid counts,
Latin-hypercube and Sobol' strata, level shares), determinism, the resolved round trip,
what each factor does to the Run, and a one-line error for every kind of bad input.
Nothing here simulates."""

import dataclasses
import math
import pickle
import re

import numpy as np
import pytest

from rubdiag.dataset import Design, Factor, gap_ramps_s
from rubdiag.dataset import _design as design_module
from rubdiag.dataset import _expansion as expansion_module
from rubdiag.model import save_rig
from rubdiag.simulation import Run

# a design as a user writes it
ISSUE_TOML = """
[base]
rig = "paper"             # preset name or rig TOML path
duration_s = 2.3          # the analysis window (2 s) resolves the 2–5 Hz sidebands
discard_s = 0.3

[sampling]
method = "lhs"            # "grid" | "lhs" | "sobol" | "random" (scipy.stats.qmc)
n = 200                   # ignored by "grid" (product of the levels)
seed = 7
replicates = 1            # start histories per design point (as paper.ensemble)

[factors]
case = [1, 2]                              # unbalance pattern: levels
speed_ratio = {low = 0.8, high = 1.2}      # speed / that case's forward critical speed
gap_mm = {low = 0.5, high = 4.0}           # wide enough that some runs do not rub
mu = {low = 0.1, high = 0.5}
unbalance_scale = {low = 0.6, high = 1.4}  # times the study's magnitudes
"""

# reference speeds given, so that most designs here need no eigenvalue problem
SPEEDS = {"critical_speeds_rad_s": [150.0, 600.0]}
RANGES = {"speed_ratio": (0.8, 1.2), "gap_mm": (0.5, 4.0), "mu": (0.1, 0.5),
          "unbalance_scale": (0.6, 1.4)}


def make(factors, base=None, **sampling) -> Design:
    return Design.from_dict({"base": {**SPEEDS, **(base or {})}, "sampling": sampling,
                             "factors": factors})


def issue_factors():
    return {"case": [1, 2], **{k: {"low": lo, "high": hi} for k, (lo, hi) in RANGES.items()}}


@pytest.fixture(scope="module")
def issue_design():
    return Design.from_toml(ISSUE_TOML)


# --- the design ----------------------------------------------------------------------
def test_rub_lhs200_toml_gives_200_runs_inside_the_ranges(issue_design, paper_rig):
    runs = issue_design.runs()
    assert issue_design.n_runs == len(runs) == 200
    assert issue_design.rig == paper_rig
    assert [r.replicate for r in runs] == [0] * 200
    assert len({r.run_id for r in runs}) == len({r.point_id for r in runs}) == 200
    for name, (lo, hi) in RANGES.items():
        values = np.array([r.point[name] for r in runs])
        assert lo <= values.min() and values.max() < hi, name
    # LHS with n = 200 and two levels: exactly 100 points each
    assert sorted(np.unique([r.point["case"] for r in runs], return_counts=True)[1]) == [100, 100]


def test_rub_lhs200_toml_runs_follow_their_points(issue_design):
    speeds = issue_design.resolved_critical_speeds_rad_s()
    for r in issue_design.runs()[:20]:
        p, run = r.point, r.run
        assert run.speed_rad_s == p["speed_ratio"] * speeds[p["case"] - 1]
        assert run.gap_m == p["gap_mm"] * 1e-3
        assert run.contact.friction_coefficient == p["mu"]
        assert run.unbalance == dataclasses.replace(
            issue_design.rig.unbalance(p["case"]),
            magnitudes_kg_m=tuple(m * p["unbalance_scale"]
                                  for m in issue_design.rig.loading.unbalance_kg_m))
        assert (run.duration_s, run.discard_s, run.gap_ramp_s) == (2.3, 0.3, 0.1)


def test_rub_lhs200_toml_with_replicates(issue_design):
    design = dataclasses.replace(issue_design, replicates=3)
    runs = design.runs()
    assert len(runs) == design.n_runs == 600
    assert len({r.run_id for r in runs}) == 600
    assert len({r.point_id for r in runs}) == 200
    for i in range(0, 600, 3):
        group = runs[i:i + 3]
        assert [r.replicate for r in group] == [0, 1, 2]
        assert len({r.point_id for r in group}) == 1
        assert [r.run.gap_ramp_s for r in group] == [0.1, 0.099, 0.101]
        assert group[0].point == group[1].point == group[2].point
    # replicates keep the points of the single-replicate design
    assert [r.point for r in runs[::3]] == [r.point for r in issue_design.runs()]


def test_critical_speeds_are_the_cases_forward_critical_speeds(issue_design, paper_rig):
    from rubdiag.simulation import critical_speed_for_case

    speeds = issue_design.resolved_critical_speeds_rad_s()
    assert speeds == (critical_speed_for_case(paper_rig, 1), critical_speed_for_case(paper_rig, 2))
    assert speeds == pytest.approx((1500 * math.pi / 30, 5700 * math.pi / 30), rel=1e-6)


def test_study_cell_is_the_paper_run(paper_rig):
    """case = [c], speed_ratio = [1], gap_mm = [2.3] is Run.paper_case(c, 2.3) with the
    default sensors and the design's step tolerance: same Run (but for the label), same
    run_id; with ``step_error = 0`` the study's run itself."""
    from rubdiag.dataset import run_id
    from rubdiag.dataset._design import DEFAULT_STEP_ERROR
    from rubdiag.simulation import default_sensors

    for case, step_error in ((1, DEFAULT_STEP_ERROR), (2, DEFAULT_STEP_ERROR), (1, 0.0)):
        design = Design.from_dict({"base": {"step_error": step_error},
                                   "factors": {"case": [case], "speed_ratio": [1.0],
                                               "gap_mm": [2.3]}})
        (item,) = design.runs()
        paper = Run.paper_case(case, 2.3, sensors=default_sensors(paper_rig),
                               step_error=step_error or None)
        assert item.run == dataclasses.replace(paper, label=item.run.label)
        assert item.run_id == run_id(paper)


# --- sampling ---------------------------------------------------------------------------------
def test_lhs_puts_one_point_in_each_stratum_of_every_range():
    for n in (7, 50):
        points = make(issue_factors(), method="lhs", n=n, seed=3).points()
        for name, (lo, hi) in RANGES.items():
            strata = np.floor((np.array([p[name] for p in points]) - lo) / (hi - lo) * n)
            assert sorted(strata.astype(int)) == list(range(n)), (n, name)


def test_lhs_gives_each_level_an_equal_share():
    factors = {"case": [1, 2], "speed_rpm": [900.0], "gap_mm": [1.0, 2.0, 3.0],
               "mu": {"low": 0.1, "high": 0.5}}
    points = make(factors, method="lhs", n=12, seed=1).points()
    for name, k in (("case", 2), ("gap_mm", 3)):
        values, counts = np.unique([p[name] for p in points], return_counts=True)
        assert len(values) == k and set(counts) == {12 // k}, name


def test_sobol_n_must_be_a_power_of_two_and_its_strata_are_balanced():
    with pytest.raises(ValueError, match=r"^sampling.n = 200 is out of range "
                       r"\(allowed: a power of 2 for method = 'sobol', e.g. 128 or 256\)$"):
        make(issue_factors(), method="sobol", n=200)
    points = make(issue_factors(), method="sobol", n=64, seed=5).points()
    for name, (lo, hi) in RANGES.items():     # a (0, 6, 1)-net: one point per 1/64
        strata = np.floor((np.array([p[name] for p in points]) - lo) / (hi - lo) * 64)
        assert sorted(strata.astype(int)) == list(range(64)), name
    assert sorted(np.unique([p["case"] for p in points], return_counts=True)[1]) == [32, 32]


def test_random_is_uniform_draws_in_the_ranges():
    points = make(issue_factors(), method="random", n=400, seed=2).points()
    for name, (lo, hi) in RANGES.items():
        u = (np.array([p[name] for p in points]) - lo) / (hi - lo)
        assert 0 <= u.min() and u.max() < 1
        assert abs(u.mean() - 0.5) < 0.05
        # unlike LHS, some of the 400 strata hold two points or more
        assert len(np.unique(np.floor(u * 400))) < 400


@pytest.mark.parametrize("method", ["lhs", "sobol", "random"])
def test_sampling_is_deterministic_given_the_seed(method):
    a = make(issue_factors(), method=method, n=16, seed=11).points()
    assert make(issue_factors(), method=method, n=16, seed=11).points() == a
    assert make(issue_factors(), method=method, n=16, seed=12).points() != a


def test_points_do_not_depend_on_the_order_of_the_factors_in_the_file():
    factors = issue_factors()
    reordered = dict(reversed(list(factors.items())))
    a = make(factors, method="lhs", n=10, seed=4)
    b = make(reordered, method="lhs", n=10, seed=4)
    assert a == b and a.points() == b.points()
    assert list(a.points()[0]) == ["case", "speed_ratio", "gap_mm", "mu", "unbalance_scale"]


def test_single_level_factors_take_no_sampling_axis():
    a = make(issue_factors(), method="lhs", n=10, seed=4).points()
    b = make({**issue_factors(), "casing_stiffness_scale": [2.0]}, method="lhs", n=10,
             seed=4).points()
    assert [{k: v for k, v in p.items() if k != "casing_stiffness_scale"} for p in b] == a
    assert {p["casing_stiffness_scale"] for p in b} == {2.0}


def test_grid_is_the_product_of_the_levels_times_the_replicates():
    factors = {"case": [1, 2], "speed_ratio": {"low": 0.8, "high": 1.2, "n": 5},
               "gap_mm": [1.9, 2.3, 3.0], "mu": {"low": 0.2, "high": 0.4, "n": 2}}
    design = make(factors, base={"discard_s": 0.3}, method="grid", n=999, replicates=5)
    assert design.n == 2 * 5 * 3 * 2            # the given n is ignored
    runs = design.runs()
    assert len(runs) == design.n_runs == 60 * 5
    points = design.points()
    assert points[0] == {"case": 1, "speed_ratio": 0.8, "gap_mm": 1.9, "mu": 0.2}
    assert points[1] == {"case": 1, "speed_ratio": 0.8, "gap_mm": 1.9, "mu": 0.4}  # last fastest
    assert sorted({p["speed_ratio"] for p in points}) == pytest.approx([0.8, 0.9, 1.0, 1.1, 1.2])
    assert {p["speed_ratio"] for p in points} >= {0.8, 1.2}            # both ends exactly
    assert len({tuple(p.values()) for p in points}) == 60
    assert len({r.run_id for r in runs}) == 300 and len({r.point_id for r in runs}) == 60


# --- replicates -------------------------------------------------------------------------------
def test_five_replicates_are_the_papers_ensemble():
    from rubdiag.paper._ensemble import GAP_RAMPS_S

    ramps = gap_ramps_s(5, 2.3)
    assert ramps == (0.1, 0.099, 0.101, 0.098, 0.102)
    assert sorted(ramps) == list(GAP_RAMPS_S)


def test_more_replicates_halve_the_spacing_inside_two_percent():
    ramps = gap_ramps_s(65, 2.3)
    assert ramps[:9] == (0.1, 0.099, 0.101, 0.098, 0.102, 0.0995, 0.1005, 0.0985, 0.1015)
    assert gap_ramps_s(12, 2.3) == ramps[:12]        # replicate r is the same history
    assert len(set(ramps)) == 65
    assert min(ramps) == 0.098 and max(ramps) == 0.102
    assert np.diff(sorted(ramps)).min() == pytest.approx(0.1 * 0.01 / 16)
    # short runs: around the Run's standard ramp, half the duration
    assert gap_ramps_s(3, 0.1) == (0.05, 0.0495, 0.0505)
    assert Run.paper_case(1, 2.3, duration_s=0.1, discard_s=0.06).gap_ramp_s == 0.05


def test_replicates_differ_only_in_their_start_history():
    design = make({"case": [2], "speed_ratio": [1.0]}, replicates=4)
    runs = design.runs()
    base = runs[0].run
    for r in runs[1:]:
        assert r.run == dataclasses.replace(base, gap_ramp_s=r.run.gap_ramp_s,
                                            label=r.run.label)
        assert r.point_id == runs[0].point_id and r.run_id != runs[0].run_id


# --- what each factor does --------------------------------------------------------------------
def test_phase_difference_spans_the_two_cases(paper_rig):
    design = make({"phase_diff_deg": [0.0, 90.0, 180.0], "speed_rpm": [1500.0]})
    runs = design.runs()
    assert runs[0].run.unbalance == paper_rig.unbalance(1)
    assert runs[2].run.unbalance == paper_rig.unbalance(2)
    assert runs[1].run.unbalance.phases_rad == (0.0, math.pi / 2)
    assert runs[0].run.speed_rad_s == 1500.0 * math.pi / 30
    assert design.critical_speeds_rad_s == (150.0, 600.0)   # given, kept; not needed


def test_contact_and_casing_factors(paper_rig):
    law, casing = paper_rig.contact, paper_rig.casing
    point = {"case": 1, "speed_ratio": 1.0}
    design = make({"case": [1], "speed_ratio": [1.0]})
    run = design.run_for({**point, "normal_stiffness_n_m": 2e8, "mu": 0.2})
    assert run.contact == dataclasses.replace(law, normal_stiffness_n_m=2e8,
                                              tangential_stiffness_n_m=2e8,
                                              friction_coefficient=0.2)
    run = design.run_for({**point, "contact_stiffness_scale": 0.5})
    assert run.contact.normal_stiffness_n_m == law.normal_stiffness_n_m * 0.5
    assert run.contact.tangential_stiffness_n_m == law.tangential_stiffness_n_m * 0.5
    run = design.run_for({**point, "casing_stiffness_scale": 3.0})
    assert run.contact is None        # the rig's law: no contact factor given
    assert run.rig.casing == dataclasses.replace(
        casing, support_k_y_n_m=3 * casing.support_k_y_n_m,
        support_k_z_n_m=3 * casing.support_k_z_n_m)
    assert run.rig.shaft == paper_rig.shaft and run.rig.contact == law
    run = design.run_for({**point, "unbalance_scale": 0.0, "gap_mm": 1.5})
    assert run.unbalance.magnitudes_kg_m == (0.0, 0.0) and run.gap_m == 1.5e-3
    assert design.run_for(point).gap_m == paper_rig.nominal_gap_m()


def test_resolved_reference_speeds_are_used_not_recomputed(monkeypatch):
    def fail(*args):
        raise AssertionError("computed a critical speed")

    monkeypatch.setattr(expansion_module, "rig_critical_speeds", fail)
    (item,) = make({"case": [2], "speed_ratio": [1.5]}).runs()
    assert item.run.speed_rad_s == 900.0


def test_making_a_design_solves_no_eigenvalue_problem(monkeypatch, paper_rig):
    """The design refers to its rig's critical speeds (speed_ratio) without giving
    them: reading it, checking it and drawing its points solve nothing (every eigenvalue
    solver raises meanwhile, nothing kept from other tests); its runs compute the speeds
    then, and are the runs of the same design given the cases' critical speeds."""
    import scipy.linalg
    import scipy.sparse.linalg

    from rubdiag.dataset import _resolve
    from rubdiag.simulation import _rig_cache, critical_speed_for_case

    def solve(*args, **kwargs):
        raise AssertionError("an eigenvalue problem was solved")

    with monkeypatch.context() as patch:
        for module, names in ((scipy.linalg, ("eig", "eigh", "eigvals", "eigvalsh")),
                              (scipy.sparse.linalg, ("eigs", "eigsh")),
                              (_rig_cache, ("forward_critical_speeds", "whirl_threshold_speed"))):
            for name in names:
                patch.setattr(module, name, solve)
        patch.setattr(_resolve, "_CRITICAL", {})
        patch.setattr(_resolve, "_THRESHOLD", {})
        design = Design.from_toml(ISSUE_TOML)
        points = design.points()
        with pytest.raises(AssertionError, match="an eigenvalue problem was solved"):
            design.runs()          # the solvers do raise: the runs need the speeds
    assert design.critical_speeds_rad_s is None
    given = dataclasses.replace(design, critical_speeds_rad_s=(
        critical_speed_for_case(paper_rig, 1), critical_speed_for_case(paper_rig, 2)))
    runs = design.runs()
    assert [r.point for r in runs] == points
    assert runs == given.runs()
    assert design == given and hash(design) == hash(given)
    assert design != dataclasses.replace(design, critical_speeds_rad_s=(150.0, 600.0))


# --- resolved form ----------------------------------------------------------------------------
def test_resolved_toml_round_trips_exactly(issue_design):
    text = issue_design.to_toml()
    again = Design.from_toml(text)
    assert again == issue_design
    assert again.to_toml() == text
    assert Design.from_dict(issue_design.to_dict()) == issue_design
    assert again.runs() == issue_design.runs()
    assert "[factors]\ncase = [1, 2]\nspeed_ratio = {low = 0.8, high = 1.2}\n" in text
    assert "\n[base.rig.contact]\n" in text       # the rig itself, not a name


def test_resolved_form_fills_in_the_defaults():
    design = Design.from_dict({"factors": {"case": [1], "speed_rpm": [1000],
                                           "gap_mm": {"low": 1, "high": 2, "n": 3}}})
    data = design.to_dict()
    assert data["sampling"] == {"method": "grid", "n": 3, "seed": 0, "replicates": 1}
    assert data["factors"] == {"case": [1], "speed_rpm": [1000.0],
                               "gap_mm": {"low": 1.0, "high": 2.0, "n": 3}}
    assert data["base"]["duration_s"] == 2.3 and data["base"]["discard_s"] == 0.3
    assert "critical_speeds_rad_s" not in data["base"]     # speed_rpm needs none


def test_design_and_runs_pickle(issue_design):
    assert pickle.loads(pickle.dumps(issue_design)) == issue_design
    assert hash(issue_design) == hash(pickle.loads(pickle.dumps(issue_design)))
    item = issue_design.runs()[0]
    assert pickle.loads(pickle.dumps(item)) == item


def test_rig_path_is_relative_to_the_design_file(tmp_path, paper_rig):
    rig = dataclasses.replace(paper_rig, name="stiffer casing", casing=dataclasses.replace(
        paper_rig.casing, support_k_y_n_m=2e6))
    (tmp_path / "rigs").mkdir()
    save_rig(rig, tmp_path / "rigs" / "r.toml")
    path = tmp_path / "design.toml"
    path.write_text('[base]\nrig = "rigs/r.toml"\n[factors]\ncase = [1]\nspeed_rpm = [900]\n')
    design = Design.from_toml(path)
    assert design.rig == rig
    assert Design.from_toml(str(path)) == design
    assert Design.from_toml(design.to_toml()).rig == rig     # embedded, file not needed


def test_factor_objects_are_accepted():
    a = make(issue_factors(), method="lhs", n=8)
    b = Design(rig=a.rig, factors=(Factor("mu", low=0.1, high=0.5), Factor("case", (1, 2)),
                                   Factor("gap_mm", low=0.5, high=4.0),
                                   Factor("speed_ratio", low=0.8, high=1.2),
                                   Factor("unbalance_scale", low=0.6, high=1.4)),
               method="lhs", n=8, critical_speeds_rad_s=(150.0, 600.0))
    assert a == b


# --- bad input: one line each -----------------------------------------------------------------
GOOD = {"base": {**SPEEDS}, "sampling": {"method": "lhs", "n": 8},
        "factors": {"case": [1, 2], "speed_ratio": {"low": 0.8, "high": 1.2}}}


def edit(section, **changes):
    data = {k: dict(v) for k, v in GOOD.items()}
    for key, value in changes.items():
        if value is None:
            del data[section][key]
        else:
            data[section][key] = value
    return data


BAD = [
    (edit("factors", speed={"low": 1, "high": 2}),
     r"unknown factor 'factors.speed' \(allowed: case, phase_diff_deg, speed_ratio, speed_rpm, "
     r"gap_mm, interference_ratio, mu, unbalance_scale, normal_stiffness_n_m, "
     r"contact_stiffness_scale, casing_stiffness_scale, damping_ratio, disc_mass_scale, "
     r"oil_viscosity_scale, bearing_clearance_scale, blade_count, fault, crack_depth_ratio, "
     r"misalignment_angle_mrad, looseness_preload_n, whirl_speed_ratio, rub_kind, "
     r"rubbing_blades\)"),
    (edit("sampling", replicate=2),
     r"unknown key 'sampling.replicate' \(allowed: method, n, seed, replicates\)"),
    (edit("base", duration=2.3),
     r"unknown key 'base.duration' \(allowed: rig, duration_s, discard_s, reduced, "
     r"reduction_cutoff_hz, step_error, critical_speeds_rad_s, gravity_m_s2, crack_element, "
     r"crack_law, coupling_node, drive_torque_n_m, spacer_length_m, misalignment_offset_m, "
     r"loose_bearing, loose_direction, loose_stiffness_n_m, seal_node\)"),
    ({**GOOD, "noises": {}},
     r"unknown table \[noises\] \(allowed: base, ramp, sampling, factors, labels, noise, "
     r"sensors\)"),
    ({**GOOD, "sensors": [{"point": "shaft 99", "direction": "y"}]},
     r"sensor 'shaft99_y_disp': no DOF \('shaft 99', 'y'\) in rig"),
    ({**GOOD, "sensors": [{"point": "shaft 4", "direction": "y", "gain": 2}]},
     r"unknown key 'sensors.gain' \(allowed: point, direction, quantity, name\)"),
    ({**GOOD, "sensors": []}, r"sensors is empty"),
    ({**GOOD, "noise": {"displacement_m": -1e-6}}, r"noise.displacement_m = -1e-06 is out of "),
    (edit("factors", mu={"low": 0.1, "high": 0.5, "step": 0.1}),
     r"unknown key 'factors.mu.step' \(allowed: low, high, n, bands\)"),
    (edit("factors", mu={"low": 0.5, "high": 0.1}),
     r"factors.mu.low = 0.5 is out of range \(allowed: < high = 0.1\)"),
    (edit("factors", mu={"low": 0.1}), r"factors.mu.high is missing"),
    (edit("sampling", n=0), r"sampling.n = 0 is out of range \(allowed: >= 1\)"),
    (edit("sampling", n=-3), r"sampling.n = -3 is out of range \(allowed: >= 1\)"),
    (edit("sampling", n=None), r"sampling.n is missing \(method = 'lhs' needs"),
    (edit("sampling", n=8.0), r"sampling.n = 8.0 has the wrong type \(expected an integer\)"),
    (edit("factors", mu={"low": 0.1, "high": 0.5, "n": 0}),
     r"factors.mu.n = 0 is out of range \(allowed: >= 2\)"),
    (edit("factors", gap_mm={"low": -1.0, "high": 2.0}),
     r"factors.gap_mm.low = -1.0 is out of range \(allowed: > 0 and <= 100 mm\)"),
    (edit("factors", mu=[0.2, 20.0]),
     r"factors.mu\[1\] = 20.0 is out of range \(allowed: >= 0 and <= 10\)"),
    (edit("factors", case=[1, 3]), r"factors.case\[1\] = 3 is out of range \(allowed: >= 1 and "
     r"<= 2\)"),
    (edit("factors", case=[1.0]), r"factors.case\[0\] = 1.0 has the wrong type"),
    (edit("factors", case={"low": 1, "high": 2}), r"factors.case = .* has the wrong type "
     r"\(expected a list of levels, e.g. \[1, 2\]\)"),
    (edit("factors", gap_mm="2"), r"factors.gap_mm = '2' has the wrong type"),
    (edit("factors", gap_mm=[2.0, 2.0]), r"factors.gap_mm = \[2.0, 2.0\] lists a level twice"),
    (edit("factors", gap_mm=[]), r"factors.gap_mm is empty"),
    (edit("factors", speed_ratio={"low": 0.0, "high": 1.2}),
     r"factors.speed_ratio.low = 0.0 is out of range \(allowed: > 0 and <= 10\)"),
    (edit("factors", unbalance_scale={"low": -0.5, "high": 1.0}),
     r"factors.unbalance_scale.low = -0.5 is out of range"),
    (edit("factors", normal_stiffness_n_m=[0.0]),
     r"factors.normal_stiffness_n_m\[0\] = 0.0 is out of range \(allowed: > 0 N/m\)"),
    (edit("factors", phase_diff_deg=[0.0, 180.0]),
     r"factors.case and factors.phase_diff_deg exclude each other"),
    (edit("factors", speed_rpm=[1500.0]),
     r"factors.speed_ratio and factors.speed_rpm exclude each other"),
    (edit("factors", normal_stiffness_n_m=[1e8], contact_stiffness_scale=[2.0]),
     r"factors.normal_stiffness_n_m and factors.contact_stiffness_scale exclude each other"),
    (edit("factors", case=None, phase_diff_deg=[0.0, 90.0]),
     r"factors.speed_ratio needs case .*; with phase_diff_deg give speed_rpm"),
    (edit("factors", case=None), r"factors needs case or phase_diff_deg"),
    (edit("factors", speed_ratio=None, gap_mm={"low": 1, "high": 2}),
     r"factors needs speed_ratio or speed_rpm"),
    (edit("factors", speed_ratio=[1.0]),
     r"sampling.method = 'lhs' needs a \{low, high\} factor .*use 'grid'"),
    (edit("sampling", method="grid"),
     r"factors.speed_ratio.n is missing \(method = 'grid' needs"),
    (edit("sampling", method="latin"),
     r"sampling.method = 'latin' is not allowed \(allowed: grid, lhs, sobol, random\)"),
    (edit("sampling", replicates=0), r"sampling.replicates = 0 is out of range \(allowed: >= 1"),
    (edit("sampling", replicates=66), r"sampling.replicates = 66 is out of range "
     r"\(allowed: >= 1 and <= 65\)"),
    (edit("sampling", seed=-1), r"sampling.seed = -1 is out of range"),
    (edit("base", discard_s=0.05), r"base.discard_s = 0.05 is out of range \(allowed: >= 0.1 s, "
     r"the longest gap ramp"),
    (edit("base", discard_s=3.0), r"base.discard_s = 3.0 is out of range \(allowed: >= 0 and "
     r"< 2.3 s\)"),
    (edit("base", duration_s=0.0), r"base.duration_s = 0.0 is out of range"),
    (edit("base", rig="nosuchrig.toml"), r"base.rig = 'nosuchrig.toml' is neither a preset nor "
     r"a file \(allowed: 'paper', 'paper-pedestal', 'paper-journal' or a rig TOML "
     r"path\)"),
    (edit("base", rig={"name": "x"}), r"base.rig: "),
    (edit("base", critical_speeds_rad_s=[150.0]),
     r"base.critical_speeds_rad_s has 1 entries \(allowed: one per case, at least 2\)"),
    (edit("base", critical_speeds_rad_s=[150.0, -1.0]),
     r"base.critical_speeds_rad_s\[1\] = -1.0 is out of range"),
    ({**GOOD, "factors": [1, 2]}, r"factors = \[1, 2\] has the wrong type \(expected a table\)"),
]


@pytest.mark.parametrize(("data", "message"), BAD, ids=[m[:40] for _, m in BAD])
def test_bad_input_is_one_line(data, message):
    with pytest.raises(ValueError, match=f"^{message}") as info:
        Design.from_dict(data)
    assert "\n" not in str(info.value)


def test_rig_without_contact_is_refused(paper_rig):
    rig = dataclasses.replace(paper_rig, contact=None)
    with pytest.raises(ValueError, match=r"has no blade-casing contact"):
        Design(rig=rig, factors={"case": [1], "speed_rpm": [900]})


def test_a_design_that_repeats_a_run_is_refused(paper_rig):
    # a rig whose two loading cases are the same pattern: case = [1, 2] makes one run twice
    loading = dataclasses.replace(paper_rig.loading,
                                  case2_phases_rad=paper_rig.loading.case1_phases_rad)
    rig = dataclasses.replace(paper_rig, loading=loading)
    design = Design(rig=rig, factors={"case": [1, 2], "speed_rpm": [900.0, 1000.0]})
    with pytest.raises(ValueError, match=r"^the design repeats a run: point 2 is point 0 "
                       r"\(case = 2, speed_rpm = 900\)$"):
        design.runs()


def test_file_errors_name_the_file(tmp_path):
    path = tmp_path / "d.toml"
    path.write_text("[factors]\ncase = [1, 2\n")
    with pytest.raises(ValueError, match=r"^d.toml: not valid TOML"):
        Design.from_toml(path)
    path.write_text("[factors]\ncase = [1]\nspeed_rpm = [-5.0]\n")
    with pytest.raises(ValueError, match=r"^d.toml: factors.speed_rpm\[0\] = -5.0 is out of "
                       r"range \(allowed: > 0 and <= 900000 rpm\)$"):
        Design.from_toml(path)


def test_good_base_is_good():
    assert make(GOOD["factors"], method="lhs", n=8).n_runs == 8


def test_a_window_short_of_the_revolutions_never_reads_as_enough():
    """0.5 s at 1199.9999 rpm is 9.9999992 revolutions, refused: the message must not say
    it holds 10 (it read "holds 10 revolutions at 1200 rpm … allowed: at least 10")."""
    text = ('[base]\nduration_s = 0.6\ndiscard_s = 0.1\n[factors]\ncase = [1]\n'
            'speed_rpm = [1199.9999]\n')
    with pytest.raises(ValueError) as info:
        Design.from_toml(text)
    shown = re.search(r"holds ([0-9.e+-]+) revolutions at ([0-9.e+-]+) rpm", str(info.value))
    assert float(shown.group(1)) < design_module.MIN_REVOLUTIONS
    assert float(shown.group(2)) < 1200.0
    Design.from_toml(text.replace("1199.9999", "1200"))       # exactly 10: accepted
