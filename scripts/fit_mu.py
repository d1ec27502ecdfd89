#!/usr/bin/env python
"""Fit the friction coefficient μ on one part of the study's Table 2 and score the rest.

The study gives no μ; the paper rig preset's μ was chosen by looking at all of Table 2 at
once. This script states the rule instead, fits μ on one part of the study's results and
reports how well the part it did not look at is reproduced.

Runs
----
μ = 0.10, 0.15 … 0.60 (every other value first: 0.1, 0.2 … 0.6, then 0.15 … 0.55, so that
an interrupted scan still covers the whole range); for every μ the four Table 2 cells
(case 1 and 2, g0 = 2.3 and 1.9 mm) from the five start histories of
:data:`rubdiag.paper._ensemble.GAP_RAMPS_S` (gap ramp 0.1 s ± 2 %), through
:func:`rubdiag.paper._ensemble` with ``contact = replace(rig.contact,
friction_coefficient=μ)`` on the paper rig preset, everything else as in Table 2 (dt =
1e-5 s, 2.3 s simulated, the first 0.3 s discarded). 11 × 4 × 5 = 220 runs.

Numbers and the objective
-------------------------
For each μ and cell, ``m(μ, cell, q)`` is the median over the start histories of quantity
``q``: ``contact1_max_force_n`` (contact-1 maximum normal force) or ``casing_max_y_um``
(casing maximum y displacement). Over a set ``S`` of (cell, q) pairs the score is the
root-mean-square log-ratio to the study's value ``p(cell, q)``::

    r_S(μ) = sqrt( mean over (cell, q) in S of ln( m(μ, cell, q) / p(cell, q) )² )

(100 · r is about the rms deviation in %; printed so). The other Table 2 numbers are not
used: the minimum force and the entry counts change with dt by more than the start-history
spread (64.7 → 19.6 → 7.3 N at 10, 5, 2.5 µs), so fitting μ to them would
fit a step size.

Splits (fixed before the scan):

- **A (main): fit on case 1, hold out case 2.** Fit set: both case-1 cells × (force, casing),
  4 numbers; held out: both case-2 cells × (force, casing), and the claims below.
- **B: fit on the forces, hold out the casing.** Fit set: the contact-1 maximum force of the
  four cells; held out: the casing maximum of the four cells, and the claims.
- **All**: all 8 numbers (what "reproduces the study's numbers best" means on the numbers).

μ* = argmin of ``r_fit`` over the scanned μ (the smallest μ on a tie); reported with the
held-out score at μ*, at the preset μ and at the held-out optimum (argmin of ``r_held``).
Robustness: μ* again with each start history left out in turn (the same gap ramp dropped from
every cell and μ; "jackknife"), a rough measure of how well five histories fix μ*.

Claims (held out in both splits)
--------------------------------
The study's qualitative claims that μ can move, with the per-run rules and tolerances of
``data/claims.csv`` (ids there; shaft node 11, as there). Each is scored as the share of the
runs it is about in which it holds (5 or 10 per μ):

``C1c`` (case 1 light) a continuous hump at 4×: ``min(B4 / (amp_4x/√2), B4 / max(B3, B5))
≥ 1`` with ``Bn = √(bb_nx_rms² − (sb_nx_lower² + sb_nx_upper²)/2)``;
``C1d/l`` (case 1) sidebands 4× ± Δ with |Δ − 5 Hz| ≤ 1 Hz; ``C1i`` / ``C1j`` (case 1
serious) a 3×/2 / a 7×/2 line; ``C1k`` (case 1 light) neither 3×/2 nor 7×/2; ``C1o`` (case
1 light) mainly sliding (contact-1 sticking share < 0.5); ``C2d/e`` (case 2) the strongest
combination pair sums to 2×; ``C2f/g`` (case 2) its f_a within 2 Hz of the study's 43 Hz
(light) / 44 Hz (serious); ``C2l/m`` (case 2) mainly sticking (sticking share > 0.5).

``claims`` is the mean of the nine shares (1: every claim in every run). The case-2 / case-1
ratios (``C2a/b``, ``C2i/j``, study 3.9 and 5.5) are shown as the ratios of the medians;
in split A they are held out too.

Files
-----
``data/mu_fit.csv``: one row per run (μ, cell, gap ramp, the numbers and the spectral
features the claims use, ``status``, the μ's wall time and date); rewritten atomically (a
temporary file, then a rename) after every μ. A rerun skips the μ already complete there (20
rows with the same dt and durations; a failed run stays recorded as such), so an interrupted
scan resumes.
``data/mu_fit_summary.csv``: one row per μ (medians, scores, claim shares), recomputed from
``mu_fit.csv`` as stored (6 significant digits), so that it can be checked from that file.

Usage::

    python scripts/fit_mu.py [--jobs 2] [--mu 0.3 0.4] [--out-dir data]
    python scripts/fit_mu.py --table     # the documentation's table, from the stored files

A run takes about 4–9 s of one core (case 2 the longer); the whole scan about 15–30 min on
2 cores.
"""

