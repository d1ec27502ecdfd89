"""Oil whirl from the response, not from the design: at one speed, the rig variant whose
threshold of instability lies below it whirls and the one whose threshold lies above it
does not, and the rows say so (``faults``) while their design level (``fault``) is the
same. This is how data/designs/faults_bands.toml gets its whirl runs: no level has whirl,
and in case 2 around the second critical speed the damping, disc mass and film factors
move the threshold across the band (from 0.78 to 1.36 of the critical speed over the rig
variants).

Muszynska (2005, "Rotordynamics", the chapters on fluid-induced instabilities) and Bently
& Hatch (2002): above the threshold the journal precesses forward at a sub-synchronous
frequency (whirl near 0.4-0.48x, or whip locked to the first natural frequency); below it
the linear rotor shows none.
"""

from __future__ import annotations

import math

import pytest

from rubdiag.dataset import Design
from rubdiag.dataset._faults import whirl_threshold_rad_s
from rubdiag.dataset._rig_factors import varied_rig
from rubdiag.dataset._rows import make_row

# the nominal second critical speed of paper-journal: 4474 rpm
TOML = """
[base]
rig = "paper-journal"
duration_s = 2.5
discard_s = 1.2
reduced = true
gravity_m_s2 = 9.81
[sampling]
method = "grid"
[factors]
case = [2]
speed_rpm = [4474.0]
fault = ["none"]
damping_ratio = [0.03, 0.05]
"""


@pytest.fixture(scope="module")
def rows():
    design = Design.from_toml(TOML)
    return {item.point["damping_ratio"]: (item, make_row(item)) for item in design.runs()}


def test_the_thresholds_lie_on_either_side_of_the_speed(rows):
    for damping, (item, _) in rows.items():
        threshold_rpm = whirl_threshold_rad_s(item.run.rig) * 30.0 / math.pi
        assert item.run.rig == varied_rig(Design.from_toml(TOML).rig,
                                          {"damping_ratio": damping})
        # 3811 rpm at 0.03, 5033 rpm at 0.05
        assert (threshold_rpm < 4474.0) == (damping == 0.03)


def test_the_variant_above_its_threshold_whirls_and_its_row_says_so(rows):
    _, unstable = rows[0.03]
    _, stable = rows[0.05]
    assert unstable["fault"] == stable["fault"] == "none"      # the design level
    assert unstable["faults"] == "whirl" and unstable["fault_whirl"]
    assert stable["faults"] == "none" and not stable["fault_whirl"]
    assert unstable["subsync_share"] >= 0.25 > 0.01 > stable["subsync_share"]


def test_the_whirl_precesses_forward_below_the_speed(rows):
    """The disc's full spectrum: the largest sub-synchronous line is forward."""
    _, row = rows[0.03]
    orders = ("0p33x", "0p5x", "0p67x")
    forward = max(row[f"shaft11_yz_disp__fwd_{k}"] for k in orders)
    reverse = max(row[f"shaft11_yz_disp__rev_{k}"] for k in orders)
    assert forward > 2 * reverse
