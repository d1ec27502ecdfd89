#!/usr/bin/env python
"""Sensitivity of the Table 2 reproduction to the choices the study leaves open.

One knob at a time around the default (the paper rig preset: mu = 0.4, pure penalty,
distributed casing support; dt = 1e-5 s, 2.3 s simulated with the first 0.3 s discarded),
every setting runs all four Table 2 cases through :func:`rubdiag.paper._table2`
(``figures=False``):

=============================  =====================================================
knob                           values
=============================  =====================================================
``mu``                         0.1, 0.2, 0.3, **0.4**, 0.5
``augmentation``               **off**; on with eps = 50, 20, 10 µm
``casing_support``             **distributed**, point (the support node opposite
                               contact 1, rubdiag's default for a point support)
``dt``                         2e-5, **1e-5**, 5e-6 s (largest step; the variable
                               step never halves it on the paper rig)
``window``                     1.3, **2.3**, 4.3 s simulated (0.3 s discarded); and
                               4.3 s with 2.3 s discarded (the default 2 s window,
                               but late)
``gap_ramp (noise floor)``     gap ramp 0.098 … **0.1** … 0.102 s at mu = 0.4: the
                               same machine, another start-up history; the rub is
                               chaotic, so this gives the spread that any knob's
                               effect must exceed to mean something
``gap_ramp at μ = 0.3``        the same five ramps at mu = 0.3 (BladeContact's
                               generic default and the previous centre of the sweep)
=============================  =====================================================

(bold: the default.)

Rows (one per setting and case) go to ``DIR/sensitivity.parquet`` and ``DIR/sensitivity.csv``,
rewritten atomically after every setting; a rerun skips the settings already there (with the
same duration and discard), so an interrupted sweep resumes. A setting whose ``table2`` call
raises is retried case by case, so that the cases that do run are kept and the failing one is
recorded with its message (``status`` = ``diverged`` / ``failed``); nothing stops the sweep.
Settings that describe the same runs share one run cache (``DIR/runs/<key>/``): the
default is simulated once, not once per knob.

At the end the study's findings are checked per setting (:func:`findings`) and written to
``DIR/findings.csv``. A complete sweep (no ``--quick``, no ``--only``, every case run) is also
stored in the repository: its rows without the machine's wall times as
``data/sensitivity.csv`` (6 significant digits) and its findings as
``data/sensitivity_findings.csv``; the validation pages' prose reads its numbers from them.

Usage::

    python scripts/sensitivity.py [--out out/sensitivity] [--jobs N] [--quick]

``--quick``: two settings (mu = 0.4 and 0.2), 0.8 s simulated with 0.3 s discarded (the
notebook test uses it; about 10 s on 2 cores).
"""

from __future__ import annotations

import argparse
import dataclasses
import math
import os
import re
import sys
import time
import traceback
from concurrent.futures import ProcessPoolExecutor, as_completed
from dataclasses import dataclass
from pathlib import Path

import rubdiag

if __name__ == "__main__":     # a run starts here (imported, numpy is loaded already)
    rubdiag.pin_blas_kernels()  # first: before numpy loads OpenBLAS (the same bits anywhere)

# isort: split
import numpy as np
import pandas as pd

DEFAULT_MU = 0.4   # the paper rig preset's friction coefficient
DEFAULT_DT = 1e-5
DEFAULT_DURATION = 2.3
DISCARD = 0.3
QUICK_DURATION = 0.8
DEFAULT_RAMP = 0.1

#: key metrics copied from the Table 2 row of each case
TABLE_METRICS = (
    "rotor_max_y_mm", "casing_max_y_um", "contact1_min_force_n", "contact1_p05_force_n",
    "contact1_max_force_n", "contact1_sliding_entries", "contact1_sticking_entries",
    "contact1_sliding_entries_per_s", "contact1_sticking_entries_per_s",
    "contact1_sticking_share", "contact1_mean_force_sliding_n",
    "contact1_mean_force_sticking_n",
)
#: spectral features copied for the shaft (node 11) and the blade tip (node 39)
SPECTRAL = (
    "amp_1x", "amp_1p5x", "amp_3p5x", "bb_3x_rms", "bb_4x_rms", "bb_5x_rms",
    "sb_4x_delta_hz", "combo_fa_hz", "combo_fb_hz", "combo_order",
)
PAPER = ("paper_casing_max_y_um", "paper_contact1_max_force_n",
         "paper_contact1_sliding_entries", "paper_contact1_sticking_entries")