from __future__ import annotations

import argparse
import dataclasses
import math
import os
import sys
import time
from pathlib import Path

import rubdiag

if __name__ == "__main__":     # a run starts here (imported, numpy is loaded already)
    rubdiag.pin_blas_kernels()  # first: before numpy loads OpenBLAS (the same bits anywhere)

# isort: split
import numpy as np
import pandas as pd

ROOT = Path(__file__).resolve().parents[1]
DATA = ROOT / "data"
RUNS_FILE, SUMMARY_FILE = "mu_fit.csv", "mu_fit_summary.csv"

#: the scan, in the order it runs (coarse grid first)
MUS = (0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.15, 0.25, 0.35, 0.45, 0.55)
CELLS = ((1, "light", 2.3), (1, "serious", 1.9), (2, "light", 2.3), (2, "serious", 1.9))
RUN_OPTIONS = {"dt_s": 1e-5, "duration_s": 2.3, "discard_s": 0.3}
NUMBERS = ("contact1_max_force_n", "casing_max_y_um")

#: (fit set, held-out set) per split; a set is a tuple of (case, intensity, quantity)
_CASE1 = tuple((1, i, q) for i in ("light", "serious") for q in NUMBERS)
_CASE2 = tuple((2, i, q) for i in ("light", "serious") for q in NUMBERS)
_FORCES = tuple((c, i, "contact1_max_force_n") for c, i, _ in CELLS)
_CASING = tuple((c, i, "casing_max_y_um") for c, i, _ in CELLS)
SPLITS = {
    "A": {"title": "fit on case 1, hold out case 2", "fit": _CASE1, "held": _CASE2},
    "B": {"title": "fit on the forces, hold out the casing", "fit": _FORCES, "held": _CASING},
}
ALL = _CASE1 + _CASE2

#: claim -> (case, intensities) it is about; the rules are in :func:`claim_holds`
CLAIMS = {
    "C1c": (1, ("light",)), "C1d/l": (1, ("light", "serious")), "C1i": (1, ("serious",)),
    "C1j": (1, ("serious",)), "C1k": (1, ("light",)), "C1o": (1, ("light",)),
    "C2d/e": (2, ("light", "serious")), "C2f/g": (2, ("light", "serious")),
    "C2l/m": (2, ("light", "serious")),
}
SIDEBAND_HZ, SIDEBAND_TOL_HZ = 5.0, 1.0
PAIR_STUDY_HZ, PAIR_TOL_HZ = {"light": 43.0, "serious": 44.0}, 2.0
#: shaft features kept per run (the claims use them)
SPECTRAL = ("amp_1x", "amp_4x", "amp_1p5x", "amp_3p5x", "sb_4x_delta_hz",
            *(f"{k}_{n}x_{s}" for n in (3, 4, 5) for k, s in (("sb", "lower"), ("sb", "upper"),
                                                             ("bb", "rms"))),
            "combo_fa_hz", "combo_fb_hz", "combo_order")
