"""Each workflow of rubdiag done with top-level names only: ``import rubdiag`` and
``rubdiag.<name>`` for names in ``rubdiag.__all__``, nothing else of rubdiag
(tests/test_public_api.py checks that, runs this file and reads what it prints).

Run: python tests/api_walk.py WORK_FOLDER
"""

import json
import sys
from pathlib import Path

import numpy as np
import pandas as pd

import rubdiag

work = Path(sys.argv[1])
report = {}

# a rig and its linear behaviour: the paper rig's first forward critical speed
rig = rubdiag.paper_rig()
model = rubdiag.assemble(rig)
report["first_critical_rpm"] = float(rubdiag.critical_speeds(model, n=1)[0] * 60 / (2 * np.pi))

# features of a measured signal: a 2 um 1x with 0.7 um at 3x, at 1500 rpm
fs = 2000.0
t = np.arange(8000) / fs
x = 2e-6 * np.cos(2 * np.pi * 25 * t) + 0.7e-6 * np.cos(2 * np.pi * 75 * t)
row = rubdiag.signal_features(x, fs, speed_rpm=1500).iloc[0]
report["signal_1x_um"], report["signal_3x_um"] = row["amp_1x"] * 1e6, row["amp_3x"] * 1e6

# features of a probe pair: a forward 1x of 1.0 with a reverse 2x of 0.2
w = 2 * np.pi * 25 * t
orbit = rubdiag.orbit_features(np.cos(w) + 0.2 * np.cos(2 * w), np.sin(w) - 0.2 * np.sin(2 * w),
                               fs, 1500)
report["orbit_fwd_1x"], report["orbit_rev_2x"] = orbit["fwd_1x"], orbit["rev_2x"]

# a labelled dataset: the study's case 2 around its critical speed, gaps with and without rub
design = rubdiag.Design.from_toml("""
[base]
rig = "paper"
duration_s = 0.75
discard_s = 0.25
reduced = true
[sampling]
method = "grid"
[factors]
case = [1, 2]
speed_ratio = [0.9, 1.0]
gap_mm = [0.7, 1.6, 3.5]
""")
summary = rubdiag.generate(design, work / "dataset", jobs=2, progress=False)
data = rubdiag.load(work / "dataset")
report["runs"], report["rub_runs"] = int(summary["ok"]), int(data["rub"].astype(bool).sum())

# a run simulated alone, and its features
run = rubdiag.Run.paper_case(2, gap_mm=0.7, duration_s=0.75, discard_s=0.25)
result = rubdiag.simulate(run)
features = rubdiag.run_features(result).iloc[0]
report["run_rub_episodes"] = int(result.summary()["n_episodes"])
report["run_shaft_1x_um"] = float(features["shaft_amp_1x"] * 1e6)

# classifiers: trained, scored on its own dataset, used on a plant's record
model = rubdiag.train(work / "dataset", work / "model", target="rub", n_splits=3,
                      baselines=False, audit=False, n_repeats=1, seed=0)
scores = rubdiag.evaluate(work / "model", work / "dataset", n_bootstrap=50)
report["in_sample"] = bool(scores.shared_runs)
channels = {"shaft11_y_disp": result.displacement("shaft 11 y", windowed=True),
            "shaft11_z_disp": result.displacement("shaft 11 z", windowed=True)}
csv = work / "record.csv"
pd.DataFrame({c: v for c, v in channels.items() if c in model.channels}).assign(
    t=np.arange(len(channels["shaft11_y_disp"])) / result.fs).to_csv(csv, index=False)
table = rubdiag.predict(work / "model", csv, units=dict.fromkeys(model.channels, "m"),
                        speed_rpm=run.speed_rpm)
report["predicted"] = sorted(set(table["predicted"].astype(str)))

print(json.dumps(report))
