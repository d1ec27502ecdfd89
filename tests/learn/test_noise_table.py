"""The noise-robustness table (scripts/noise_table.py, data/noise_curve.csv): the
documentation shows what the CSV holds, each level's added noise is the σ its SNR asks for
(σ² = P_ref 10^(-SNR/10): one level 10 dB below another adds √10 times the σ), every score
lies inside its interval, and both curves start from the same stored features."""

import numpy as np
import pandas as pd
import pytest
from docs_tables import table
from scripts_loader import load_script

script = load_script("noise_table")
ROWS = pd.read_csv(script.CSV)


def test_the_documented_table_is_the_csv():
    assert table("noise-curve") == script.table(ROWS) + "\n"


@pytest.mark.parametrize("how", list(script.TRAIN_ON))
def test_each_level_adds_the_sigma_its_snr_asks_for(how):
    part = ROWS[(ROWS["train_on"] == how) & np.isfinite(ROWS["snr_db"])]
    assert list(part["snr_db"]) == list(script.SNR_DB)
    sigma = part[[c for c in ROWS.columns if c.endswith("__noise_std")]].to_numpy()
    snr = part["snr_db"].to_numpy()
    expected = 10.0 ** (-(snr[:, None] - snr[0]) / 20.0) * sigma[0]
    np.testing.assert_allclose(sigma, expected, rtol=2e-5)       # the CSV's 6 digits


def test_scores_lie_inside_their_intervals_and_start_alike():
    assert (ROWS["macro_f1_lo"] <= ROWS["macro_f1"] + 1e-6).all()
    assert (ROWS["macro_f1"] <= ROWS["macro_f1_hi"] + 1e-6).all()
    stored = ROWS[np.isinf(ROWS["snr_db"])].set_index("train_on")
    # without added noise both ways of training see the same features and folds
    assert stored.loc["noisy", "macro_f1"] == stored.loc["stored", "macro_f1"]