#: per-run columns kept besides the spectral ones
KEPT = ("speed_rpm", "window_s", "casing_max_y_um", "contact1_max_force_n",
        "contact1_min_force_n", "contact1_n_episodes", "contact1_sliding_entries",
        "contact1_sticking_entries", "contact1_sticking_share",
        "contact1_mean_force_sliding_n", "contact1_mean_force_sticking_n")


def log(message: str) -> None:
    print(f"[fit_mu {time.strftime('%H:%M:%S')}] {message}", file=sys.stderr, flush=True)


# ------------------------------------------------------------------------------------------
# runs
# ------------------------------------------------------------------------------------------
def _rows(table: pd.DataFrame, mu: float) -> pd.DataFrame:
    """Our per-run columns from :func:`rubdiag.paper._ensemble` rows."""
    intensity = {gap: name for _, name, gap in CELLS}
    out = pd.DataFrame({"mu": mu, "case": table["case"],
                        "intensity": table["gap_mm"].map(intensity),
                        "gap_mm": table["gap_mm"], "gap_ramp_s": table["gap_ramp_s"],
                        **RUN_OPTIONS, "status": "ok", "message": ""})
    table = table.assign(casing_max_y_um=table["casing_max_y_m"] * 1e6)
    for key in KEPT:
        out[key] = table[key]
    for key in SPECTRAL:
        out[f"shaft_{key}"] = table[f"shaft_{key}"]
    return out


def run_mu(mu: float, jobs: int) -> pd.DataFrame:
    """The 20 runs of one μ; a run that raises becomes a row with its status and message."""
    from rubdiag.model import paper_rig
    from rubdiag.paper import ensemble
    from rubdiag.paper._ensemble import GAP_RAMPS_S

    rig = paper_rig()
    contact = dataclasses.replace(rig.contact, friction_coefficient=mu)
    cases = [(case, gap) for case, _, gap in CELLS]
    try:
        return _rows(ensemble(cases, GAP_RAMPS_S, jobs=jobs, rig=rig, contact=contact,
                              **RUN_OPTIONS), mu)
    except Exception as exc:   # recorded below, run by run
        log(f"mu = {mu:g}: {type(exc).__name__}: {exc}; retrying run by run")
    parts = []
    for case, gap in cases:
        for ramp in GAP_RAMPS_S:
            try:
                parts.append(_rows(ensemble([(case, gap)], (ramp,), jobs=1, rig=rig,
                                            contact=contact, **RUN_OPTIONS), mu))
            except Exception as exc:   # a failed run is data
                name = dict((g, i) for _, i, g in CELLS)[gap]
                parts.append(pd.DataFrame([{
                    "mu": mu, "case": case, "intensity": name, "gap_mm": gap,
                    "gap_ramp_s": ramp, **RUN_OPTIONS, "status": type(exc).__name__,
                    "message": str(exc)[:200]}]))
    return pd.concat(parts, ignore_index=True)


def _atomic_csv(frame: pd.DataFrame, path: Path) -> None:
    from rubdiag.paper._table2 import write_csv

    tmp = path.with_name(path.name + ".tmp")
    write_csv(frame, tmp)
    os.replace(tmp, path)


def load_runs(out_dir: Path = DATA) -> pd.DataFrame:
    path = Path(out_dir) / RUNS_FILE
    return pd.read_csv(path, keep_default_na=False, na_values=[""]) if path.is_file() \
        else pd.DataFrame()


def _done(runs: pd.DataFrame, mu: float) -> bool:
    if runs.empty:
        return False
    mine = runs[np.isclose(runs["mu"], mu)]
    same = all(np.isclose(mine[k], v).all() for k, v in RUN_OPTIONS.items())
    return len(mine) == len(CELLS) * 5 and same


