"""rubdiag.signal._fullspectrum: synthetic orbits of known content.

The convention: y + i z, the shaft turning from y towards z, is forward at positive
frequencies. A circle turning with the shaft is forward, against it reverse; an ellipse of
semi-axes a and b is forward (a + b)/2 and reverse (a - b)/2.
"""

from __future__ import annotations

import numpy as np
import pytest

from rubdiag.signal._fullspectrum import NEAR_RADIUS, full_spectrum_lines, orbit_measures

FS, SPEED = 5000.0, 25.0            # Hz
T = np.arange(int(2.0 * FS)) / FS    # 2 s: 50 whole revolutions
W = 2 * np.pi * SPEED
ORDERS = (0.5, 1.0, 1.5, 2.0, 3.0, 4.0)


def lines(y, z, rotation=1):
    return full_spectrum_lines(y, z, FS, SPEED, ORDERS, rotation=rotation)


def test_a_forward_circle_is_forward_and_a_reverse_one_reverse():
    forward, reverse = lines(3.0 * np.cos(W * T + 0.4), 3.0 * np.sin(W * T + 0.4))
    np.testing.assert_allclose(forward, [0, 3.0, 0, 0, 0, 0], atol=1e-6)
    np.testing.assert_allclose(reverse, 0.0, atol=1e-6)
    forward, reverse = lines(2.0 * np.cos(W * T), -2.0 * np.sin(W * T))
    np.testing.assert_allclose(reverse, [0, 2.0, 0, 0, 0, 0], atol=1e-6)
    np.testing.assert_allclose(forward, 0.0, atol=1e-6)
    # the same probes with the shaft turning the other way: the roles swap
    forward, reverse = lines(2.0 * np.cos(W * T), -2.0 * np.sin(W * T), rotation=-1)
    np.testing.assert_allclose(forward, [0, 2.0, 0, 0, 0, 0], atol=1e-6)


def test_an_ellipse_is_half_the_sum_forward_and_half_the_difference_reverse():
    a, b = 5.0, 2.0
    forward, reverse = lines(a * np.cos(W * T + 1.1), b * np.sin(W * T + 1.1))
    assert forward[1] == pytest.approx((a + b) / 2, abs=1e-6)
    assert reverse[1] == pytest.approx((a - b) / 2, abs=1e-6)
    m = orbit_measures(a * np.cos(W * T), b * np.sin(W * T), FS, SPEED, ORDERS)
    assert m.ellipticity_1x == pytest.approx((a - b) / (a + b), abs=1e-6)
    assert m.precession_1x == 1
    assert m.flattening == pytest.approx(1 - b / a, abs=1e-6)


def test_a_forward_1x_with_a_reverse_2x():
    y = 4.0 * np.cos(W * T) + 1.5 * np.cos(2 * W * T + 0.3)
    z = 4.0 * np.sin(W * T) - 1.5 * np.sin(2 * W * T + 0.3)
    forward, reverse = lines(y, z)
    np.testing.assert_allclose(forward, [0, 4.0, 0, 0, 0, 0], atol=1e-6)
    np.testing.assert_allclose(reverse, [0, 0, 0, 1.5, 0, 0], atol=1e-6)
    m = orbit_measures(y, z, FS, SPEED, ORDERS)
    assert m.reverse_share == pytest.approx(1.0, abs=1e-6)
    assert m.forward_1x == pytest.approx(4.0, abs=1e-6) and m.reverse_1x < 1e-6
    # a forward half order beside it: the reverse share is 1.5² / (1.5² + 0.8²)
    y2, z2 = y + 0.8 * np.cos(0.5 * W * T), z + 0.8 * np.sin(0.5 * W * T)
    m2 = orbit_measures(y2, z2, FS, SPEED, ORDERS)
    assert m2.reverse_share == pytest.approx(1.5**2 / (1.5**2 + 0.8**2), abs=1e-6)


