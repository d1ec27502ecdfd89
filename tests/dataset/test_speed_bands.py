"""A factor given as separate bands (``speed_ratio = {bands = [[0.45, 0.55], [0.9, 1.1]]}``):
each band owns an equal share of the sampling axis and is continuous inside it, a grid takes
``n`` levels per band, the resolved form round-trips, bad bands are refused in one line; and
the shipped design data/designs/faults_bands.toml puts every fault level in every band of
both cases alike. Nothing here simulates."""

from pathlib import Path

import numpy as np
import pytest

from rubdiag.dataset import Design, Factor

ROOT = Path(__file__).resolve().parents[2]
SPEEDS = {"critical_speeds_rad_s": [150.0, 600.0]}
BANDS = [[0.45, 0.55], [0.9, 1.1]]


def make(factors, **sampling) -> Design:
    return Design.from_dict({"base": dict(SPEEDS), "sampling": sampling,
                             "factors": {"case": [1, 2], **factors}})


def test_lhs_gives_each_band_half_the_points_one_per_stratum():
    n = 40
    points = make({"speed_ratio": {"bands": BANDS}}, method="lhs", n=n, seed=3).points()
    speeds = np.array([p["speed_ratio"] for p in points])
    for low, high in BANDS:
        inside = speeds[(speeds >= low) & (speeds < high)]
        assert inside.size == n // 2
        # continuous inside the band: one point in each of its n/2 strata
        strata = np.floor((inside - low) / (high - low) * (n // 2)).astype(int)
        assert sorted(strata) == list(range(n // 2))
    assert np.all(((speeds >= 0.45) & (speeds < 0.55)) | ((speeds >= 0.9) & (speeds < 1.1)))


def test_grid_takes_n_levels_in_each_band():
    design = make({"speed_ratio": {"bands": BANDS, "n": 3}}, method="grid")
    assert sorted({p["speed_ratio"] for p in design.points()}) == [0.45, 0.5, 0.55, 0.9,
                                                                    1.0, 1.1]
    assert design.n == 2 * 6


def test_bands_round_trip_through_the_resolved_form():
    design = make({"speed_ratio": {"bands": BANDS}, "mu": {"low": 0.1, "high": 0.5}},
                  method="lhs", n=8, seed=1)
    again = Design.from_toml(design.to_toml())
    assert again == design and again.points() == design.points()
    assert "speed_ratio = {bands = [[0.45, 0.55], [0.9, 1.1]]}" in design.to_toml()


def test_the_slowest_band_sets_the_window_check():
    """The window must hold its revolutions at the lowest band's low end (here 0.45 x
    150 rad/s = 10.7 rev/s: 0.9 s holds 9.7 revolutions, fewer than the features need)."""
    with pytest.raises(ValueError, match=r"holds 9\.67 revolutions"):
        Design.from_dict({"base": {**SPEEDS, "duration_s": 1.2, "discard_s": 0.3},
                          "sampling": {"method": "lhs", "n": 4},
                          "factors": {"case": [1, 2], "speed_ratio": {"bands": BANDS}}})


@pytest.mark.parametrize(("spec", "message"), [
    ({"bands": [[0.5, 0.4], [0.9, 1.1]]},
     r"factors.speed_ratio.bands\[0\]\[0\] = 0.5 is out of range \(allowed: < its high = "
     r"0.4\)"),
    ({"bands": [[0.4, 0.6], [0.5, 1.1]]},
     r"factors.speed_ratio.bands\[1\]\[0\] = 0.5 is out of range \(allowed: > the previous "
     r"band's high = 0.6"),
    ({"bands": [[0.4, 0.6]]}, r"factors.speed_ratio.bands has 1 band\(s\) \(allowed: at least "
     r"2"),
    ({"bands": [[0.4, 0.6], [0.9, 1.1]], "low": 0.4},
     r"factors.speed_ratio has bands and levels or low/high"),
    ({"bands": "0.4-0.6"}, r"factors.speed_ratio.bands = '0.4-0.6' has the wrong type"),
    ({"bands": [[0.4], [0.9, 1.1]]}, r"factors.speed_ratio.bands\[0\] = \[0.4\] has the wrong "
     r"type"),
    ({"bands": [[0.4, 0.6], [0.9, 11.0]]},
     r"factors.speed_ratio.bands\[1\]\[1\] = 11.0 is out of range \(allowed: > 0 and <= 10\)"),
])
def test_bad_bands_are_one_line(spec, message):
    with pytest.raises(ValueError, match=f"^{message}") as info:
        Factor.from_spec("speed_ratio", spec)
    assert "\n" not in str(info.value)


def test_a_levels_only_factor_takes_no_bands():
    with pytest.raises(ValueError, match=r"^factors.case = .* has the wrong type"):
        Factor.from_spec("case", {"bands": [[1, 2], [3, 4]]})


# --- the shipped design ----------------------------------------------------------------------
def _cells(name):
    design = Design.from_toml(ROOT / "data" / "designs" / name)
    points = design.points()
    levels = next(f.levels for f in design.factors if f.name == "fault")
    for case in (1, 2):
        for low, high in BANDS:
            cell = [p for p in points if p["case"] == case and low <= p["speed_ratio"] < high]
            yield design, levels, (low, high), {
                lv: [p["speed_ratio"] for p in cell if p["fault"] == lv] for lv in levels}


@pytest.mark.parametrize("name", ["faults_bands.toml", "faults_bands_slice.toml"])
def test_every_level_has_its_share_of_every_speed_band_of_both_cases(name):
    """No level is told apart by its speed: each (case, band) cell holds about a quarter of
    every level's runs (within -20 % and +30 %: the seeds were chosen for it)."""
    for design, levels, _, speeds in _cells(name):
        assert "whirl" not in " ".join(levels)     # whirl comes from the response alone
        share = design.n / len(levels) / 4
        counts = {lv: len(s) for lv, s in speeds.items()}
        assert min(counts.values()) >= 0.8 * share, counts
        assert max(counts.values()) <= 1.3 * share, counts


def test_inside_a_band_every_level_spans_the_band():
    """In the full design (25-35 runs of a level per cell) every level reaches within a fifth
    of the band's width of both its ends."""
    for _, _, (low, high), speeds in _cells("faults_bands.toml"):
        for lv, s in speeds.items():
            assert min(s) < low + 0.2 * (high - low), (low, lv)
            assert max(s) > high - 0.2 * (high - low), (low, lv)


def test_the_slice_has_the_full_designs_factors():
    full = Design.from_toml(ROOT / "data" / "designs" / "faults_bands.toml")
    part = Design.from_toml(ROOT / "data" / "designs" / "faults_bands_slice.toml")
    assert part.factors == full.factors and part.rig == full.rig
    assert (part.n, full.n) == (320, 960)
    assert part.fault_settings == full.fault_settings
    assert (part.duration_s, part.discard_s, part.reduction) == (full.duration_s,
                                                               full.discard_s, full.reduction)
