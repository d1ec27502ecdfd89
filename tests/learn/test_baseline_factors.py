"""The design-factors baseline reads only the conditions every run shows: a factor blank by
design for some level is left out, and so is, in a design with a fault factor, the
``interference_ratio`` column, which holds the run's measured ratio — about 0.001 where the
casing was out of reach, 1.2 and up where the design made the run rub: an oracle for rub."""

import numpy as np
import pandas as pd

from rubdiag.learn._controls import baseline_factors


def rows(**extra):
    return pd.DataFrame({"speed_ratio": [0.5, 0.52, 0.95, 1.0],
                         "interference_ratio": [0.0011, 0.0008, 2.1, 1.5],
                         "crack_depth_ratio": [np.nan, 0.3, np.nan, np.nan], **extra})


def test_a_measured_ratio_is_left_out_beside_faults():
    read, left_out = baseline_factors(rows(faults=["none", "crack", "rub", "rub"]))
    assert read == ["speed_ratio"]
    assert left_out == ["interference_ratio", "crack_depth_ratio"]


def test_where_every_run_rubs_the_ratio_is_a_condition():
    read, left_out = baseline_factors(rows())
    assert read == ["speed_ratio", "interference_ratio"]
    assert left_out == ["crack_depth_ratio"]
