"""Labels from what a run did (rubdiag.dataset._labels): the study's four cells get the
study's severities, the measures follow their definitions, the rules their thresholds."""

from __future__ import annotations

import dataclasses
import math
import re
from types import SimpleNamespace

import numpy as np
import pytest

from rubdiag.dataset import _labels as L
from rubdiag.simulation import Run, simulate
from rubdiag.simulation._result import EpisodeLog

CELLS = {(1, 2.3): "light", (1, 1.9): "serious", (2, 2.3): "light", (2, 1.9): "serious"}


@pytest.fixture(scope="module")
def cells():
    """The study's four cells, short (0.35 s; labels need no spectrum)."""
    return {cell: simulate(Run.paper_case(*cell, duration_s=0.35, discard_s=0.15))
            for cell in CELLS}


@pytest.fixture(scope="module")
def no_rub():
    return simulate(Run.paper_case(2, 4.0, duration_s=0.35, discard_s=0.15))


def test_the_study_cells_get_the_study_severities(cells):
    for cell, severity in CELLS.items():
        labels = L.label_run(cells[cell])
        assert labels["rub"] and labels["rub_state"] == "partial", cell
        assert labels["severity"] == severity, (cell, labels["interference_ratio"])


def test_the_default_threshold_is_inside_the_documented_calibration_band(cells):
    """The docstring's band is (largest light ratio, smallest serious ratio]; the default
    lies inside, and the band is what the four cells give."""
    ratio = {cell: L.label_run(r)["interference_ratio"] for cell, r in cells.items()}
    light = max(v for c, v in ratio.items() if CELLS[c] == "light")
    serious = min(v for c, v in ratio.items() if CELLS[c] == "serious")
    band = re.search(r"any threshold in\s+\((?P<lo>[\d.]+), (?P<hi>[\d.]+)\]", L.__doc__)
    assert band is not None
    assert float(band["lo"]) == pytest.approx(light, abs=0.005)
    assert float(band["hi"]) == pytest.approx(serious, abs=0.005)
    assert light < L.LabelRules().severity_threshold <= serious


def test_interference_ratio_is_the_linear_approach_over_the_gap(cells):
    """Both gaps of a case share the linear response: the ratios scale as 1/g0."""
    for case in (1, 2):
        a = L.label_run(cells[(case, 2.3)])["interference_ratio"]
        b = L.label_run(cells[(case, 1.9)])["interference_ratio"]
        assert a * 2.3 == pytest.approx(b * 1.9, rel=1e-12)
        assert cells[(case, 2.3)].linear_approach_m == pytest.approx(a * 2.3e-3, rel=1e-12)


def test_measures_agree_with_the_sampled_waveforms(cells):
    """Contact-time fraction against the sampled status (within one sample per episode
    edge); the peak force is at least every sampled force; the penetration is the penalty
    one; friction dissipates."""
    for cell, result in cells.items():
        m = L.run_measures(result)
        window = result.window
        status = result.system.contact_status[window]
        sampled = (status > 1).mean(axis=0).max()
        ep = result.system.episodes
        edges = 2 * np.sum(ep.t_end > result.run.discard_s) / result.fs
        span = result.t[window][-1] - result.t[window][0]
        assert abs(m["contact_time_fraction"] - sampled) <= edges / span + 1e-9, cell
        assert m["peak_normal_force_n"] >= result.system.contact_fn[window].max() - 1e-9
        k_n = result.run.contact_law.normal_stiffness_n_m
        assert m["peak_penetration_m"] == pytest.approx(m["peak_normal_force_n"] / k_n)
        assert m["friction_work_per_rev_j"] > 0
        assert 0 < m["sticking_share"] < 1


def test_a_run_that_never_touches_is_no_rub_and_its_casing_never_moves(no_rub):
    m = L.label_run(no_rub)
    assert m["interference_ratio"] < 1
    assert (m["rub"], m["rub_state"], m["severity"]) == (False, "none", "none")
    assert m["n_rub_episodes"] == 0 and m["peak_normal_force_n"] == 0
    assert m["contact_time_fraction"] == 0 and m["friction_work_per_rev_j"] == 0
    assert math.isnan(m["sticking_share"])
    # the casing moves only through contact: exactly zero, not small
    assert not np.any(no_rub.displacement("casing 1 y"))
    assert not np.any(no_rub.displacement("casing 1 z"))