CASE_NAMES = (("case1_light", 1, "light", 2.3), ("case1_serious", 1, "serious", 1.9),
              ("case2_light", 2, "light", 2.3), ("case2_serious", 2, "serious", 1.9))
FINDINGS = ("a_severity", "b_combination", "c_hump_4x", "d_half_orders", "e_stick_slip",
            "f_vs_study")


def log(message: str) -> None:
    print(f"[sensitivity {time.strftime('%H:%M:%S')}] {message}", file=sys.stderr, flush=True)


# ------------------------------------------------------------------------------------------
# settings
# ------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class Setting:
    """One point of the sweep: a knob and its value; everything else at the default."""

    name: str
    knob: str
    value: str                 # as shown
    value_num: float           # numeric value for plots (NaN when the value is a word)
    mu: float = DEFAULT_MU
    augmented: bool = False
    eps_m: float = 20e-6
    support: str = "distributed"
    dt_s: float = DEFAULT_DT
    duration_s: float = DEFAULT_DURATION
    discard_s: float = DISCARD
    gap_ramp_s: float | None = None   # None: the Run default (0.1 s)

    @property
    def key(self) -> str:
        """Identifies the runs (settings with equal keys share the run cache)."""
        aug = f"aug{self.eps_m * 1e6:g}um" if self.augmented else "penalty"
        ramp = "" if self.gap_ramp_s is None else f"_ramp{self.gap_ramp_s:g}"
        return (f"mu{self.mu:g}_{aug}_{self.support}_dt{self.dt_s:g}_"
                f"T{self.duration_s:g}_d{self.discard_s:g}{ramp}")

    @property
    def is_default(self) -> bool:
        return (self.mu == DEFAULT_MU and not self.augmented and self.support == "distributed"
                and self.dt_s == DEFAULT_DT and self.duration_s == DEFAULT_DURATION
                and self.gap_ramp_s in (None, DEFAULT_RAMP))

    def run_options(self) -> dict:
        """Further options of Run (only those that differ from its defaults)."""
        return {} if self.gap_ramp_s is None else {"gap_ramp_s": self.gap_ramp_s}

    def rig(self):
        rig = rubdiag.paper_rig()
        if self.support != rig.casing.support:
            rig = dataclasses.replace(rig, casing=dataclasses.replace(rig.casing,
                                                                      support=self.support))
        return rig

    def contact(self):
        from rubdiag.model import BladeContact

        return BladeContact(friction_coefficient=self.mu, augmented=self.augmented,
                            penetration_tolerance_m=self.eps_m)


def settings(quick: bool = False) -> list[Setting]:
    """The sweep, knob by knob (the default appears once per knob)."""
    if quick:
        d = QUICK_DURATION
        return [Setting(f"mu={mu:g}", "mu", f"{mu:g}", mu, mu=mu, duration_s=d)
                for mu in (DEFAULT_MU, 0.2)]
    out = [Setting(f"mu={mu:g}", "mu", f"{mu:g}", mu, mu=mu) for mu in (0.1, 0.2, 0.3, 0.4, 0.5)]
    out.append(Setting("augmentation=off", "augmentation", "off", math.nan))
    out += [Setting(f"augmentation=eps{e:g}um", "augmentation", f"ε = {e:g} µm", float(e),
                    augmented=True, eps_m=e * 1e-6) for e in (50, 20, 10)]
    out += [Setting(f"casing_support={s}", "casing_support", s, math.nan, support=s)
            for s in ("distributed", "point")]
    out += [Setting(f"dt={dt:g}", "dt", f"{dt:g} s", dt, dt_s=dt) for dt in (2e-5, 1e-5, 5e-6)]
    out += [Setting(f"window={T:g}", "window", f"{T - DISCARD:g} s (T = {T:g} s)", T - DISCARD,
                    duration_s=T) for T in (1.3, 2.3, 4.3)]
    # the same 2 s window, but late: is the default window a steady state?
    out.append(Setting("window=4.3/discard=2.3", "window", "2 s after 2.3 s (T = 4.3 s)", 2.0,
                       duration_s=4.3, discard_s=2.3))
    # not a physical knob: the same machine with the gap ramp (the start-up) 1 % shorter or
    # longer. The rub is chaotic, so this measures the spread of every number between runs
    # that differ only in their history (the noise floor of the other knobs' effects).
    out += [Setting(f"gap_ramp={r:g}", "gap_ramp (noise floor)", f"{r:g} s", r,
                    gap_ramp_s=None if r == DEFAULT_RAMP else r)
            for r in (0.098, 0.099, 0.1, 0.101, 0.102)]
    # the same noise floor at mu = 0.3 (BladeContact's generic default, the sweep's former
    # centre): are its findings a property of mu or of one history?
    out += [Setting(f"mu=0.3/gap_ramp={r:g}", "gap_ramp at μ = 0.3 (noise floor)", f"{r:g} s",
                    r, mu=0.3, gap_ramp_s=None if r == DEFAULT_RAMP else r)
            for r in (0.098, 0.099, 0.1, 0.101, 0.102)]
    return out


