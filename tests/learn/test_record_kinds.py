"""The per-kind scores of a rub model name what rubbed when the design says (its
``rub_kind`` factor): a seal rub is scored apart from a blade rub, and a run that did not rub
keeps its own kind whatever its design point."""

import numpy as np
import pandas as pd

from rubdiag.learn._train import record_kinds


def test_rubs_are_split_by_what_rubbed():
    rows = pd.DataFrame({"faults": ["none", "rub", "rub+crack", "rub", "crack", "none"],
                         "rub_kind": [None, "seal", "blade", "blade", None, "seal"]})
    kinds, rubbing = record_kinds(rows, "rub")
    # the last run was designed to rub on its seal but did not: it is a run without rub
    assert kinds.tolist() == ["none", "rub (seal)", "rub+crack (blade)", "rub (blade)",
                              "crack", "none"]
    assert rubbing.tolist() == [False, True, True, True, False, False]


def test_without_the_factor_kinds_are_the_fault_labels():
    rows = pd.DataFrame({"faults": ["none", "rub"]})
    kinds, rubbing = record_kinds(rows, "rub")
    assert kinds.tolist() == ["none", "rub"] and rubbing.tolist() == [False, True]
    assert record_kinds(rows.assign(rub=[False, True]).drop(columns="faults"),
                        "severity") is None
    only_rub = pd.DataFrame({"rub": [True, False]}, index=[7, 9])
    assert record_kinds(only_rub, "rub")[0].tolist() == ["rub", "none"]
    assert np.asarray(record_kinds(only_rub, "rub")[1]).tolist() == [True, False]
