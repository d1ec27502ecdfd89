"""Rig presets: ``paper`` is the study's rig, ``paper-pedestal`` the same rig with its drive-end
bearing on a pedestal, whose rotor modes stay where they were."""

from __future__ import annotations

import math
import subprocess
import sys

import numpy as np
import pytest

from rubdiag.model import PRESETS, paper_rig, preset_rig
from rubdiag.simulate.rig_cache import forward_critical_speeds


def test_paper_is_the_study_rig():
    assert preset_rig("paper") == paper_rig()


def test_an_unknown_preset_is_refused_with_the_list():
    with pytest.raises(ValueError, match=r"rig.*paper, paper-pedestal"):
        preset_rig("papr")


def test_the_pedestal_rig_differs_only_by_its_pedestal():
    base, rig = paper_rig(), preset_rig("paper-pedestal")
    assert rig.bearings[0].pedestal is not None and rig.bearings[1].pedestal is None
    assert rig.shaft == base.shaft and rig.discs == base.discs and rig.casing == base.casing
    assert rig.bearings[0].k_y_n_m == base.bearings[0].k_y_n_m


def test_the_pedestal_leaves_the_rotor_critical_speeds_within_a_tenth_of_a_percent():
    """The preset's docstring promises the rotor's criticals move by under 0.1 %: a pedestal
    of 20 kg on 20 MN/m (its own frequency sqrt(k/m)/2pi = 159 Hz with the shaft held, above
    the rotor's first two modes, 25 and 94.5 Hz at rest)."""
    base = np.asarray(forward_critical_speeds(paper_rig(), 2))
    moved = np.asarray(forward_critical_speeds(preset_rig("paper-pedestal"), 2))
    assert np.all(np.abs(moved / base - 1.0) < 1e-3)
    assert not np.allclose(moved, base, rtol=1e-9, atol=0.0)     # the pedestal is in the model


@pytest.mark.parametrize("name", list(PRESETS))
def test_the_cli_takes_a_preset_name_for_rig(name):
    command = [sys.executable, "-m", "rubdiag", "modal", "--rig", name, "--n-modes", "2"]
    out = subprocess.run(command, capture_output=True, text=True, timeout=300)
    assert out.returncode == 0, out.stderr
    first = forward_critical_speeds(preset_rig(name), 1)[0] * 30.0 / math.pi
    assert f"{first:.1f}" in out.stdout


def test_the_cli_names_the_presets_for_a_missing_rig():
    out = subprocess.run([sys.executable, "-m", "rubdiag", "modal", "--rig", "nothing-here"],
                         capture_output=True, text=True, timeout=300)
    assert out.returncode == 2 and "Traceback" not in out.stderr
    assert "paper-pedestal" in out.stderr and len(out.stderr.strip().splitlines()) == 1