# ------------------------------------------------------------------------------------------
# rows
# ------------------------------------------------------------------------------------------
def _base(setting: Setting, stem: str, case: int, intensity: str, gap_mm: float) -> dict:
    return {
        "setting": setting.name, "knob": setting.knob, "value": setting.value,
        "value_num": setting.value_num, "is_default": setting.is_default,
        "run_key": setting.key, "case": case, "intensity": intensity, "cell": stem,
        "gap_mm": gap_mm, "mu": setting.mu, "augmented": setting.augmented,
        "eps_um": setting.eps_m * 1e6 if setting.augmented else math.nan,
        "support": setting.support, "dt_s": setting.dt_s, "duration_s": setting.duration_s,
        "discard_s": setting.discard_s,
        "gap_ramp_s": DEFAULT_RAMP if setting.gap_ramp_s is None else setting.gap_ramp_s,
    }


def _row_from_features(base: dict, feat: dict, table_row: dict | None, paper: dict) -> dict:
    from rubdiag.paper import describe_spectrum

    row = dict(base)
    row["window_s"] = feat.get("window_s", math.nan)
    row["speed_rpm"] = feat.get("speed_rpm", math.nan)
    if table_row is not None:
        for key in TABLE_METRICS:
            row[key] = table_row[key]
        row["spectrum"] = table_row["shaft_blade_spectrum_features"]
    else:   # same definitions as table2 (rubdiag/paper/_table2.py)
        row["rotor_max_y_mm"] = feat.get("_rotor_max_y_mm", math.nan)
        row["casing_max_y_um"] = feat["casing_max_y_m"] * 1e6
        for key in TABLE_METRICS[2:]:
            row[key] = feat[key]
        row["spectrum"] = describe_spectrum(feat)
    for prefix in ("shaft", "blade"):
        for key in SPECTRAL:
            row[f"{prefix}_{key}"] = feat.get(f"{prefix}_{key}", math.nan)
    row["max_force_any_contact_n"] = feat.get("contacts_max_force_n", math.nan)
    row.update(paper)
    return row


def _paper_values() -> dict:
    from rubdiag.paper import paper_values

    p = paper_values().set_index(["case", "intensity"])
    return {(c, i): {"paper_casing_max_y_um": p.loc[(c, i), "casing_max_y_um"],
                     "paper_contact1_max_force_n": p.loc[(c, i), "contact1_max_force_n"],
                     "paper_contact1_sliding_entries": p.loc[(c, i), "contact1_sliding_entries"],
                     "paper_contact1_sticking_entries":
                         p.loc[(c, i), "contact1_sticking_entries"]}
            for c, i in p.index}


