"""The noise floor of a channel's broadband bands: the quietest band, never below
MIN_FLOOR_OF_LEVEL of the level; a band over it is never below 1."""

from __future__ import annotations

import numpy as np

from rubdiag.signal._bandfloor import MIN_FLOOR_OF_LEVEL, channel_floor, over_floor


def test_the_floor_is_the_quietest_band_above_the_rules_least():
    bands = [[3.0, 2.0, 5.0, np.nan],       # noise above the rule: its quietest band
             [3.0, 2.0, 5.0, np.nan],       # a loud channel: the rule's floor
             [0.0, 1e-9, 2e-3, np.nan],     # noise-free: round-off and an exact 0
             [np.nan] * 4,                  # no band measured: the rule's floor
             [0.0] * 4]                     # a still channel (level 0): none
    level = np.array([1.0, 1e5, 1.0, 7.0, 0.0])
    floor = channel_floor(bands, level)
    np.testing.assert_array_equal(floor[:4], [2.0, 1e5 * MIN_FLOOR_OF_LEVEL,
                                              MIN_FLOOR_OF_LEVEL, 7.0 * MIN_FLOOR_OF_LEVEL])
    assert np.isnan(floor[4])


def test_a_band_over_the_floor_is_never_below_one():
    band = np.array([0.0, 0.5, 2.0, 6.0, np.nan, 3.0])
    floor = np.array([2.0, 2.0, 2.0, 2.0, 2.0, np.nan])
    z = over_floor(band, floor)
    np.testing.assert_array_equal(z[:4], [1.0, 1.0, 1.0, 3.0])
    assert np.isnan(z[4])            # not measured stays so
    assert z[5] == 0.0               # no floor (still channel): nothing over it