def scan(mus=MUS, jobs: int = 2, out_dir: Path = DATA) -> pd.DataFrame:
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    runs = load_runs(out_dir)
    start = time.perf_counter()
    for i, mu in enumerate(mus, start=1):
        if _done(runs, mu):
            log(f"[{i}/{len(mus)}] mu = {mu:g}: already in {out_dir / RUNS_FILE}, skipped")
            continue
        t0 = time.perf_counter()
        rows = run_mu(mu, jobs)
        rows["mu_wall_s"] = time.perf_counter() - t0
        rows["date"] = time.strftime("%Y-%m-%d")
        if not runs.empty:
            runs = runs[~np.isclose(runs["mu"], mu)]
        runs = rows if runs.empty else pd.concat([runs, rows], ignore_index=True)
        runs = runs.sort_values(["mu", "case", "gap_mm", "gap_ramp_s"],
                                ascending=[True, True, False, True]).reset_index(drop=True)
        _atomic_csv(runs, out_dir / RUNS_FILE)
        runs = load_runs(out_dir)   # the summary is computed from the file as stored
        _atomic_csv(summary(runs), out_dir / SUMMARY_FILE)
        log(f"[{i}/{len(mus)}] mu = {mu:g}: {time.perf_counter() - t0:.0f} s, "
            f"{(rows['status'] == 'ok').sum()}/{len(rows)} ok "
            f"({time.perf_counter() - start:.0f} s elapsed)")
    return runs


# ------------------------------------------------------------------------------------------
# scores
# ------------------------------------------------------------------------------------------
def study() -> dict:
    """The study's value of each (case, intensity, quantity) of :data:`NUMBERS`."""
    from rubdiag.paper import paper_values

    p = paper_values().set_index(["case", "intensity"])
    return {(c, i, q): float(p.loc[(c, i), q]) for c, i, _ in CELLS for q in NUMBERS}


def medians(runs: pd.DataFrame) -> pd.DataFrame:
    """Median over the ok runs of each (μ, case, intensity) of each of :data:`NUMBERS`."""
    ok = runs[runs["status"] == "ok"]
    return ok.groupby(["mu", "case", "intensity"])[list(NUMBERS)].median()


def score(med: pd.DataFrame, mu: float, items, ref: dict) -> float:
    """``r`` (the module docstring) of the medians ``med`` at ``mu`` over ``items``."""
    logs = []
    for case, intensity, q in items:
        key = (mu, case, intensity)
        if key not in med.index:
            return math.nan
        logs.append(math.log(med.loc[key, q] / ref[(case, intensity, q)]))
    return math.sqrt(float(np.mean(np.square(logs))))


def _band(row, n: int) -> float:
    """``Bn``: the shaft's broadband RMS around n× without the n× line and its sidebands."""
    side = sum(float(row[f"shaft_sb_{n}x_{s}"]) ** 2 for s in ("lower", "upper")
               if math.isfinite(float(row[f"shaft_sb_{n}x_{s}"])))
    return math.sqrt(max(float(row[f"shaft_bb_{n}x_rms"]) ** 2 - side / 2, 0.0))


def claim_holds(row, claim: str) -> bool | None:
    """Whether ``claim`` (a key of :data:`CLAIMS`) holds in one run (a row of
    ``mu_fit.csv``); None when the claim is not about the run's cell."""
    case, intensities = CLAIMS[claim]
    intensity = row["intensity"]
    if int(row["case"]) != case or intensity not in intensities:
        return None
    share = float(row["contact1_sticking_share"])
    if claim == "C1c":
        b4 = _band(row, 4)
        line = float(row["shaft_amp_4x"]) / math.sqrt(2)
        around = max(_band(row, 3), _band(row, 5))
        return bool(b4 > 0 and b4 >= line and b4 >= around)
    if claim == "C1d/l":
        return abs(float(row["shaft_sb_4x_delta_hz"]) - SIDEBAND_HZ) <= SIDEBAND_TOL_HZ
    if claim in ("C1i", "C1j"):
        return float(row["shaft_amp_1p5x" if claim == "C1i" else "shaft_amp_3p5x"]) > 0
    if claim == "C1k":
        return max(float(row["shaft_amp_1p5x"]), float(row["shaft_amp_3p5x"])) == 0
    if claim == "C1o":
        return share < 0.5
    if claim == "C2l/m":
        return share > 0.5
    if claim == "C2d/e":
        return float(row["shaft_combo_order"]) == 2
    return (float(row["shaft_combo_order"]) == 2 and abs(
        float(row["shaft_combo_fa_hz"]) - PAIR_STUDY_HZ[intensity]) <= PAIR_TOL_HZ)