def _rows_from_table(setting: Setting, table: pd.DataFrame, wall: float) -> list[dict]:
    feats = table.attrs["features"]
    results = table.attrs.get("results", {})
    paper = _paper_values()
    rows = []
    for j, (stem, case, intensity, gap) in enumerate(CASE_NAMES):
        trow = table.iloc[j].to_dict()
        assert trow["case"] == case and trow["intensity"] == intensity
        row = _row_from_features(_base(setting, stem, case, intensity, gap),
                                 feats.iloc[j].to_dict(), trow, paper[(case, intensity)])
        result = results.get(stem)
        row.update(status="ok", message="", failure_time_s=math.nan,
                   run_wall_s=float(result.wall_s) if result is not None else math.nan,
                   n_steps=int(result.system.n_steps) if result is not None else -1,
                   setting_wall_s=wall)
        rows.append(row)
    return rows


def _simulate_case(run, path: str) -> dict:
    """Worker for the case-by-case retry: never raises (exceptions are reported as data, so
    that a worker's failure, whatever it is, becomes a row with its message)."""
    from rubdiag.simulation import SimulationDiverged, simulate

    start = time.perf_counter()
    try:
        result = simulate(run)
        result.save(path)
        return {"status": "ok", "message": "", "path": path,
                "wall": time.perf_counter() - start}
    except SimulationDiverged as exc:
        partial = exc.result
        system = getattr(partial, "system", partial)
        return {"status": "diverged", "message": str(exc),
                "failure_time_s": float(getattr(system, "failure_time", math.nan)),
                "partial_max_force_n": float(np.max(system.max_normal_force))
                if getattr(system, "max_normal_force", np.zeros(0)).size else math.nan,
                "partial_contact1_max_force_n": float(system.max_normal_force[0])
                if getattr(system, "max_normal_force", np.zeros(0)).size else math.nan,
                "wall": time.perf_counter() - start}
    except Exception as exc:   # recorded, not fatal
        return {"status": "failed", "message": f"{type(exc).__name__}: {exc}",
                "wall": time.perf_counter() - start}


def _rows_case_by_case(setting: Setting, out_dir: Path, jobs: int, first_error: str
                       ) -> list[dict]:
    """The retry after table2 raised: run each case on its own, keep what runs."""
    from rubdiag.paper._table2 import _cached
    from rubdiag.runs import run_features
    from rubdiag.simulation import Run

    rig, contact = setting.rig(), setting.contact()
    run_dir = out_dir / "runs"
    run_dir.mkdir(parents=True, exist_ok=True)
    runs = {stem: Run.paper_case(case, gap, rig=rig, duration_s=setting.duration_s,
                                 discard_s=setting.discard_s, dt_s=setting.dt_s,
                                 contact=contact,
                                 label=f"case {case} {intensity} (g0 = {gap} mm)",
                                 **setting.run_options())
            for stem, case, intensity, gap in CASE_NAMES}
    outcomes = {}
    todo = {}
    for stem, run in runs.items():
        cached = _cached(run_dir / f"{stem}.npz", run)
        if cached is not None:
            outcomes[stem] = {"status": "ok", "message": "", "result": cached,
                              "wall": cached.wall_s}
        else:
            todo[stem] = run
    start = time.perf_counter()
    with ProcessPoolExecutor(max_workers=max(1, min(jobs, len(todo) or 1))) as pool:
        futures = {pool.submit(_simulate_case, run, str(run_dir / f"{stem}.npz")): stem
                   for stem, run in todo.items()}
        for future in as_completed(futures):
            stem = futures[future]
            try:
                outcome = future.result()
            except Exception as exc:   # a worker that died
                outcome = {"status": "failed", "message": f"{type(exc).__name__}: {exc}",
                           "wall": math.nan}
            if outcome["status"] == "ok":
                outcome["result"] = _cached(Path(outcome["path"]), runs[stem])
                if outcome["result"] is None:
                    outcome = {"status": "failed", "message": "saved result unreadable",
                               "wall": outcome["wall"]}
            log(f"  {setting.name} {stem}: {outcome['status']} {outcome['message'][:120]}")
            outcomes[stem] = outcome
    wall = time.perf_counter() - start
    paper = _paper_values()
    rows = []
    for stem, case, intensity, gap in CASE_NAMES:
        outcome = outcomes[stem]
        base = _base(setting, stem, case, intensity, gap)
        if outcome["status"] == "ok":
            result = outcome["result"]
            feat = run_features([result]).iloc[0].to_dict()
            feat["_rotor_max_y_mm"] = result.displacement("shaft 11 y", True).max() * 1e3
            row = _row_from_features(base, feat, None, paper[(case, intensity)])
            row.update(status="ok", message=f"(case-by-case retry after: {first_error})",
                       failure_time_s=math.nan, run_wall_s=float(result.wall_s),
                       n_steps=int(result.system.n_steps))
        else:
            row = dict(base)
            row.update(paper[(case, intensity)])
            row.update(status=outcome["status"], message=outcome["message"],
                       failure_time_s=outcome.get("failure_time_s", math.nan),
                       partial_max_force_n=outcome.get("partial_max_force_n", math.nan),
                       partial_contact1_max_force_n=outcome.get("partial_contact1_max_force_n",
                                                                math.nan),
                       run_wall_s=outcome.get("wall", math.nan), n_steps=-1)
        row["setting_wall_s"] = wall
        rows.append(row)
    return rows