def test_a_clipped_orbit_against_values_computed_here():
    """A forward circle of radius 3 held by a flat wall at y = 2: its radius, clipped where
    it would cross the wall, computed sample by sample here."""
    y, z = 3.0 * np.cos(W * T), 3.0 * np.sin(W * T)
    y = np.minimum(y, 2.0)
    m = orbit_measures(y, z, FS, SPEED, ORDERS)
    centre = (y + 1j * z).mean()
    radius = np.abs(y + 1j * z - centre)
    assert m.flattening == pytest.approx(1 - radius.min() / radius.max(), rel=1e-12)
    limit = np.percentile(radius, 99.0)
    assert m.limit_radius == pytest.approx(limit, rel=1e-12)
    near = np.mean(np.abs(radius - limit) <= NEAR_RADIUS * limit)
    assert m.near_limit_share == pytest.approx(near, rel=1e-12)
    # the wall holds the orbit acos(2/3)/pi of the time (27 %; to one sample of the 200 a
    # revolution has): a flat side, far from a
    # circle (flattening 0) and from a line (1)
    assert np.mean(y == 2.0) == pytest.approx(np.arccos(2 / 3) / np.pi, abs=1 / 200)
    assert 0.2 < m.flattening < 0.5


def test_bad_input_is_refused_by_name():
    with pytest.raises(ValueError, match="rotation"):
        lines(np.cos(W * T), np.sin(W * T), rotation=2)
    with pytest.raises(ValueError, match="same length"):
        full_spectrum_lines(np.zeros(10), np.zeros(11), FS, SPEED, ORDERS)
    with pytest.raises(ValueError, match="revolutions"):
        full_spectrum_lines(np.zeros(10), np.zeros(10), FS, SPEED, ORDERS)
    with pytest.raises(ValueError, match="NaN or inf"):
        full_spectrum_lines(np.full(1000, np.nan), np.zeros(1000), FS, SPEED, ORDERS)


def test_the_full_spectrum_puts_forward_right_and_reverse_left():
    """A forward circle of 3 at 1x and a reverse one of 1 at 2x, both on bins: the
    spectrum reads 3 at +25 Hz and 1 at -50 Hz, and little elsewhere."""
    from rubdiag.signal._fullspectrum import full_spectrum

    y = 3.0 * np.cos(W * T) + 1.0 * np.cos(2 * W * T)
    z = 3.0 * np.sin(W * T) - 1.0 * np.sin(2 * W * T)
    f, amp = full_spectrum(y, z, FS)
    assert f[0] == pytest.approx(-FS / 2) and np.all(np.diff(f) > 0)
    # (np.hanning is the symmetric window: its gain on a bin differs from the periodic
    # one's by 1.5e-9)
    assert amp[np.argmin(np.abs(f - SPEED))] == pytest.approx(3.0, rel=1e-6)
    assert amp[np.argmin(np.abs(f + 2 * SPEED))] == pytest.approx(1.0, rel=1e-6)
    assert amp[np.argmin(np.abs(f + SPEED))] < 1e-6
    assert amp[np.argmin(np.abs(f - 2 * SPEED))] < 1e-6


def test_the_full_spectrum_figure_is_drawn(tmp_path):
    import matplotlib.image as mpimg

    from rubdiag.plotting._faults import full_spectrum_figure

    y = 3.0 * np.cos(W * T) + 1.0 * np.cos(2 * W * T)
    z = 3.0 * np.sin(W * T) - 1.0 * np.sin(2 * W * T)
    fig = full_spectrum_figure(y, z, FS, SPEED, clearance=4.5, title="test")
    fig.savefig(tmp_path / "full.png", dpi=80)
    pixels = mpimg.imread(tmp_path / "full.png")
    assert min(pixels.shape[:2]) > 200 and pixels[..., :3].std() > 0.02


