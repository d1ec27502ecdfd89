"""amplitude_spectrum and spectral_lines: known tones in, known amplitudes out."""

from __future__ import annotations

import numpy as np
import pytest

from rubdiag.signal import amplitude_spectrum, spectral_lines


class TestAmplitudeSpectrum:
    @pytest.mark.parametrize("window", ["hann", "boxcar", "hamming", "blackman", "flattop"])
    @pytest.mark.parametrize("n", [2000, 2001])
    def test_on_bin_tone_reads_its_amplitude(self, synth, window, n):
        fs = 1000.0
        x = synth([(125.0 * 2000 / n, 2.5, 0.3)], fs, n / fs) + 0.7
        f, a = amplitude_spectrum(x, fs, window=window)
        k = int(np.argmax(a))
        assert f[k] == pytest.approx(125.0 * 2000 / n)
        assert a[k] == pytest.approx(2.5, rel=1e-9)
        assert a[0] == pytest.approx(0.0, abs=1e-9)  # mean removed by detrend

    def test_grid_and_dc_without_detrend(self):
        fs, n = 200.0, 64
        f, a = amplitude_spectrum(np.full(n, 3.0), fs, detrend=False)
        assert f.shape == (n // 2 + 1,)
        np.testing.assert_allclose(np.diff(f), fs / n)
        assert f[-1] == pytest.approx(fs / 2)
        assert a[0] == pytest.approx(3.0)  # DC is not doubled
        f_odd, _ = amplitude_spectrum(np.ones(63), fs, detrend=False)
        assert f_odd.shape == (32,)

    def test_segments_average_to_the_tone_amplitude(self, synth):
        fs = 1024.0
        x = synth([(64.0, 1.5)], fs, 8.0, noise=0.01)
        f, a = amplitude_spectrum(x, fs, nperseg=1024)
        assert f[1] - f[0] == pytest.approx(1.0)
        assert a[np.argmin(np.abs(f - 64.0))] == pytest.approx(1.5, rel=0.01)

    def test_zero_padding_keeps_on_bin_amplitude(self, synth):
        fs = 1000.0
        x = synth([(100.0, 1.0)], fs, 1.0)
        f, a = amplitude_spectrum(x, fs, nfft=4000)
        assert f[1] == pytest.approx(0.25)
        assert a.max() == pytest.approx(1.0, rel=1e-9)

    def test_axis(self, synth):
        fs = 500.0
        cols = np.column_stack([synth([(50.0, a)], fs, 1.0) for a in (1.0, 3.0)])
        f, a = amplitude_spectrum(cols, fs, axis=0)
        assert a.shape == (f.size, 2)
        np.testing.assert_allclose(a.max(axis=0), [1.0, 3.0], rtol=1e-9)

    @pytest.mark.parametrize(
        ("x", "kwargs", "message"),
        [
            ([], {}, "empty"),
            ([1.0, np.nan, 2.0, 3.0], {}, "NaN or inf"),
            ([1.0, np.inf, 2.0, 3.0], {}, "NaN or inf"),
            (np.ones(16), {"fs": 0.0}, r"fs = 0\.0 is out of range \(allowed: > 0 Hz\)"),
            (np.ones(16), {"fs": -5.0}, r"fs = -5\.0 is out of range"),
            (np.ones(16), {"fs": "fast"}, "fs = 'fast' has the wrong type"),
            (np.ones(16), {"nperseg": 32}, r"nperseg = 32 is out of range \(allowed: <= 16"),
            (np.ones(16), {"nperseg": 8.0}, "nperseg = 8.0 has the wrong type"),
            (np.ones(16), {"nperseg": 8, "noverlap": 8}, "noverlap = 8 is out of range"),
            (np.ones(16), {"window": "nosuchwindow"}, "unknown window"),
            (np.ones(16), {"detrend": "quadratic"}, "detrend"),
        ],
    )
    def test_bad_input(self, x, kwargs, message):
        with pytest.raises(ValueError, match=message):
            amplitude_spectrum(x, **{"fs": 100.0, **kwargs})


class TestSpectralLines:
    @pytest.mark.parametrize("window", ["hann", "hamming", "blackman", "flattop"])
    def test_off_bin_lines_within_one_percent(self, synth, window):
        fs, duration = 2000.0, 1.2345  # not a whole number of periods of any line
        comps = [(37.3, 1.0, 0.4), (101.77, 0.2, -1.2), (333.3, 0.05, 2.5)]
        f, a, ph = spectral_lines(synth(comps, fs, duration), fs, window=window)
        assert f.size == 3
        for (fk, ak, phik), fi, ai, phi in zip(comps, f, a, ph, strict=True):
            assert fi == pytest.approx(fk, abs=0.01 * fs / (duration * fs))
            assert ai == pytest.approx(ak, rel=0.01)
            assert np.degrees(phik) == pytest.approx(phi, abs=1.0)

    @pytest.mark.parametrize("offset", [0.0, 0.1, 0.25, 0.4, 0.5, 0.6, 0.9])
    def test_worst_case_scalloping_is_corrected(self, synth, offset):
        fs, n = 1000.0, 1000
        f0 = (80 + offset) * fs / n
        f, a, _ = spectral_lines(synth([(f0, 1.0)], fs, n / fs, noise=1e-5), fs)
        assert f[np.argmax(a)] == pytest.approx(f0, abs=0.02)
        assert a.max() == pytest.approx(1.0, rel=0.01)

    def test_weak_lines_under_the_threshold_are_not_reported(self, synth):
        fs = 1000.0
        x = synth([(100.0, 1.0), (210.0, 0.002)], fs, 2.0, noise=0.01)
        f, _, _ = spectral_lines(x, fs)
        assert f.size == 1 and f[0] == pytest.approx(100.0, abs=0.05)

    def test_multichannel_is_refused(self):
        with pytest.raises(ValueError, match="one signal"):
            spectral_lines(np.random.default_rng(0).standard_normal((2, 100)), 100.0)