def run_setting(setting: Setting, out: Path, jobs: int) -> list[dict]:
    """All four cases of one setting; never raises (failures become rows)."""
    from rubdiag.paper import table2

    out_dir = out / "runs" / setting.key
    start = time.perf_counter()
    try:
        table = table2(out_dir, jobs=jobs, duration_s=setting.duration_s,
                       discard_s=setting.discard_s, figures=False, rig=setting.rig(),
                       dt_s=setting.dt_s, contact=setting.contact(),
                       log=lambda m: log(f"  {setting.name}: {m}"), **setting.run_options())
        return _rows_from_table(setting, table, time.perf_counter() - start)
    except Exception as exc:   # BrokenProcessPool included: retry case by case
        error = f"{type(exc).__name__}: {exc}"
        log(f"  {setting.name}: table2 raised {error}; retrying case by case")
        try:
            return _rows_case_by_case(setting, out_dir, jobs, error)
        except Exception as exc2:
            message = f"{error}; retry: {type(exc2).__name__}: {exc2}"
            log(f"  {setting.name}: retry failed too\n{traceback.format_exc()}")
            paper = _paper_values()
            return [dict(_base(setting, stem, case, intensity, gap),
                         **paper[(case, intensity)], status="failed", message=message,
                         setting_wall_s=time.perf_counter() - start)
                    for stem, case, intensity, gap in CASE_NAMES]


# ------------------------------------------------------------------------------------------
# files
# ------------------------------------------------------------------------------------------
def _atomic_write(frame: pd.DataFrame, path: Path, **csv_options) -> None:
    tmp = path.with_name(f".{path.name}.{os.getpid()}.tmp")
    if path.suffix == ".parquet":
        frame.to_parquet(tmp, index=False)
    else:
        frame.to_csv(tmp, index=False, **csv_options)
    os.replace(tmp, path)


def _normalise(frame: pd.DataFrame) -> pd.DataFrame:
    """Stable dtypes for parquet (object columns with mixed content become strings)."""
    frame = frame.copy()
    if "gap_ramp_s" in frame:   # rows written before the column existed
        frame["gap_ramp_s"] = frame["gap_ramp_s"].fillna(DEFAULT_RAMP)
    for col in ("message", "spectrum", "value", "status", "setting", "knob", "run_key",
                "cell", "intensity", "support"):
        if col in frame:
            frame[col] = frame[col].fillna("").astype(str)
    return frame


def save(frame: pd.DataFrame, out: Path) -> None:
    frame = _normalise(frame)
    _atomic_write(frame, out / "sensitivity.parquet")
    _atomic_write(frame, out / "sensitivity.csv")


#: where a complete sweep is stored for the documentation, and what is left out of it: the
#: run cache's key and the wall times (they describe the machine, not the model)
DATA = Path(__file__).resolve().parents[1] / "data"
NOT_STORED = ("run_key", "message", "failure_time_s", "run_wall_s", "setting_wall_s")
DIGITS = 6


def store(frame: pd.DataFrame, found: pd.DataFrame, data: Path = DATA) -> None:
    """Write a complete sweep to ``data/sensitivity.csv`` and ``data/sensitivity_findings.csv``
    (floats to :data:`DIGITS` significant digits; each file atomically)."""
    for table, name in ((frame.drop(columns=[c for c in NOT_STORED if c in frame]),
                         "sensitivity.csv"), (found, "sensitivity_findings.csv")):
        _atomic_write(table, data / name, float_format=f"%.{DIGITS}g", lineterminator="\n")