def claim_shares(runs: pd.DataFrame) -> pd.DataFrame:
    """Per μ, the share of the ok runs a claim is about in which it holds, and their mean
    ``claims``."""
    ok = runs[runs["status"] == "ok"]
    out = {}
    for mu, grp in ok.groupby("mu"):
        records = grp.to_dict("records")
        rec = {}
        for claim in CLAIMS:
            held = [h for h in (claim_holds(r, claim) for r in records) if h is not None]
            rec[claim] = float(np.mean(held)) if held else math.nan
        rec["claims"] = float(np.mean([rec[c] for c in CLAIMS]))
        out[mu] = rec
    return pd.DataFrame.from_dict(out, orient="index").rename_axis("mu")


def summary(runs: pd.DataFrame) -> pd.DataFrame:
    """One row per μ: run counts, wall time, the medians, the scores ``r_…`` and the claim
    shares."""
    ref = study()
    med = medians(runs)
    rows = []
    for mu, grp in runs.groupby("mu"):
        rec = {"mu": mu, "n_runs": len(grp), "n_ok": int((grp["status"] == "ok").sum()),
               "wall_s": float(grp["mu_wall_s"].iloc[0])}
        for c, i, _ in CELLS:
            for q in NUMBERS:
                key = (mu, c, i)
                rec[f"case{c}_{i}_{q}"] = med.loc[key, q] if key in med.index else math.nan
        for name, split in SPLITS.items():
            rec[f"r_{name}_fit"] = score(med, mu, split["fit"], ref)
            rec[f"r_{name}_held"] = score(med, mu, split["held"], ref)
        rec["r_all"] = score(med, mu, ALL, ref)
        for q, short in zip(NUMBERS, ("force", "casing"), strict=True):
            for i in ("light", "serious"):
                rec[f"ratio_{short}_{i}"] = (rec[f"case2_{i}_{q}"] / rec[f"case1_{i}_{q}"])
        rows.append(rec)
    frame = pd.DataFrame(rows).set_index("mu")
    return frame.join(claim_shares(runs)).reset_index()


def _argmin(frame: pd.DataFrame, column: str) -> float:
    """μ of the smallest finite ``column`` (the smallest μ on a tie)."""
    ok = frame[np.isfinite(frame[column])].sort_values("mu")
    return float(ok.loc[ok[column].idxmin(), "mu"]) if not ok.empty else math.nan


def jackknife(runs: pd.DataFrame, items) -> list[float]:
    """argmin over μ of ``r`` over ``items`` with each gap ramp left out in turn."""
    ref, out = study(), []
    for ramp in sorted(runs["gap_ramp_s"].unique()):
        med = medians(runs[~np.isclose(runs["gap_ramp_s"], ramp)])
        mus = sorted(med.index.get_level_values("mu").unique())
        r = pd.DataFrame({"mu": mus, "r": [score(med, mu, items, ref) for mu in mus]})
        out.append(_argmin(r, "r"))
    return out


def results(runs: pd.DataFrame, summ: pd.DataFrame, preset_mu: float) -> dict:
    """μ* and the held-out scores of each split (what the documentation states)."""
    at = summ.set_index("mu")
    out = {"preset_mu": preset_mu, "mu_all": _argmin(summ, "r_all"),
           "mu_claims": float(summ.sort_values("mu").loc[summ["claims"].idxmax(), "mu"])}
    for name, split in SPLITS.items():
        star = _argmin(summ, f"r_{name}_fit")
        held_best = _argmin(summ, f"r_{name}_held")
        out[name] = {
            "mu_star": star, "r_fit": at.loc[star, f"r_{name}_fit"],
            "r_held_at_star": at.loc[star, f"r_{name}_held"],
            "r_held_at_preset": at.loc[preset_mu, f"r_{name}_held"]
            if preset_mu in at.index else math.nan,
            "mu_held_best": held_best, "r_held_best": at.loc[held_best, f"r_{name}_held"],
            "claims_at_star": at.loc[star, "claims"],
            "jackknife": jackknife(runs, split["fit"]),
        }
    return out


