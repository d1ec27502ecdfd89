"""Steps sized by error keep the default classifier's score.

The shipped classifier design (data/designs/rub_classifier_lhs300.toml, 300 runs) is made
twice: with the design's default ``step_error`` (long steps where nothing is in contact) and
with ``step_error = 0`` (every step 10 µs or shorter, as before). The default classifier —
``cross_validate(read_dataset(DATA))`` with every default, as README "Classifiers": target
``rub``, random forest, channels ``auto``, grouped by design point, ``seed = 0`` — must score
a macro-F1 on the new-defaults dataset inside the 95 % bootstrap interval of the 10-µs one.
Cheaper checks beside it: both datasets hold every run, all ``ok``; the rub label agrees for
at least 95 % of the runs (a run at the rub threshold may flip: the test prints how many);
the two datasets are not the same rows (the long steps were taken).

Both datasets take 10–20+ minutes each on 2 local workers. ``RUBDIAG_STEP_STUDY_DATA=DIR``
makes (or resumes, or reuses) them in ``DIR/default`` and ``DIR/step0`` instead of a
temporary folder, so the assertion can be rerun in a few minutes::

    RUBDIAG_STEP_STUDY_DATA=/tmp/step-study-classifier \\
        .venv/bin/python -m pytest -m slow tests/learn/test_step_defaults_classifier.py -q -s

Measured (2026-11-27, 2 local workers on 2 cores shared with other jobs, load 6–9):

* generation: new defaults 14.3 min (856 s; the runs' own wall times sum to 28.3 min,
  median 4.7 s a run), ``step_error = 0`` 21.6 min (1293 s; 42.9 min, median 7.8 s);
  300 of 300 runs ``ok`` in each;
* labels: ``rub`` the same in 300 of 300 runs (166 rub, 134 no rub in both), ``severity``
  the same in 300 of 300; the disc probe's ``rms`` moves by a median 1.3e-4 (at most
  5.5e-4) on runs without rub, a median 3e-5 (at most 1.3e-2) on rubbing runs;
* the default classifier (channels ``shaft11_y_disp``, ``shaft11_z_disp``): new defaults
  macro-F1 1.000 [1.000, 1.000] (every run right), 10 µs 0.993 [0.979, 1.000] (2 of 166
  rubbing runs called no rub) — inside, at the top of the interval. A rerun on the
  stored datasets takes about a minute.

``run_id`` and ``point_id`` hash the run, ``step_error`` included, so ``read_dataset`` puts
the two datasets' rows in different orders and their folds differ: the two scores differ
by the draw of the folds as well as by the steps.
"""

from __future__ import annotations

import os
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[2]
DESIGN = ROOT / "data" / "designs" / "rub_classifier_lhs300.toml"
STUDY_ENV = "RUBDIAG_STEP_STUDY_DATA"
JOBS = 2
MIN_LABEL_AGREEMENT = 0.95
KEY = ["point_id", "replicate"]
FACTORS = ["case", "speed_ratio", "gap_mm", "mu", "unbalance_scale", "replicate"]


def _make(design, out: Path, name: str) -> None:
    from rubdiag.dataset import generate

    summary = generate(design, out, jobs=JOBS, progress=False)
    print(f"\n{name}: {summary['total']} runs, {summary['stored_before']} stored before, "
          f"{summary['run']} run now in {summary['wall_s']:.0f} s "
          f"({summary['wall_s'] / 60:.1f} min, {JOBS} workers), {summary['failed']} failed")


@pytest.mark.slow
def test_new_step_defaults_keep_the_default_classifiers_score(tmp_path):
    from rubdiag.dataset import Design, load
    from rubdiag.dataset._design import DEFAULT_STEP_ERROR
    from rubdiag.learn import cross_validate, read_dataset

    root = Path(os.environ.get(STUDY_ENV) or tmp_path)
    design = Design.from_toml(DESIGN)
    assert design.step_error == DEFAULT_STEP_ERROR > 0      # the shipped design's default
    made = {"default": design, "step0": replace(design, step_error=0.0)}
    for name, d in made.items():
        _make(d, root / name, name)
        # a reused folder is the design it claims (generate refuses another design's folder)
        assert Design.from_toml(root / name / "design.toml").step_error == d.step_error

    # run_id and point_id hash the run, step_error included: the two datasets' runs are
    # paired by their place in the design (the same sampling), and their factors must agree
    rows = {}
    for name, d in made.items():
        place = {item.run_id: i for i, item in enumerate(d.runs())}
        r = load(root / name)
        rows[name] = r.assign(place=r["run_id"].map(place)).sort_values("place")
    n_runs = len(design.runs())
    for name, r in rows.items():
        assert len(r) == n_runs and r["place"].tolist() == list(range(n_runs)), name
        assert (r["status"] == "ok").all(), (name, r.loc[r["status"] != "ok", KEY])
    new, old = rows["default"], rows["step0"]
    np.testing.assert_array_equal(new[FACTORS].to_numpy(), old[FACTORS].to_numpy())

    # labels: the same for nearly every run; a run at the rub threshold may flip
    agree = {}
    for label in ("rub", "severity"):
        same = new[label].to_numpy() == old[label].to_numpy()
        agree[label] = int(same.sum())
        print(f"{label}: same in {same.sum()} of {n_runs} runs; differs in "
              f"{(~same).sum()}: {new.loc[~same, FACTORS].to_dict('records')} "
              f"(new {new.loc[~same, label].tolist()}, 10 us {old.loc[~same, label].tolist()})")
    print(f"rub: {int(new['rub'].sum())} with new defaults, {int(old['rub'].sum())} at 10 us")

    # the long steps were taken: the rows are not the 10-µs rows
    level = "shaft11_y_disp__rms"
    assert not np.array_equal(new[level].to_numpy(), old[level].to_numpy())

    scores = {}
    for name in made:
        ev = cross_validate(read_dataset(root / name))      # the default classifier (README)
        scores[name] = ev.scores["macro_f1"]
        print(f"{name}: macro-F1 {scores[name]} ({ev.class_counts}, unscored "
              f"{ev.unscored}, channels {ev.channels}, confusion "
              f"{ev.confusion.to_numpy().tolist()})")

    assert agree["rub"] >= MIN_LABEL_AGREEMENT * n_runs, agree
    f1, ref = scores["default"], scores["step0"]
    assert ref.lo <= f1.value <= ref.hi, (f"new defaults {f1} outside the 10-us dataset's "
                                          f"interval {ref}")