def load(out: Path) -> pd.DataFrame:
    path = out / "sensitivity.parquet"
    if path.is_file():
        return pd.read_parquet(path)
    return pd.DataFrame()


# ------------------------------------------------------------------------------------------
# the study's findings, per setting
# ------------------------------------------------------------------------------------------
#: a broadband peak stands this many times above the levels around 3× and 5×
#: (the same factor as rubdiag.paper._describe.BROADBAND_FACTOR)
HUMP_FACTOR = 5.0


def _cell(frame: pd.DataFrame, cell: str) -> dict | None:
    rows = frame[frame["cell"] == cell]
    if rows.empty or rows.iloc[0]["status"] != "ok":
        return None
    return rows.iloc[0].to_dict()


def _either(row: dict, key: str) -> float:
    """Largest of the shaft and blade values (a line counts when either shows it)."""
    vals = [row.get(f"{p}_{key}", math.nan) for p in ("shaft", "blade")]
    vals = [float(v) for v in vals if v is not None and np.isfinite(v)]
    return max(vals) if vals else math.nan


def findings(frame: pd.DataFrame) -> pd.DataFrame:
    """One row per setting: each of the study's findings (a)-(f) as True/False (None when a
    case of the setting did not run) and the numbers behind it (``…_detail``).

    (a) case 2 / case 1 contact-1 max force >= 3 and casing max >= 2.5, at both gaps;
    (b) both case-2 runs show a combination pair f_a < 1× < f_b with f_a + f_b = 2×;
    (c) both case-1 runs show a broadband hump at 4×: shaft ``bb_4x_rms`` >= 5 × max(bb_3x,
        bb_5x);
    (d) 3×/2 and 7×/2 both present in case-1 serious (shaft or blade), and each absent or
        weaker in case-1 light;
    (e) mean normal force while sticking > while sliding in every cell, and the case-1
        sticking share grows from light to serious;
    (f) contact-1 max force within ±30 % of the study and casing max within a factor 2, in
        all four cells.
    """
    out = []
    for name, grp in frame.groupby("setting", sort=False):
        first = grp.iloc[0]
        rec = {"setting": name, "knob": first["knob"], "value": first["value"],
               "value_num": first["value_num"],
               "status": ", ".join(f"{r.cell}: {r.status}" for r in grp.itertuples()
                                   if r.status != "ok") or "ok"}
        c = {cell: _cell(grp, cell) for cell, *_ in CASE_NAMES}
        c1l, c1s, c2l, c2s = (c[k] for k in ("case1_light", "case1_serious", "case2_light",
                                               "case2_serious"))

        # (a) severity ratios
        if None not in (c1l, c1s, c2l, c2s):
            fr = [c2l["contact1_max_force_n"] / c1l["contact1_max_force_n"],
                  c2s["contact1_max_force_n"] / c1s["contact1_max_force_n"]]
            cr = [c2l["casing_max_y_um"] / c1l["casing_max_y_um"],
                  c2s["casing_max_y_um"] / c1s["casing_max_y_um"]]
            rec["a_severity"] = bool(min(fr) >= 3 and min(cr) >= 2.5)
            rec["a_severity_detail"] = (f"force ×{fr[0]:.1f}/×{fr[1]:.1f}, "
                                        f"casing ×{cr[0]:.1f}/×{cr[1]:.1f}")
        else:
            rec["a_severity"], rec["a_severity_detail"] = None, "not run"

        # (b) combination pair in case 2
        if None not in (c2l, c2s):
            ok, parts = True, []
            for r in (c2l, c2s):
                f1 = r["speed_rpm"] / 60.0
                best = None
                for p in ("shaft", "blade"):
                    fa, fb, m = (r.get(f"{p}_combo_fa_hz"), r.get(f"{p}_combo_fb_hz"),
                                 r.get(f"{p}_combo_order"))
                    if fa is not None and np.isfinite(fa) and np.isfinite(fb):
                        best = (fa, fb, m)
                        break
                if best is None:
                    ok = False
                    parts.append("none")
                else:
                    fa, fb, m = best
                    ok &= bool(m == 2 and fa < f1 < fb)
                    parts.append(f"{fa:.1f}+{fb:.1f}={m:g}×")
            rec["b_combination"], rec["b_combination_detail"] = bool(ok), " / ".join(parts)
        else:
            rec["b_combination"], rec["b_combination_detail"] = None, "not run"

        # (c) broadband hump at 4x in case 1
        if None not in (c1l, c1s):
            ratios = []
            for r in (c1l, c1s):
                # rubdiag measures the broadband levels on short records too; NaN (not
                # evaluable) only when a line's main lobe covers a whole band
                around = max(r["shaft_bb_3x_rms"], r["shaft_bb_5x_rms"])
                ok = np.isfinite(around) and around > 0 and np.isfinite(r["shaft_bb_4x_rms"])
                ratios.append(r["shaft_bb_4x_rms"] / around if ok else math.nan)
            rec["c_hump_4x"] = (bool(min(ratios) >= HUMP_FACTOR)
                                if all(np.isfinite(ratios)) else None)
            sb = [r["shaft_sb_4x_delta_hz"] for r in (c1l, c1s)]
            sbt = "/".join("–" if not np.isfinite(s) else f"{s:.1f}" for s in sb)
            rec["c_hump_4x_detail"] = (f"bb4/bb3,5 = {ratios[0]:.1f}/{ratios[1]:.1f}; "
                                       f"4×±Δ: {sbt} Hz")
        else:
            rec["c_hump_4x"], rec["c_hump_4x_detail"] = None, "not run"

        # (d) half orders in case 1 serious, not (or weaker) in light
        if None not in (c1l, c1s):
            a15 = [_either(r, "amp_1p5x") * 1e6 for r in (c1l, c1s)]
            a35 = [_either(r, "amp_3p5x") * 1e6 for r in (c1l, c1s)]
            ok = a15[1] > 0 and a35[1] > 0 and a15[0] < a15[1] and a35[0] < a35[1]
            rec["d_half_orders"] = bool(ok)
            extra = ""
            if c2s is not None:
                extra = (f"; case 2 serious {_either(c2s, 'amp_1p5x') * 1e6:.0f}/"
                         f"{_either(c2s, 'amp_3p5x') * 1e6:.1f}")
            rec["d_half_orders_detail"] = (f"3×/2 {a15[0]:.0f}→{a15[1]:.0f} µm, "
                                           f"7×/2 {a35[0]:.1f}→{a35[1]:.1f} µm{extra}")
        else:
            rec["d_half_orders"], rec["d_half_orders_detail"] = None, "not run"

        # (e) stick at higher force than slide; case-1 sticking share grows
        if None not in (c1l, c1s, c2l, c2s):
            cells = (c1l, c1s, c2l, c2s)
            higher = all(r["contact1_mean_force_sticking_n"] > r["contact1_mean_force_sliding_n"]
                         for r in cells)
            grows = c1s["contact1_sticking_share"] > c1l["contact1_sticking_share"]
            rec["e_stick_slip"] = bool(higher and grows)
            ratio = min(r["contact1_mean_force_sticking_n"] / r["contact1_mean_force_sliding_n"]
                        for r in cells)
            rec["e_stick_slip_detail"] = (
                f"stick/slip force ≥ ×{ratio:.1f}; case-1 share "
                f"{c1l['contact1_sticking_share']:.2f}→{c1s['contact1_sticking_share']:.2f}")
        else:
            rec["e_stick_slip"], rec["e_stick_slip_detail"] = None, "not run"

        # (f) numbers vs the study
        if None not in (c1l, c1s, c2l, c2s):
            cells = (c1l, c1s, c2l, c2s)
            fdev = [r["contact1_max_force_n"] / r["paper_contact1_max_force_n"] - 1
                    for r in cells]
            cfac = [r["casing_max_y_um"] / r["paper_casing_max_y_um"] for r in cells]
            ok = all(abs(d) <= 0.30 for d in fdev) and all(0.5 <= f <= 2.0 for f in cfac)
            rec["f_vs_study"] = bool(ok)
            rec["f_vs_study_detail"] = (
                "force " + "/".join(f"{100 * d:+.0f}" for d in fdev) + " %; casing "
                + "/".join(f"×{f:.2f}" for f in cfac))
        else:
            rec["f_vs_study"], rec["f_vs_study_detail"] = None, "not run"
        out.append(rec)
    return pd.DataFrame(out)


