"""Model-uncertainty factors (rubdiag.dataset._rig_factors) and the gap set by
interference_ratio: each changes what it names, the speed follows the run's own rig, and
a rub run's gap is its linear approach over the ratio."""

import math

import numpy as np
import pytest

from rubdiag.dataset import Design
from rubdiag.dataset._rig_factors import bearing_loads_n, varied_rig
from rubdiag.model import preset_rig

G = 9.81

TOML = """
[base]
rig = "paper-journal"
duration_s = 2.5
discard_s = 1.2
reduced = true
gravity_m_s2 = 9.81

[sampling]
method = "lhs"
n = 8
seed = 3

[factors]
case = [1, 2]
speed_ratio = {low = 0.7, high = 0.8}
interference_ratio = {low = 1.2, high = 3.0}
fault = ["rub", "whirl"]
whirl_speed_ratio = {low = 1.35, high = 1.55}
damping_ratio = [0.035, 0.045]
disc_mass_scale = [0.9, 1.1]
bearing_clearance_scale = [0.95, 1.05]
"""


@pytest.fixture(scope="module")
def design():
    return Design.from_toml(TOML)


def _x(rig, node) -> float:
    return rig.shaft.node_positions_m[list(rig.shaft.nodes).index(node)]


def test_the_heavier_discs_load_the_bearings_by_the_lever_rule():
    """The two-bearing rotor is statically determinate: the discs' extra weight splits
    between the bearings in inverse proportion to the distances (closed form)."""
    rig = preset_rig("paper-journal")
    heavy = varied_rig(rig, {"disc_mass_scale": 1.1})
    (b0, b1), rho = rig.bearings, rig.material.density_kg_m3
    x0, x1 = _x(rig, b0.node), _x(rig, b1.node)
    extra = np.zeros(2)
    for d in rig.discs:
        w = 0.1 * d.inertia(rho)[0] * G
        xd = _x(rig, d.node)
        extra += [w * (x1 - xd) / (x1 - x0), w * (xd - x0) / (x1 - x0)]
    np.testing.assert_allclose(np.subtract(bearing_loads_n(heavy), bearing_loads_n(rig)),
                               extra, rtol=1e-6)
    assert [b.journal.load_n for b in heavy.bearings] == list(bearing_loads_n(heavy))
    # and the preset's loads are the reactions of its own rotor
    np.testing.assert_allclose(bearing_loads_n(rig),
                               [b.journal.load_n for b in rig.bearings], atol=1e-3)


def test_each_factor_changes_what_it_names():
    rig = preset_rig("paper-journal")
    v = varied_rig(rig, {"casing_stiffness_scale": 2.0, "damping_ratio": 0.03,
                         "disc_mass_scale": 1.1, "oil_viscosity_scale": 0.9,
                         "bearing_clearance_scale": 1.05})
    assert v.casing.support_k_y_n_m == 2.0 * rig.casing.support_k_y_n_m
    assert v.casing.support_c_y_ns_m == rig.casing.support_c_y_ns_m     # not the dampers
    assert (v.damping.xi_1, v.damping.xi_2) == (0.03, 0.03)
    rho = rig.material.density_kg_m3
    for new, old in zip(v.discs, rig.discs, strict=True):
        np.testing.assert_allclose(new.inertia(rho), 1.1 * np.array(old.inertia(rho)),
                                   rtol=1e-12)
    for new, old in zip(v.bearings, rig.bearings, strict=True):
        assert new.journal.viscosity_pa_s == pytest.approx(0.9 * old.journal.viscosity_pa_s)
        assert new.journal.clearance_m == pytest.approx(1.05 * old.journal.clearance_m)
    assert varied_rig(rig, {"case": 1}) is rig


def test_a_journal_factor_on_a_rig_without_journals_is_refused():
    text = TOML.replace('"paper-journal"', '"paper-pedestal"').replace(
        'fault = ["rub", "whirl"]\nwhirl_speed_ratio = {low = 1.35, high = 1.55}\n', "")
    with pytest.raises(ValueError, match=r"^factors.bearing_clearance_scale needs a rig "
                                         r"with journal bearings"):
        Design.from_toml(text)


def test_speed_follows_each_run_s_own_rig(design):
    from rubdiag.dataset._faults import whirl_threshold_rad_s
    from rubdiag.simulation import critical_speed_for_case

    for item in design.runs():
        p = item.point
        rotor = {k: p[k] for k in ("disc_mass_scale", "bearing_clearance_scale")}
        if p["fault"] == "whirl":
            threshold = whirl_threshold_rad_s(varied_rig(
                design.rig, {**rotor, "damping_ratio": p["damping_ratio"]}))
            assert item.run.speed_rad_s == pytest.approx(p["whirl_speed_ratio"] * threshold,
                                                         rel=1e-9)
        else:
            critical = critical_speed_for_case(varied_rig(design.rig, rotor), p["case"])
            assert item.run.speed_rad_s == pytest.approx(p["speed_ratio"] * critical,
                                                         rel=1e-9)
        assert item.run.rig == varied_rig(design.rig, p)


def test_a_rub_run_s_gap_is_its_linear_approach_over_the_ratio(design):
    from rubdiag.dataset._approach import sweep_linear_approach_m

    runs = [r for r in design.runs() if r.point["fault"] == "rub"]
    assert runs
    for item in runs:
        approach = sweep_linear_approach_m(item.run)
        assert item.run.gap_m == pytest.approx(approach / item.point["interference_ratio"],
                                               abs=1e-9)
    others = [r for r in design.runs() if r.point["fault"] == "whirl"]
    assert all(math.isnan(r.point["interference_ratio"]) for r in others)