# ------------------------------------------------------------------------------------------
# the documentation's table
# ------------------------------------------------------------------------------------------
def _pct(r: float) -> str:
    return "–" if not math.isfinite(r) else f"{100 * r:.0f}"


def _share(s: float) -> str:
    return "–" if not math.isfinite(s) else f"{s:.2f}"


def _mus(values) -> str:
    return ", ".join(f"{v:g}" for v in values)


def render(runs: pd.DataFrame, summ: pd.DataFrame, preset_mu: float) -> str:
    """The documentation's table (Markdown): the scores and the claims per μ, and the results, from
    the stored files."""
    res = results(runs, summ, preset_mu)
    bold = {res[name]["mu_star"] for name in SPLITS} | {preset_mu}
    ref = study()
    ratio = {short: [ref[(2, i, q)] / ref[(1, i, q)] for i in ("light", "serious")]
             for q, short in zip(NUMBERS, ("force", "casing"), strict=True)}
    text = ("| μ | A fit: case 1 | A held out: case 2 | B fit: forces | B held out: casing "
            f"| all 8 | force case 2 / case 1 (study {ratio['force'][0]:.1f}, "
            f"{ratio['force'][1]:.1f}) | casing case 2 / case 1 (study "
            f"{ratio['casing'][0]:.1f}, {ratio['casing'][1]:.1f}) |\n"
            "|---|---|---|---|---|---|---|---|\n")
    rows = list(summ.sort_values("mu").itertuples())

    def mu_cell(r) -> str:
        return f"**{r.mu:g}**" if r.mu in bold else f"{r.mu:g}"

    for r in rows:
        text += (f"| {mu_cell(r)} | {_pct(r.r_A_fit)} | {_pct(r.r_A_held)} | {_pct(r.r_B_fit)} "
                 f"| {_pct(r.r_B_held)} | {_pct(r.r_all)} | {r.ratio_force_light:.1f}, "
                 f"{r.ratio_force_serious:.1f} | {r.ratio_casing_light:.1f}, "
                 f"{r.ratio_casing_serious:.1f} |\n")
    text += ("\n| μ | " + " | ".join(CLAIMS) + " | claims |\n|---|"
             + "---|" * (len(CLAIMS) + 1) + "\n")
    for r in rows:
        shares = summ.loc[summ["mu"] == r.mu].iloc[0]
        text += (f"| {mu_cell(r)} | " + " | ".join(_share(shares[c]) for c in CLAIMS)
                 + f" | {_share(r.claims)} |\n")
    n_ok, n = int(summ["n_ok"].sum()), int(summ["n_runs"].sum())
    text += (f"\nr in % (rms log-ratio of the 5-history medians to the study's numbers, "
             f"× 100); ratios of the medians; claims (ids of `data/claims.csv`) as the share "
             f"of the 5 or 10 runs each is about. {n_ok} of {n} runs ok, "
             f"{summ['wall_s'].sum() / 60:.0f} min on 2 processes.\n\n")
    for name, split in SPLITS.items():
        s = res[name]
        text += (f"- Split {name} ({split['title']}): μ* = {s['mu_star']:g} "
                 f"(r = {_pct(s['r_fit'])} %); held out r = {_pct(s['r_held_at_star'])} % at "
                 f"μ*, {_pct(s['r_held_at_preset'])} % at the preset μ = {preset_mu:g}, "
                 f"best {_pct(s['r_held_best'])} % at μ = {s['mu_held_best']:g}; claims "
                 f"{_share(s['claims_at_star'])} at μ*; μ* with one history left out: "
                 f"{_mus(s['jackknife'])}.\n")
    text += (f"- All 8 numbers: best μ = {res['mu_all']:g}. Claims: best μ = "
             f"{res['mu_claims']:g}. Preset μ = {preset_mu:g}.\n")
    return text


