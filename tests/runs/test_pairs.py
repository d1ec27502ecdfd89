"""The probe pairs of a simulated run: the full spectrum of a linear run
against its harmonic response written out here.

For y = Re(Y e^{iΩt}) and z = Re(Z e^{iΩt}), the complex y + i z is (Y + iZ)/2 e^{iΩt} plus
the conjugate of (Y − iZ)/2 at −Ω: its 1× is forward |Y + iZ|/2 and reverse |Y − iZ|/2.
"""

from __future__ import annotations

import numpy as np
import pytest

from rubdiag.modal import harmonic_response
from rubdiag.runs import recorded_pairs, run_orbit_features
from rubdiag.simulation import Run, simulate
from rubdiag.simulation._rig_cache import damped_model


@pytest.fixture(scope="module")
def linear():
    """Case 1 at 1200 rpm, the casing out of reach: the unbalance's steady orbit."""
    return simulate(Run.paper_case(1, 50.0, speed_rpm=1200.0, duration_s=0.6, discard_s=0.1,
                                   gap_ramp_s=0.0))


def test_every_recorded_node_with_y_and_z_is_a_pair(linear):
    assert recorded_pairs(linear) == ("shaft 11", "shaft 19", "casing 1", "blade 1.4")


def test_a_linear_run_s_1x_is_its_harmonic_response_s_forward_and_reverse(linear):
    """The paper rig's bearings are stiffer in y (500 MN/m) than in z (200): its disc orbits
    are nearly circular, forward at 1200 rpm (reverse 7e-5 of forward). Measured: forward
    equal to the harmonic response's to 5e-7, reverse to 4e-5."""
    rows = run_orbit_features(linear).set_index("pair")
    model = damped_model(linear.run.rig)
    response = harmonic_response(model, linear.run.speed_rad_s, linear.run.unbalance)
    for node in ("shaft 11", "shaft 19"):
        Y, Z = response.amplitude(node, "y"), response.amplitude(node, "z")
        forward, reverse = abs(Y + 1j * Z) / 2, abs(Y - 1j * Z) / 2
        assert rows.loc[node, "fwd_1x"] == pytest.approx(forward, rel=1e-4)
        assert rows.loc[node, "rev_1x"] == pytest.approx(reverse, rel=1e-3)
        assert rows.loc[node, "precession_1x"] == 1
        assert rows.loc[node, "ellipticity_1x"] == pytest.approx(reverse / forward, abs=1e-3)
    assert np.isfinite(rows["flattening"]).all()
