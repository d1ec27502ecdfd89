"""The spectrum text is written from the features, nothing else."""

import math

from rubdiag.paper import describe_spectrum

NAN = math.nan


def row(**features):
    base = {"shaft_amp_1x": 2e-3, "blade_amp_1x": 2e-3}
    base.update(features)
    return base


def test_lists_what_was_detected_in_either_response():
    text = describe_spectrum(row(shaft_sb_4x_delta_hz=5.0, blade_amp_1p5x=1e-5,
                                 shaft_amp_3p5x=2e-5, shaft_amp_7x=3e-6,
                                 blade_combo_fa_hz=43.0, blade_combo_fb_hz=147.0,
                                 blade_combo_order=2.0))
    assert text.startswith("1× dominant")
    assert "7×" in text and "4× ± 5.0 Hz sidebands" in text
    assert "3×/2, 7×/2" in text
    assert "combination 43.0 Hz + 147.0 Hz = 2×" in text


def test_broadband_peak_needs_both_neighbours_well_below():
    hump = row(shaft_bb_3x_rms=1e-6, shaft_bb_4x_rms=2e-5, shaft_bb_5x_rms=1e-6)
    assert "broadband peak around 4×" in describe_spectrum(hump)
    flat = row(shaft_bb_3x_rms=1e-5, shaft_bb_4x_rms=2e-5, shaft_bb_5x_rms=1e-6)
    assert "broadband" not in describe_spectrum(flat)


def test_absent_and_nan_features_say_nothing():
    text = describe_spectrum(row(shaft_sb_4x_delta_hz=NAN, shaft_amp_1p5x=0.0,
                                 shaft_combo_fa_hz=NAN, blade_amp_1x=NAN))
    assert text == "1× dominant"
    assert describe_spectrum({"shaft_amp_1x": 0.0}) == "no significant line"
