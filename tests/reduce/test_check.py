"""The reduced paper rig against the full one (``rubdiag.reduce._check``): the tolerances are
the module's constants, which README's "Reduced model" section quotes."""

from __future__ import annotations

import numpy as np
import pytest

from rubdiag.model import paper_rig
from rubdiag.reduce import check, reduced_model
from rubdiag.reduce._check import FREQUENCY_TOLERANCE, RESPONSE_TOLERANCE, STATIC_TOLERANCE


@pytest.fixture(scope="module")
def report():
    return check(paper_rig(), n_frequencies=40)


def test_the_reduced_paper_rig_passes(report):
    s = report.summary()
    assert report.passed, s
    assert s["n_reduced"] < s["n_full"] / 5       # 60 of 412 coordinates
    # the criticals of both cases, within 0.5 %
    crit = report.critical_speeds
    assert crit.full_rpm.iloc[0] == pytest.approx(1500.0, rel=1e-3)
    assert crit.full_rpm.iloc[1] == pytest.approx(5700.0, rel=1e-3)
    assert (crit.error.abs().iloc[:2] <= FREQUENCY_TOLERANCE).all()
    assert s["static_compliance_error"] <= STATIC_TOLERANCE
    assert s["max_sensor_response_error_in_band"] <= RESPONSE_TOLERANCE


def test_frequencies_are_upper_bounds_at_rest(report):
    # Rayleigh–Ritz on an undamped, non-rotating structure: never below the full model
    at_rest = report.frequencies[report.frequencies.speed_rpm == 0]
    assert len(at_rest) > 20
    assert (at_rest.error >= -1e-8).all()


def test_a_model_too_coarse_for_its_band_fails(monkeypatch):
    # the check can fail: a model with the modes of a 300-Hz cutoff, answering for the
    # default 1-kHz band, misses the band's modes
    import dataclasses
    import importlib

    from rubdiag.reduce import Reduction

    check_module = importlib.import_module("rubdiag.reduce._check")   # the module, not check()

    rig = paper_rig()
    coarse = dataclasses.replace(reduced_model(rig, Reduction(cutoff_hz=300.0)),
                                 reduction=Reduction())
    monkeypatch.setattr(check_module, "reduced_model", lambda rig, reduction: coarse)
    report = check(rig, n_frequencies=10)
    assert not report.passed
    assert report.summary()["max_frequency_error_in_band"] > FREQUENCY_TOLERANCE


def test_one_reduction_per_rig_and_process():
    rig = paper_rig()
    a = reduced_model(rig)
    assert reduced_model(rig) is a
    np.testing.assert_array_equal(a.M, a.M.T)     # the kernel reads rows as columns
    np.testing.assert_array_equal(a.K, a.K.T)
    np.testing.assert_allclose(a.G, -a.G.T, atol=1e-12 * np.abs(a.G).max())


def test_sensor_dofs_are_those_of_the_default_sensors():
    # check() sits below rubdiag.simulate, so it names the default sensors' DOFs itself
    from rubdiag.assembly import assemble
    from rubdiag.reduce._check import _sensor_dofs
    from rubdiag.simulation import default_sensors

    rig = paper_rig()
    model = assemble(rig)
    expected = [model.dofs.index(s.point, s.direction) for s in default_sensors(rig)]
    assert _sensor_dofs(model) == expected


# The contact blades' first bending at rest, with the tips as the only boundary DOFs of each
# blade, is represented by the static shapes the tip DOFs give: Rayleigh–Ritz on a uniform
# cantilever (EI, m, L; ω = c √(EI / m L⁴), exact c = 1.8751² = 3.5160) gives
#   tip force alone, shape x²(3L − x):            c² = 420/33           → +1.465 %
#   tip force and moment, shapes x², x³ (Ritz):   K = [[4, 6], [6, 12]], M = [[1/5, 1/6],
#                                                 [1/6, 1/7]]            → +0.475 %
# The FE blade's own discretisation adds ≈ 0.01 % to both.
EXACT_C = 1.875104069**2


def _ritz_two_term() -> float:
    from scipy.linalg import eigh

    lowest = eigh([[4.0, 6.0], [6.0, 12.0]], [[1 / 5, 1 / 6], [1 / 6, 1 / 7]],
                  eigvals_only=True)[0]
    return np.sqrt(lowest) / EXACT_C - 1


@pytest.mark.parametrize(("tip_rotations", "rayleigh_error"), [
    (False, np.sqrt(420 / 33) / EXACT_C - 1),
    (True, _ritz_two_term()),
])
def test_contact_blade_bending_is_the_rayleigh_ritz_value(tip_rotations, rayleigh_error,
                                                          report):
    from rubdiag.reduce import Reduction

    if tip_rotations:
        assert Reduction().tip_rotations      # the default: the module's report is that check
    else:
        report = check(paper_rig(), Reduction(tip_rotations=False), n_frequencies=40)
    at_rest = report.frequencies[report.frequencies.speed_rpm == 0]
    # the blade cluster: the most frequent full-model frequency (every blade's first bending)
    cluster = at_rest.full_hz.round(3).mode().iloc[0]
    blades = at_rest[np.isclose(at_rest.full_hz, cluster, rtol=1e-6)]
    assert len(blades) >= 8
    assert blades.error.max() == pytest.approx(rayleigh_error, abs=3e-4)
