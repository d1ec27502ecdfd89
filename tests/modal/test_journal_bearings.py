"""The linear analysis of a rotor on plain journal bearings: the films'
speed-dependent, cross-coupled coefficients in the modes, the unbalance response, the
critical speed map and the threshold of instability.

The test rotor (tests/journal_rig.py): a practically rigid shaft with a 20 kg disc at
mid-span on two identical short bearings, each carrying 98.1 N. Its cylindrical mode is the rigid
rotor of half the mass on one bearing, whose threshold the film's own 2-DOF linearisation
gives (the same as tests/simulation/test_journal_bearing.py: 1122.45 rad/s).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from journal_rig import FILM, LOAD, MASS, rig
from scipy.optimize import brentq

from rubdiag import _fluidfilm as ff
from rubdiag.assembly import assemble
from rubdiag.modal import (
    critical_speeds,
    direct_film_stiffness,
    harmonic_response,
    modes,
    stability_threshold,
)
from rubdiag.model import Bearing, JournalFilm, Rig


def rigid_growth(omega: float) -> complex:
    """The rightmost root of half the rotor on one bearing (2 DOF, the film linearised)."""
    K, C, _ = ff.linearised_coefficients(LOAD, omega, FILM["viscosity_pa_s"], FILM["radius_m"],
                                         FILM["length_m"], FILM["clearance_m"], (-1.0, 0.0))
    half = MASS / 2
    A = np.block([[np.zeros((2, 2)), np.eye(2)], [-K / half, -C / half]])
    lam = np.linalg.eigvals(A)
    return lam[np.argmax(lam.real)]


def test_a_journal_bearing_needs_zero_springs_and_a_valid_film():
    film = JournalFilm(**FILM, load_n=LOAD)
    with pytest.raises(ValueError, match=r"Bearing.k_y_n_m = .*0 for a journal bearing"):
        Bearing(0, 1e6, 0.0, journal=film)
    with pytest.raises(ValueError, match=r"JournalFilm.clearance_m"):
        JournalFilm(**{**FILM, "clearance_m": 0.05}, load_n=LOAD)
    with pytest.raises(ValueError, match=r"JournalFilm.load_direction"):
        JournalFilm(**FILM, load_n=LOAD, load_direction="down")
    assert JournalFilm(**FILM, load_n=LOAD, load_direction="+z").load_vector == (0.0, 1.0)


def test_the_rig_file_round_trips_the_film(tmp_path):
    from rubdiag.model import load_rig, save_rig

    path = save_rig(rig(), tmp_path / "journal.toml")
    assert "[bearings.journal]" in path.read_text() and load_rig(path) == rig()


def test_the_bearing_matrices_are_the_film_s_coefficients_at_each_bearing():
    model = assemble(rig())
    Kb, Cb = model.bearing_matrices(800.0)
    K2, C2, _ = ff.linearised_coefficients(LOAD, 800.0, *FILM.values(), (-1.0, 0.0))
    for node in (0, 6):
        idx = [model.dofs.index(node, "y"), model.dofs.index(node, "z")]
        np.testing.assert_array_equal(Kb[np.ix_(idx, idx)].toarray(), K2)
        np.testing.assert_array_equal(Cb[np.ix_(idx, idx)].toarray(), C2)
    assert Kb.nnz == 8 and not np.allclose(K2, K2.T)      # cross-coupled, non-symmetric
    with pytest.raises(ValueError, match=r"speed = 0\.0"):
        model.bearing_matrices(0.0)


def test_the_threshold_of_the_rigid_rotor_is_the_film_s():
    """The stiff rotor's cylindrical mode turns unstable where half the rotor on one
    linearised bearing does, to the shaft's flexibility (the film's stiffness over the
    shaft's is about 1e-4; measured 2.4e-4 lower)."""
    rigid = brentq(lambda w: rigid_growth(w).real, 300.0, 3000.0, xtol=1e-9)
    found = stability_threshold(assemble(rig()), 300.0, 3000.0)
    assert found.speed_rad_s == pytest.approx(rigid, rel=5e-4)
    assert found.frequency_rad_s == pytest.approx(abs(rigid_growth(rigid).imag), rel=1e-3)
    assert 0.45 < found.whirl_ratio < 0.55
    below = modes(assemble(rig()), 0.95 * rigid, n_modes=4)
    above = modes(assemble(rig()), 1.05 * rigid, n_modes=4)
    assert below.damping_ratios.min() > 0.0 > above.damping_ratios.min()


def test_the_unbalance_response_uses_the_films():
    """At a speed the response of the model equals the solve with K + K_b, C + C_b written
    out here."""
    model = assemble(rig(stiff=False))
    speed = 600.0
    response = harmonic_response(model, speed, model.rig.unbalance(1)).amplitudes
    Kb, Cb = model.bearing_matrices(speed)
    Z = (model.K + Kb - speed**2 * model.M
         + 1j * speed * (model.C + Cb + speed * model.G)).toarray()
    expected = np.linalg.solve(Z, model.unbalance_force(model.rig.unbalance(1), speed))
    np.testing.assert_allclose(response, expected, rtol=1e-9, atol=1e-12 * abs(expected).max())


def test_the_critical_speed_map_is_a_fixed_point():
    """The flexible rotor's first forward critical speed Ω₁ is the first synchronous
    solution with the films' direct stiffness at Ω₁ itself."""
    from rubdiag.modal import synchronous_modes

    model = assemble(rig(stiff=False))
    first = critical_speeds(model, n=1)[0]
    again = synchronous_modes(model, 12, direct_film_stiffness(model, first)).forward[0]
    assert again == pytest.approx(first, rel=1e-9)
    # the films soften the rotor below its rigid-bearing critical speed
    rigid = Rig(**{**rig(stiff=False).__dict__,
                   "bearings": (Bearing(0, 1e13, 1e13), Bearing(6, 1e13, 1e13))})
    assert first < critical_speeds(assemble(rigid), n=1)[0]
    assert math.isfinite(first)


def test_rubdiag_modal_says_what_journal_bearings_change(tmp_path, capsys):
    import json

    from rubdiag.cli import main
    from rubdiag.model import save_rig

    path = save_rig(rig(), tmp_path / "journal.toml")
    assert main(["modal", "--rig", str(path)]) == 0
    text = capsys.readouterr().out
    assert "2 plain journal bearing(s), speed-dependent and cross-coupled" in text
    assert "threshold of instability:" in text and "natural frequencies at " in text
    assert main(["modal", "--rig", str(path), "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    found = stability_threshold(assemble(rig()), 0.05 * out["critical_speeds_rad_s"][0],
                                4.0 * out["critical_speeds_rad_s"][-1])
    assert out["journal_bearings"] == 2
    assert out["stability_threshold_rpm"] == pytest.approx(found.speed_rad_s * 30 / math.pi)
    assert main(["campbell", "--rig", str(path), "--out", str(tmp_path), "--n-speeds",
                 "5", "--max-speed-rpm", "20000"]) == 0
    assert "journal bearing(s): the films' speed-dependent" in capsys.readouterr().err
    import pandas as pd

    table = pd.read_csv(tmp_path / "campbell.csv")      # 5 speeds from 20000 / 5 rpm
    assert table["speed_rpm"].min() == pytest.approx(4000.0)