def robustness_table(found: pd.DataFrame) -> pd.DataFrame:
    """Knob value × finding as ✓ / ✗ (— when a case did not run)."""
    def mark(v):
        if v is None or (isinstance(v, float) and math.isnan(v)):
            return "—"
        return "✓" if bool(v) else "✗"

    table = found.set_index(["knob", "value"])[list(FINDINGS)].map(mark)
    return table


# ------------------------------------------------------------------------------------------
# main
# ------------------------------------------------------------------------------------------
def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--out", default="out/sensitivity", type=Path,
                        help="output directory (default: out/sensitivity)")
    parser.add_argument("--quick", action="store_true",
                        help="two settings (mu = 0.4, 0.2), 0.8 s with 0.3 s discarded")
    parser.add_argument("--jobs", type=int, default=None,
                        help="parallel processes per setting (default: all cores, at most 4)")
    parser.add_argument("--only", default=None,
                        help="regular expression: run only the settings whose name matches")
    parser.add_argument("--retry-failed", action="store_true",
                        help="rerun settings recorded with a failed or diverged case")
    args = parser.parse_args(argv)

    out: Path = args.out
    out.mkdir(parents=True, exist_ok=True)
    jobs = args.jobs or min(4, os.cpu_count() or 1)
    todo = settings(args.quick)
    if args.only:
        todo = [s for s in todo if re.search(args.only, s.name)]
    frame = load(out)
    start = time.perf_counter()
    log(f"{len(todo)} setting(s) → {out / 'sensitivity.parquet'} ({jobs} process(es))")
    for i, setting in enumerate(todo, start=1):
        if not frame.empty:
            mine = frame[frame["setting"] == setting.name]
            same = mine[np.isclose(mine["duration_s"], setting.duration_s)
                        & np.isclose(mine["discard_s"], setting.discard_s)]
            if len(same) == len(CASE_NAMES) and not (args.retry_failed
                                                    and (same["status"] != "ok").any()):
                log(f"[{i}/{len(todo)}] {setting.name}: already in the file, skipped")
                continue
            frame = frame[frame["setting"] != setting.name]
        log(f"[{i}/{len(todo)}] {setting.name} ({setting.key}) ...")
        t0 = time.perf_counter()
        rows = run_setting(setting, out, jobs)
        new = pd.DataFrame(rows)
        frame = new if frame.empty else pd.concat([frame, new], ignore_index=True)
        save(frame, out)
        brief = ", ".join(
            f"{r['cell']}: {r['status']}" + (f" F={r.get('contact1_max_force_n', math.nan):.0f} N"
                                             f" casing={r.get('casing_max_y_um', math.nan):.0f} µm"
                                             if r["status"] == "ok" else "")
            for r in rows)
        log(f"[{i}/{len(todo)}] {setting.name}: {time.perf_counter() - t0:.0f} s — {brief}")
    if not frame.empty:
        order = {s.name: j for j, s in enumerate(settings(args.quick))}
        frame = frame.assign(_o=frame["setting"].map(order).fillna(1e9)).sort_values(
            ["_o", "case", "gap_mm"], ascending=[True, True, False], kind="stable"
        ).drop(columns="_o").reset_index(drop=True)
        save(frame, out)
        try:
            found = findings(frame)
            _atomic_write(found, out / "findings.csv")
            print(robustness_table(found).to_string(), file=sys.stderr)
            complete = (len(frame) == len(settings()) * len(CASE_NAMES)
                        and (frame["status"] == "ok").all())
            if not (args.quick or args.only) and complete:
                store(frame, found)
                log(f"stored in {DATA / 'sensitivity.csv'} and sensitivity_findings.csv")
        except Exception:   # the sweep's data are saved; the summary is a convenience
            log(f"findings failed:\n{traceback.format_exc()}")
    log(f"done in {time.perf_counter() - start:.0f} s")
    return 0


if __name__ == "__main__":
    sys.exit(main())