def test_rubdiag_features_takes_a_probe_pair(tmp_path, capsys):
    """``rubdiag features FILE --pair y,z`` adds the row 'y+iz': a forward 1x of 3 and a
    reverse 2x of 1 at 1500 rpm read back to 1e-6; the other rotation swaps them; a
    missing channel is one line and exit 2."""
    import json

    import pandas as pd

    from rubdiag.cli import main

    y = 3.0 * np.cos(W * T) + 1.0 * np.cos(2 * W * T)
    z = 3.0 * np.sin(W * T) - 1.0 * np.sin(2 * W * T)
    path = tmp_path / "pair.csv"
    pd.DataFrame({"time": T, "y": y, "z": z}).to_csv(path, index=False)
    assert main(["features", str(path), "--speed-rpm", "1500", "--pair", "y,z",
                 "--json"]) == 0
    rows = json.loads(capsys.readouterr().out)
    pair = rows[-1]
    assert pair["channel"] == "y+iz"
    assert pair["fwd_1x"] == pytest.approx(3.0, abs=1e-6)
    assert pair["rev_2x"] == pytest.approx(1.0, abs=1e-6)
    assert pair["rev_1x"] < 1e-6 and pair["precession_1x"] == 1
    assert pair["reverse_share"] == pytest.approx(1.0, abs=1e-6)
    assert main(["features", str(path), "--speed-rpm", "1500", "--pair", "y,z",
                 "--rotation", "-1", "--json"]) == 0
    pair = json.loads(capsys.readouterr().out)[-1]
    assert pair["rev_1x"] == pytest.approx(3.0, abs=1e-6) and pair["precession_1x"] == -1
    assert main(["features", str(path), "--speed-rpm", "1500", "--pair", "y,q"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "no channel 'q'" in err[0]


def test_a_simulation_result_has_no_pair_yet(tmp_path, capsys):
    """A result's channels are y only: --pair on one is refused in one line."""
    from rubdiag.cli import main

    out = tmp_path / "run.npz"
    assert main(["simulate", "--case", "1", "--gap-mm", "50", "--duration-s", "0.05",
                 "--discard-s", "0.0", "--out", str(out)]) == 0
    capsys.readouterr()
    assert main(["features", str(out), "--pair", "shaft,blade"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "simulation result's channels are y only" in err[0]


def test_pairs_of_one_record_share_references_and_keep_every_bit():
    """orbit_features_by_pair (one set of lock-in references per record length) gives, bit for bit,
    what full_spectrum_lines and orbit_measures give each pair alone."""
    from rubdiag.signal._fullspectrum import orbit_features_by_pair
    from rubdiag.signal._orders import HALF_ORDERS, THIRD_ORDERS, order_label

    rng = np.random.default_rng(7)
    pairs = {}
    for name, n in (("a", T.size), ("b", T.size), ("short", T.size - 333)):
        t = T[:n]
        pairs[name] = (np.cos(W * t) + 0.3 * np.cos(2.5 * W * t) + rng.normal(0, 0.1, n),
                       0.5 * np.sin(W * t) - 0.2 * np.sin(W * t / 3) + rng.normal(0, 0.1, n))
    orders = np.array(sorted(HALF_ORDERS + THIRD_ORDERS))
    rows = orbit_features_by_pair(pairs, FS, 60.0 * SPEED)
    assert list(rows) == list(pairs)
    for name, (y, z) in pairs.items():
        forward, reverse = full_spectrum_lines(y, z, FS, SPEED, orders)
        measures = orbit_measures(y, z, FS, SPEED, orders)
        expected = {}
        for k, f, r in zip(orders, forward, reverse, strict=True):
            expected[f"fwd_{order_label(k)}"] = float(f)
            expected[f"rev_{order_label(k)}"] = float(r)
        expected.update(vars(measures))
        assert list(rows[name]) == list(expected)
        for key, value in expected.items():
            assert np.float64(rows[name][key]).tobytes() == np.float64(value).tobytes(), key