#: claims.csv ids of the case-2 / case-1 ratios: (quantity, intensity) -> id
RATIO_CLAIMS = {("force", "light"): "C2i", ("force", "serious"): "C2j",
                ("casing", "light"): "C2a", ("casing", "serious"): "C2b"}


def _relative_tolerance(claim_id: str) -> float:
    """The '±15 %' of a claim of data/claims.csv, as 0.15."""
    table = pd.read_csv(DATA / "claims.csv").set_index("id")
    tol = str(table.loc[claim_id, "tolerance"]).replace(" ", "")
    if not (tol.startswith("±") and tol.endswith("%")):
        raise ValueError(f"{claim_id}: tolerance {tol!r} is not a relative band")
    return float(tol[1:-1]) / 100


def validated(runs: pd.DataFrame, summ: pd.DataFrame, preset: float) -> str:
    """The documentation's *Validated* items: the claims held out of split A (fitted on case 1
    alone) scored at its μ*, and at the preset μ for comparison."""
    star = results(runs, summ, preset)["A"]["mu_star"]
    at = summ.set_index("mu")
    ref = study()
    text = ""
    for q, short in zip(NUMBERS, ("force", "casing"), strict=True):
        parts = []
        for i in ("light", "serious"):
            claim = RATIO_CLAIMS[(short, i)]
            study_ratio = ref[(2, i, q)] / ref[(1, i, q)]
            tol = _relative_tolerance(claim)
            ours = at.loc[star, f"ratio_{short}_{i}"]
            verdict = "holds" if abs(ours / study_ratio - 1) <= tol else "does not hold"
            parts.append(f"{i} {ours:.1f} against {study_ratio:.1f} ± {100 * tol:.0f} % "
                         f"({claim}: {verdict}; {at.loc[preset, f'ratio_{short}_{i}']:.1f} "
                         f"at μ = {preset:g})")
        what = "contact-1 maximum force" if short == "force" else "casing maximum"
        text += f"- Case 2 / case 1, {what}: {'; '.join(parts)}.\n"
    shares = ", ".join(f"{c} {_share(at.loc[star, c])}" for c in CLAIMS)
    text += (f"- Spectral and contact-status claims, share of the runs each is about in which "
             f"it holds: {shares}; mean {_share(at.loc[star, 'claims'])} "
             f"({_share(at.loc[preset, 'claims'])} at μ = {preset:g}).\n")
    return (f"Scored at μ = {star:g}, split A's μ* (fitted on the case-1 numbers alone, "
            f"\"How μ was chosen\"; 5 start histories):\n\n" + text)


def preset_mu() -> float:
    from rubdiag.model import paper_rig

    return float(paper_rig().contact.friction_coefficient)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--out-dir", type=Path, default=DATA,
                        help=f"where {RUNS_FILE} and {SUMMARY_FILE} go (default: data/)")
    parser.add_argument("--jobs", type=int, default=2, help="processes (default 2)")
    parser.add_argument("--mu", type=float, nargs="+", default=None,
                        help="scan only these μ (default: 0.1 … 0.6 in steps of 0.05)")
    parser.add_argument("--table", action="store_true",
                        help="print the documentation's table from the stored files; run nothing")
    parser.add_argument("--validated", action="store_true",
                        help="print the documentation's Validated items from the stored files; "
                             "run nothing")
    args = parser.parse_args(argv)
    if not (args.table or args.validated):
        scan(tuple(args.mu) if args.mu else MUS, args.jobs, args.out_dir)
    runs = load_runs(args.out_dir)
    if runs.empty:
        log(f"nothing stored in {args.out_dir / RUNS_FILE}")
        return 1
    summ = pd.read_csv(args.out_dir / SUMMARY_FILE)
    show = validated if args.validated else render
    print(show(runs, summ, preset_mu()), end="")
    return 0


if __name__ == "__main__":
    sys.exit(main())
