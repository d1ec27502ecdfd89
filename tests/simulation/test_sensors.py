"""Sensors (rubdiag.simulation._sensors): the anti-aliasing filter does what the docs say,
velocity and acceleration are the integrator's and match the steady harmonic response,
reactions are the bearing's k u + c v, and bad sensors are refused by name."""

from __future__ import annotations

import re

import numpy as np
import pytest

from rubdiag.assembly import assemble
from rubdiag.modal import harmonic_response, with_rayleigh
from rubdiag.model import paper_rig
from rubdiag.simulation import Run, Sensor, default_sensors, load_result, simulate
from rubdiag.simulation import _sensors as S

FS_IN, FACTOR = 100_000.0, 10          # dt = 10 µs streamed, 10 kHz out
NYQUIST_OUT = FS_IN / FACTOR / 2


def _tone(f_hz: float, seconds: float = 0.2) -> np.ndarray:
    t = np.arange(round(seconds * FS_IN) + 1) / FS_IN
    return np.cos(2 * np.pi * f_hz * t)


def _middle(x: np.ndarray) -> np.ndarray:
    """Away from the filter's edge transient."""
    return x[len(x) // 5: -len(x) // 5]


@pytest.mark.parametrize("f_hz", [95.0, 760.0, 2500.0, 0.65 * NYQUIST_OUT])
def test_passband_is_flat_to_two_hundredths_of_a_percent(f_hz):
    out = S.decimate(_tone(f_hz), FACTOR)
    expected = _tone(f_hz)[::FACTOR]
    assert out.shape == expected.shape
    # zero phase: sample k is the tone at t = k / fs_out, not delayed
    assert np.max(np.abs(_middle(out) - _middle(expected))) <= 2e-4


@pytest.mark.parametrize("f_hz", [NYQUIST_OUT, 7000.0, 9900.0, 13_000.0, 45_000.0])
def test_at_and_above_the_output_nyquist_is_attenuated_by_80_db(f_hz):
    """Without the filter these tones would alias at full amplitude (9900 Hz onto 100 Hz)."""
    out = S.decimate(_tone(f_hz), FACTOR)
    assert np.max(np.abs(_middle(out))) <= 10 ** (-80 / 20)
    aliased = _tone(f_hz + 1.0)[::FACTOR]           # plain sampling, for contrast
    assert np.max(np.abs(_middle(aliased))) > 0.5


def test_docstring_states_the_filter_used():
    doc = S.__doc__
    assert f"β = {S.KAISER_BETA:g}" in doc and f"{S.TAPS_PER_FACTOR}·q + 1 taps" in doc
    assert f"{S.CUTOFF_OF_NYQUIST:g} × the output Nyquist" in doc


@pytest.fixture(scope="module")
def quiet():
    """Case 2 at a gap nothing reaches: the linear steady state, every sensor kind."""
    rig = paper_rig()
    sensors = (*default_sensors(rig), Sensor("shaft 11", "y", "velocity"),
               Sensor("shaft 11", "y", "acceleration"), Sensor("shaft 4", "y", "velocity"),
               Sensor("shaft 4", "y", "reaction"), Sensor("shaft 26", "z", "reaction"),
               Sensor("shaft 26", "z", "velocity"))
    return simulate(Run.paper_case(2, 4.0, duration_s=0.2, discard_s=0.1, sensors=sensors))


def test_velocity_and_acceleration_are_the_harmonic_response_derivatives(quiet):
    """From the linear steady state with no contact the response stays u(t) = Re(U e^{iΩt}):
    v = Re(iΩ U e^{iΩt}), a = Re(-Ω² U e^{iΩt}). Newmark's period error (Ωdt)²/12 ≈ 3e-6
    and the filter's passband (2e-4) bound the difference, away from the filter's edge
    transient in the last 2 ms."""
    run = quiet.run
    model = with_rayleigh(assemble(run.rig))
    linear = harmonic_response(model, run.speed_rad_s, run.unbalance)
    k = model.dofs.index("shaft 11", "y")
    U, w = linear.amplitudes[k], run.speed_rad_s
    phase = np.exp(1j * w * quiet.t)
    sig = quiet.sensor_signals()
    window = quiet.window & (quiet.t <= quiet.t[-1] - 2e-3)
    for name, expected in (("shaft11_y_disp", U * phase), ("shaft11_y_vel", 1j * w * U * phase),
                           ("shaft11_y_acc", -(w**2) * U * phase)):
        scale = np.max(np.abs(expected.real))
        err = np.max(np.abs(sig[name][window] - expected.real[window])) / scale
        assert err <= 1e-3, (name, err)


def test_reaction_is_the_bearing_spring_and_damper(quiet):
    sig = quiet.sensor_signals()
    brg = {b.node: b for b in quiet.run.rig.bearings}
    np.testing.assert_allclose(
        sig["shaft4_y_force"],
        brg[4].k_y_n_m * sig["shaft4_y_disp"] + brg[4].c_y_ns_m * sig["shaft4_y_vel"],
        rtol=1e-12, atol=1e-12 * np.max(np.abs(sig["shaft4_y_force"])))
    np.testing.assert_allclose(
        sig["shaft26_z_force"],
        brg[26].k_z_n_m * sig["shaft26_z_disp"] + brg[26].c_z_ns_m * sig["shaft26_z_vel"],
        rtol=1e-12, atol=1e-12 * np.max(np.abs(sig["shaft26_z_force"])))
    assert np.max(np.abs(sig["shaft4_y_force"])) > 1.0     # newtons, not zero


def test_the_casing_is_silent_without_rub_and_loud_with_it(quiet):
    assert not np.any(quiet.sensor_signals()["casing1_y_acc"])
    rubbing = simulate(Run.paper_case(2, 1.9, duration_s=0.2, discard_s=0.1,
                                      sensors=default_sensors(paper_rig())))
    assert np.max(np.abs(rubbing.sensor_signals(windowed=True)["casing1_y_acc"])) > 10.0


def test_sensor_signals_survive_save_and_load(quiet, tmp_path):
    again = load_result(quiet.save(tmp_path / "quiet.npz"))
    assert again.run.sensors == quiet.run.sensors
    for name, values in quiet.sensor_signals().items():
        np.testing.assert_array_equal(again.sensor_signals()[name], values)


@pytest.mark.parametrize(("sensor", "fragment"), [
    (dict(point="shaft 99", direction="y"), "no DOF ('shaft 99', 'y') in rig 'paper rig"),
    (dict(point="casing 41", direction="z"), "no DOF ('casing 41', 'z')"),
    (dict(point="shaft 11", direction="y", quantity="reaction"),
     "a reaction needs a bearing node (allowed: shaft 4, shaft 26)"),
])
def test_a_sensor_the_rig_does_not_have_is_refused(sensor, fragment):
    with pytest.raises(ValueError, match=re.escape(fragment)):
        Run.paper_case(1, 2.3, sensors=(Sensor(**sensor),))


@pytest.mark.parametrize(("kwargs", "fragment"), [
    (dict(point="shaft 4", direction="x"), "sensor.direction = 'x' is not allowed"),
    (dict(point="shaft 4", direction="y", quantity="strain"), "sensor.quantity = 'strain'"),
    (dict(point="shaft 4", direction="y", name="a__b"), "sensor.name = 'a__b' is not allowed"),
])
def test_bad_sensor_fields_are_refused(kwargs, fragment):
    with pytest.raises(ValueError, match=re.escape(fragment)):
        Sensor(**kwargs)


def test_sensor_names_are_unique():
    with pytest.raises(ValueError, match="sensor name 'shaft4_y_disp' is given twice"):
        Run.paper_case(1, 2.3, sensors=(Sensor("shaft 4", "y"), Sensor("shaft 4", "y")))


@pytest.mark.parametrize("factor", [2, 3, 10])
@pytest.mark.parametrize("n", [0, 1, 2, 3, 11, 401, 4001, 23_007])
def test_decimation_has_the_bits_of_scipy_resample_poly(factor, n):
    """rubdiag.simulation._decimation sums the same products in the same order as scipy's
    resample_poly (line-extended ends), only many output samples at once."""
    from scipy.signal import resample_poly

    rng = np.random.default_rng(n + factor)
    x = np.cumsum(rng.standard_normal((n, 7)), axis=0) * 1e-6 + 3e-5
    with np.errstate(invalid="ignore"):         # one sample: scipy's line is 0 / 0
        expected = resample_poly(x, 1, factor, axis=0, window=S.anti_alias_taps(factor),
                                 padtype="line")
    got, one = S.decimate(x, factor), S.decimate(x[:, 3], factor)
    assert got.shape == expected.shape and one.shape == expected[:, 3].shape
    if n < 2:                                   # NaN (of either sign) or nothing
        np.testing.assert_array_equal(got, expected)
        return
    assert got.tobytes() == np.ascontiguousarray(expected).tobytes()
    assert one.tobytes() == np.ascontiguousarray(expected[:, 3]).tobytes()