def _fake(episodes: dict, discard=0.1, end=0.3, gap=1e-3, approach=2e-3):
    """A result-like object holding only what run_measures reads."""
    n = len(episodes["element"])
    zeros = np.zeros(n)
    fields = {f.name: np.asarray(episodes.get(f.name, zeros))
              for f in dataclasses.fields(EpisodeLog)}
    run = SimpleNamespace(discard_s=discard, gap_m=gap, speed_rad_s=2 * math.pi * 100,
                          contact_law=SimpleNamespace(normal_stiffness_n_m=1e8))
    t = np.linspace(0, end, 301)
    system = SimpleNamespace(t=t, episodes=EpisodeLog(**fields),
                             contact_fn=np.zeros((t.size, 2)),
                             dissipated_friction=np.where(t >= discard, t - discard, 0.0))
    return SimpleNamespace(run=run, system=system, linear_approach_m=approach)


def test_an_episode_spanning_the_window_is_a_full_rub():
    """An episode that began before the window and never ended: closed for the whole
    window (clipped at both ends), so full — counting only episodes that start in the
    window would have called it no rub."""
    fake = _fake({"element": [2], "t_start": [0.05], "t_end": [0.3], "n_steps": [25000],
                  "peak_normal_force": [50.0], "slide_time": [0.2], "stick_time": [0.05]})
    m = L.label_run(fake)
    assert m["contact_time_fraction"] == pytest.approx(1.0)
    assert m["n_rub_episodes"] == 1
    assert (m["rub"], m["rub_state"], m["severity"]) == (True, "full", "serious")
    assert m["sticking_share"] == pytest.approx(0.2)
    # friction ledger rises by 0.2 J over 0.2 s at 100 rev/s: 0.01 J per revolution
    assert m["friction_work_per_rev_j"] == pytest.approx(0.2 / 20)


def test_a_one_step_graze_is_no_rub_and_fractions_add_per_element():
    """The rule is in closed time (15 µs): one 10-µs step is a graze, two are a rub, and so
    is one 10-µs step with a 5-µs one; two 5-µs steps are not."""
    fake = _fake({"element": [1, 1, 2], "t_start": [0.12, 0.20, 0.15],
                  "t_end": [0.14, 0.25, 0.150001], "n_steps": [2000, 5000, 1],
                  "slide_time": [0.02, 0.05, 1e-5], "peak_normal_force": [10.0, 20.0, 1.0]})
    m = L.label_run(fake)
    assert m["n_rub_episodes"] == 2                          # the graze is not counted
    assert m["contact_time_fraction"] == pytest.approx((0.02 + 0.05) / 0.2)
    assert m["rub_state"] == "partial"
    for steps, rub in (([1e-5], False), ([1e-5, 1e-5], True), ([1e-5, 5e-6], True),
                       ([5e-6, 5e-6], False)):
        one = _fake({"element": [1], "t_start": [0.15], "t_end": [0.15 + sum(steps)],
                     "n_steps": [len(steps)], "slide_time": [sum(steps)],
                     "peak_normal_force": [1.0]})
        assert L.label_run(one)["rub"] is rub, steps


@pytest.mark.parametrize(("ratio", "fraction", "expected"), [
    (1.36, 0.5, ("partial", "light")), (1.37, 0.5, ("partial", "serious")),
    (5.0, 0.95, ("full", "serious")), (5.0, 0.9499, ("partial", "serious"))])
def test_rules_cut_at_their_thresholds(ratio, fraction, expected):
    measures = {"n_rub_episodes": 3, "interference_ratio": ratio,
                "contact_time_fraction": fraction}
    labels = L.labels_from_measures(measures)
    assert (labels["rub_state"], labels["severity"]) == expected
    other = L.LabelRules(severity_threshold=10.0, full_contact_share=0.5)
    assert L.labels_from_measures(measures, other)["severity"] == "light"
    assert L.labels_from_measures(measures, other)["rub_state"] == "full"


@pytest.mark.parametrize(("kwargs", "fragment"), [
    ({"severity_threshold": 0.0}, "labels.severity_threshold = 0.0 is out of range"),
    ({"full_contact_share": 1.5}, "labels.full_contact_share = 1.5 is out of range"),
    ({"full_contact_share": 0.0}, "labels.full_contact_share = 0.0 is out of range")])
def test_bad_rules_are_refused_naming_the_key(kwargs, fragment):
    with pytest.raises(ValueError, match=re.escape(fragment)):
        L.LabelRules(**kwargs)
