"""The numbers that the validation pages' prose states, read from the files in ``data/``
that the scripts write (MyST substitutions: ``{{ rub_kinds_rub_point }}`` in a page).

A page never types a measured number: when a script writes its file again, the prose follows
with the tables. Each function reads one file (or one script's files) and returns its
substitutions; :func:`values` is all of them.
"""

from __future__ import annotations

import math
from pathlib import Path

import pandas as pd

DATA = Path(__file__).resolve().parents[1] / "data"


def _ci(value: float, lo: float, hi: float, digits: int = 3) -> str:
    """A score with its interval: ``0.970 [0.952, 0.985]``."""
    return f"{value:.{digits}f} [{lo:.{digits}f}, {hi:.{digits}f}]"


def _of(hits, n) -> str:
    return f"{int(hits)} of {int(n)}"


def _span(values, fmt: str = "{:g}", sep: str = "–") -> str:
    """``lo–hi`` of ``values``, or the one value when they are all equal."""
    lo, hi = fmt.format(min(values)), fmt.format(max(values))
    return lo if lo == hi else f"{lo}{sep}{hi}"


def _percent(fraction: float) -> str:
    return f"{100 * fraction:.0f}"


# ------------------------------------------------------------------------------------------
# confusers.md: the confuser tables of faults_journal, faults_bands and rub_kinds
# ------------------------------------------------------------------------------------------
CONFUSERS = {"journal": "", "bands": "bands_", "rub_kinds": "rub_kinds_"}
UNCERTAINTY = ("casing_stiffness_scale", "damping_ratio", "disc_mass_scale",
               "oil_viscosity_scale", "bearing_clearance_scale")
SPLIT_NAMES = {"group": "point", "speed_ratio": "band", "blade_count": "count"}


def _confuser_files(prefix: str) -> tuple[pd.DataFrame, pd.DataFrame, pd.DataFrame]:
    return tuple(pd.read_csv(DATA / f"{prefix}{name}.csv")
                 for name in ("confuser_cells", "confuser_rates", "one_vs_one"))


def _rates(rates: pd.DataFrame, measure: str, target: str, split: str) -> pd.DataFrame:
    return rates[(rates["measure"] == measure) & (rates["target"] == target)
                 & (rates["split"] == split)].set_index("faults")


def _kind(faults: str) -> str:
    """A ``faults`` label as a name: ``rub+whirl`` -> ``rub_whirl``, ``rub (seal)`` ->
    ``seal``."""
    return faults.replace("rub (", "").rstrip(")").replace("+", "_")


def confuser_values() -> dict[str, str]:
    """Scores and counts of the three confuser studies: ``<study>_<target>_<split>`` is a
    macro-F1 with its interval, ``..._alarms`` the false rub alarms, ``..._recall_<kind>``
    the rubs found."""
    out = {}
    for study, prefix in CONFUSERS.items():
        cells, rates, one = _confuser_files(prefix)
        at = cells.set_index(["target", "split"])
        for (target, split), row in at.iterrows():
            if split not in SPLIT_NAMES:
                continue
            key = f"{study}_{target}_{SPLIT_NAMES[split]}"
            out[key] = _ci(row.macro_f1, row.macro_f1_lo, row.macro_f1_hi)
            out[f"{key}_f1"] = f"{row.macro_f1:.3f}"
            alarms = _rates(rates, "false rub alarm", target, split)
            out[f"{key}_alarms"] = str(int(alarms["n_called_rub"].max()))
            out[f"{key}_confuser_runs"] = _span(alarms.drop(index="whirl")["n"].astype(int))
            out[f"{key}_whirl_alarms"] = _of(alarms.loc["whirl", "n_called_rub"],
                                             alarms.loc["whirl", "n"])
            recall = _rates(rates, "rub recall", target, split)
            for kind, r in recall.iterrows():
                out[f"{key}_recall_{_kind(kind)}"] = _of(r.n_called_rub, r.n)
        rub = at.loc[("rub", "group")]
        held = at.loc[[("rub", f) for f in UNCERTAINTY if ("rub", f) in at.index]]
        out[f"{study}_uncertainty_cost"] = f"{rub.macro_f1 - held['macro_f1'].min():.3f}"
        out[f"{study}_baseline"] = f"{rub.baseline:.3f}"
        out[f"{study}_shuffled"] = f"{rub.shuffled:.2f}"
        out[f"{study}_runs_per_confuser"] = _span(
            _rates(rates, "false rub alarm", "rub", "group")["n"].astype(int))
        for r in rates[(rates["target"] == "rub") & (rates["split"] == "group")].itertuples():
            out[f"{study}_{_kind(r.faults)}_runs"] = str(r.n)   # the runs so labelled
        out.update(_one_vs_one(study, one))
    _, _, one = _confuser_files(CONFUSERS["journal"])
    plain = pair_floor(one, STUDY_FAILURES, PLAIN_FAMILIES)
    out["journal_study_failures_plain"] = f"{math.floor(100 * plain) / 100:.2f}"
    return out


def _one_vs_one(study: str, one: pd.DataFrame) -> dict[str, str]:
    """``<study>_<a>_<b>_<family>``: a pair told apart by one family, by design point."""
    out = {}
    grouped = one[one["split"] == "group"] if "split" in one else one
    for r in grouped.dropna(subset=["macro_f1"]).itertuples():
        family = r.family.replace(" ", "_")
        out[f"{study}_{r.a}_{r.b}_{family}"] = f"{r.macro_f1:.3f}"
    return out


def pair_floor(one: pd.DataFrame, pairs, families) -> float:
    """The lowest score of ``families`` over ``pairs``, by design point."""
    rows = one[(one["split"] == "group") & one["family"].isin(families)
               & one.apply(lambda r: (r.a, r.b) in pairs, axis=1)]
    return float(rows["macro_f1"].min())


#: the pairs the study's features fail on (faults_journal), and the families that tell them
STUDY_FAILURES = (("rub", "crack"), ("rub", "looseness"), ("crack", "looseness"))
PLAIN_FAMILIES = ("harmonics", "full spectrum")


def transfer_values() -> dict[str, str]:
    """``data/transfer.csv``: what the rub model finds on what it was not trained on."""
    table = pd.read_csv(DATA / "transfer.csv")
    rub = table[table["model"] == "rub, default"]
    counts = rub[rub["trained_on"].str.contains("without blade_count")]
    blade = counts[counts["kind"] == "rub (blade)"]
    seal = counts[counts["kind"] == "rub (seal)"]
    healthy = counts[~counts["kind"].str.startswith("rub") & (counts["kind"] != "all")]
    per_count = healthy.groupby("scored_on")[["n", "n_called_rub"]].sum()
    by_count = []
    for r in blade.itertuples():
        number = r.scored_on.rsplit(" ", 1)[1]
        by_count.append(_of(r.n_called_rub, r.n) + f" ({number}"
                        + (" blades)" if not by_count else ")"))
    band = rub[rub["trained_on"].str.contains("without speed_ratio")].set_index("kind")
    textbook = rub[rub["scored_on"] == "textbook records, probe pairs"].set_index("kind")
    ross = rub[rub["scored_on"] == "ROSS records, paper shaft"].set_index("kind")

    return {
        "transfer_blade_rubs": ", ".join(by_count),
        "transfer_blade_count_alarms": str(int(per_count["n_called_rub"].max())),
        "transfer_blade_count_healthy_runs": _span(per_count["n"].astype(int)),
        "transfer_seal_found": _span(seal["n_called_rub"].astype(int)),
        "transfer_seal_runs": _span(seal["n"].astype(int)),
        "transfer_seal_recall": _span(seal["rub_recall"], "{:.2f}"),
        "transfer_band_blade": _of(*band.loc["rub (blade)", ["n_called_rub", "n"]]),
        "transfer_band_seal": _of(*band.loc["rub (seal)", ["n_called_rub", "n"]]),
        **{f"transfer_textbook_{line.replace('.', 'p')}":
           _of(*textbook.loc[f"{line} (on bins)", ["n_called_rub", "n"]])
           for line in ("2x", "3x", "0.5x", "0.33x")},
        **{f"transfer_ross_{kind.replace(' ', '_')}": _of(*ross.loc[kind, ["n_called_rub", "n"]])
           for kind in ("crack", "misalignment", "seal rub")},
    }


# ------------------------------------------------------------------------------------------
# classifier-table.md: data/learn_table.csv
# ------------------------------------------------------------------------------------------
def learn_values() -> dict[str, str]:
    """The classifier table's cells that its page discusses: ``learn_<target>_<split>_<est>``
    a macro-F1 with its interval (two decimals, as the table), ``..._margin`` the margin over
    the best baseline."""
    from generate import script

    goals = script("learn_table").GOALS
    table = pd.read_csv(DATA / "learn_table.csv")
    out = {}
    for r in table.itertuples():
        key = f"learn_{r.target}_{SPLIT_NAMES[r.split]}_{r.estimator}"
        out[key] = _ci(r.macro_f1, r.macro_f1_lo, r.macro_f1_hi, 2)
        out[f"{key}_f1"] = f"{r.macro_f1:.2f}"
        out[f"{key}_margin"] = f"{r.margin:+.2f}"
        out[f"{key}_margin3"] = f"{r.margin:+.3f}"
        out[f"{key}_factors"] = f"{r.bfactors:.2f}"
        out[f"{key}_casing"] = f"{r.with_casing:.2f}"
    at = table.set_index(["target", "split", "estimator"])
    forest_rub = at.loc[("rub", slice(None), "rf"), :]
    out["learn_rub_alone_baselines"] = _span(
        list(forest_rub["b1x"]) + list(forest_rub["bspeed"]), "{:.2f}")
    severity = at.loc[("severity", slice(None), "rf"), "margin"]
    goal = goals["severity"][1]
    for split, name in (("group", "point"), ("speed_ratio", "band")):
        short = goal - severity.loc[("severity", split, "rf")]
        out[f"learn_severity_{name}_short"] = f"{short:.3f}"
    out["learn_rub_goal"] = f"{goals['rub'][1]:.2f}"
    out["learn_severity_goal"] = f"{goal:.2f}"
    classes = {t: dict(c.split(":") for c in table.loc[table["target"] == t, "classes"].iloc[0]
                       .split()) for t in ("rub", "severity")}
    out["learn_runs"] = str(int(table["n_rows"].iloc[0]))
    out["learn_rub_runs"] = classes["rub"]["True"]
    out["learn_no_rub_runs"] = classes["rub"]["False"]
    for level in ("none", "light", "serious"):
        out[f"learn_severity_{level}_runs"] = classes["severity"][level]
    out["learn_shuffled_outside"] = str(int(table["shuffled_outside"].sum()))
    out["learn_shuffles"] = str(int(table["shuffled_n"].sum()))
    out["learn_shuffles_expected"] = f"{0.05 * table['shuffled_n'].sum():g}"
    worst = table["shuffled_outside"].max()
    out["learn_shuffled_worst"] = _of(worst, table["shuffled_n"].iloc[0])
    out["learn_table_minutes"] = f"{table['wall_s'].sum() / 60:.1f}"
    return out


# ------------------------------------------------------------------------------------------
# mu-fit.md (and the pages that cite the fit): data/mu_fit.csv, data/mu_fit_summary.csv
# ------------------------------------------------------------------------------------------
def mu_values() -> dict[str, str]:
    """The fit of μ as ``scripts/fit_mu.py`` reads its stored scan: ``mu_A_star`` is split
    A's μ*, ``mu_A_held_star`` its held-out score (%) there, and so on."""
    from generate import script

    fit = script("fit_mu")
    runs = fit.load_runs(fit.DATA)
    summary = pd.read_csv(fit.DATA / fit.SUMMARY_FILE).sort_values("mu")
    preset = fit.preset_mu()
    res = fit.results(runs, summary, preset)
    at = summary.set_index("mu")
    mus = list(summary["mu"])
    out = {"mu_preset": f"{preset:g}", "mu_scan_lo": f"{mus[0]:.2f}",
           "mu_scan_hi": f"{mus[-1]:.2f}", "mu_scan_step": f"{mus[1] - mus[0]:.2f}",
           "mu_runs": str(int(summary["n_runs"].sum())), "mu_all": f"{res['mu_all']:g}"}
    for name in fit.SPLITS:
        s = res[name]
        out.update({f"mu_{name}_star": f"{s['mu_star']:g}",
                    f"mu_{name}_fit": _percent(s["r_fit"]),
                    f"mu_{name}_held_star": _percent(s["r_held_at_star"]),
                    f"mu_{name}_held_preset": _percent(s["r_held_at_preset"]),
                    f"mu_{name}_held_best": _percent(s["r_held_best"]),
                    f"mu_{name}_jackknife": _span(s["jackknife"], sep=" to ")})
    # split A's minimum is flat from the first μ within 2 points of it on
    flat = at[at["r_A_fit"] <= at["r_A_fit"].min() + 0.02].index
    flat = at.loc[flat.min():, "r_A_fit"]
    out["mu_A_flat"] = _span([round(100 * r) for r in flat])
    out["mu_A_flat_from"], out["mu_A_flat_to"] = f"{flat.index.min():g}", f"{flat.index.max():g}"
    study = pd.read_csv(DATA / "paper_table2.csv").set_index(["case", "intensity"])
    casing = study.loc[(2, "serious"), "casing_max_y_um"]
    out["study_case2_serious_casing"] = f"{casing:g}"
    for quantity, name in (("contact1_max_force_n", "force"), ("casing_max_y_um", "casing")):
        ratios = [study.loc[(2, i), quantity] / study.loc[(1, i), quantity]
                  for i in ("light", "serious")]
        out[f"study_{name}_ratio"] = _span(ratios, "{:.1f}")
    out["mu_case2_serious_casing_excess"] = _span(
        [round(100 * (v / casing - 1)) for v in summary["case2_serious_casing_max_y_um"]])
    runs_per_cell = 5
    out["mu_preset_c1i"] = _of(round(at.loc[preset, "C1i"] * runs_per_cell), runs_per_cell)
    out["mu_preset_c1j"] = _of(round(at.loc[preset, "C1j"] * runs_per_cell), runs_per_cell)
    out["mu_c1c_up_to"] = f"{at[at['C1c'] > 0.5].index.max():g}"
    sticking = at[at["C2l/m"] > 0]
    out["mu_c2lm_from"] = f"{sticking.index.min():g}"
    out["mu_c2lm_best"] = f"{sticking['C2l/m'].max():.2f}"
    return out


# ------------------------------------------------------------------------------------------
# dt-convergence.md: data/dt_convergence.csv and data/dt_convergence_runs.csv
# ------------------------------------------------------------------------------------------
CELLS = ((1, "light"), (1, "serious"), (2, "light"), (2, "serious"))


def dt_values() -> dict[str, str]:
    """The time-step study: ``dt_<quantity>_<case><intensity>_...`` from its summary."""
    runs = pd.read_csv(DATA / "dt_convergence_runs.csv")
    summary = pd.read_csv(DATA / "dt_convergence.csv").set_index(
        ["quantity", "case", "intensity"])

    def row(quantity, case, intensity):
        return summary.loc[(quantity, case, intensity)]

    steps = sorted(runs.groupby("dt_s")["n_steps"].max())
    out = {"dt_runs": str(len(runs)), "dt_wall_minutes": f"{runs['wall_s'].sum() / 60:.1f}",
           "dt_steps": ", ".join(f"{n:,}" for n in steps[:-1]) + f" and {steps[-1]:,}"}
    casing = row("casing_max_y_um", 1, "light")
    out["dt_casing_1light_shift"] = f"{casing.shift_10us:.2f}"
    out["dt_casing_1light_shift_pct"] = f"{100 * casing.shift_10us / casing.median_2p5us:.2f}"
    out["dt_casing_1light_spread"] = f"{casing.spread_10us:.2f}"

    def excess(quantity, cells):
        return [round(100 * (row(quantity, c, i).median_10us / row(quantity, c, i).median_2p5us
                             - 1)) for c, i in cells]

    case2 = [(2, "light"), (2, "serious")]
    for kind in ("sliding", "sticking"):
        q = f"contact1_{kind}_entries"
        out[f"dt_{kind}_case2_excess"] = _span(excess(q, case2))
        out[f"dt_{kind}_1light_excess"] = _span(excess(q, [(1, "light")]))
    study = pd.read_csv(DATA / "paper_table2.csv").set_index(["case", "intensity"])
    for case, intensity in CELLS:
        cell = f"{case}{intensity}"
        entries = [row(f"contact1_{k}_entries", case, intensity).median_2p5us
                   for k in ("sliding", "sticking")]
        out[f"dt_entries_{cell}"] = " / ".join(f"{v:.0f}" for v in entries)
        out[f"study_entries_{cell}"] = " / ".join(
            f"{study.loc[(case, intensity), f'contact1_{k}_entries']:.0f}"
            for k in ("sliding", "sticking"))
    forces = study["contact1_min_force_n"]
    out["study_min_force"] = _span([round(f) for f in forces])
    out["study_min_force_case1"] = _span([round(f) for f in forces.loc[1]])
    minimum = row("contact1_min_force_n", 1, "light")
    out["dt_min_force_1light_medians"] = " / ".join(
        f"{minimum[f'median_{d}']:.3g}" for d in ("10us", "5us", "2p5us"))
    every = summary.loc["contact1_min_force_n"]
    out["dt_min_force_span_2p5"] = f"{every['min_2p5us'].min():.2g}–{every['max_2p5us'].max():.2g}"
    single = runs[(runs["case"] == 1) & (runs["intensity"] == "light")
                  & (runs["gap_ramp_s"] == 0.1)].sort_values("dt_s", ascending=False)
    out["dt_min_force_single_run"] = " → ".join(
        f"{v:.1f}" for v in single["contact1_min_force_n"])
    long = summary.loc["contact1_min_force_100us_n"]
    out["dt_min_force_100us_medians"] = ", ".join(
        f"{long.loc[cell, 'median_2p5us']:.0f}" for cell in CELLS[:-1]) + (
        f" and {long.loc[CELLS[-1], 'median_2p5us']:.0f}")
    case1 = long.loc[[1]]
    lo = case1[["min_10us", "min_5us", "min_2p5us"]].min().min()
    hi = case1[["max_10us", "max_5us", "max_2p5us"]].max().max()
    out["dt_min_force_100us_case1_span"] = f"{lo:.0f}–{hi:.0f}"
    share = row("contact1_sticking_share", 2, "light")
    out["dt_sticking_share_2light"] = f"{share.median_5us:.3f} to {share.median_2p5us:.3f}"
    out["dt_sticking_share_2light_pct"] = f"{100 * share['shift'] / share.median_5us:.0f}"
    return out


# ------------------------------------------------------------------------------------------
# step-study.md: data/step_study.csv
# ------------------------------------------------------------------------------------------
def step_values() -> dict[str, str]:
    """The step study at each tolerance: ``step_<ensemble>_<family>_p95`` (95th percentile
    of change / scatter at the default tolerance), the simulation time ratios and the labels."""
    from generate import script

    study = script("step_study")
    table = pd.read_csv(DATA / "step_study.csv")
    default = table[table["step_error"] == 1e-5].set_index(["ensemble", "family"])
    out = {"step_floor": f"{100 * study.FLOOR:g}", "step_goal": "a quarter"
           if study.GOAL == 0.25 else f"{study.GOAL:g}"}
    for (ensemble, family), r in default.iterrows():
        out[f"step_{ensemble}_{family.replace(' ', '_')}_p95"] = f"{r.ratio_p95:.3f}"
    labels = table.drop_duplicates(["ensemble", "step_error"])["labels_same"].str.split("/")
    same = sum(int(a) for a, _ in labels) // table["step_error"].nunique()
    total = sum(int(b) for _, b in labels) // table["step_error"].nunique()
    out["step_labels_same"] = _of(same, total)
    study_families = ("order lines", "sidebands", "combinations")
    worst = default.loc[[("rub", f) for f in study_families], "ratio_p95"].max()
    out["step_rub_study_p95"] = f"{worst:.2f}"
    contact = table[(table["ensemble"] == "rub") & (table["family"] == "contact statistics")]
    out["step_rub_contact_span"] = _span(
        list(contact["ratio_p95"]) + list(contact["ratio_max"]), "{:.1f}")
    for step_error, name in ((1e-5, "default"), (1e-6, "tight")):
        times = table[table["step_error"] == step_error].drop_duplicates("ensemble")
        for r in times.itertuples():
            out[f"step_time_{name}_{r.ensemble}"] = f"{r.simulate_s_ratio:.2f}"
    return out


# ------------------------------------------------------------------------------------------
# model-uncertainty.md and checked-against.md: data/uncertainty.csv, data/ross_references.json
# ------------------------------------------------------------------------------------------
def rig_values() -> dict[str, str]:
    """What moves the damping ratio's threshold of instability, and which ROSS computed the
    references."""
    import json

    table = pd.read_csv(DATA / "uncertainty.csv")
    nominal = table.loc[table["factor"] == "nominal", "threshold_rpm"].iloc[0]
    moved = table.loc[table["factor"] == "damping_ratio", "threshold_rpm"] / nominal - 1
    made = json.loads((DATA / "ross_references.json").read_text(encoding="utf-8"))["generated"]
    return {"uncertainty_damping_threshold": " and ".join(
                f"{100 * m:+.0f} %".replace("-", "−") for m in sorted(moved)),
            "ross_version": made["ross"],
            "ross_python": ".".join(made["python"].split(".")[:2])}


# ------------------------------------------------------------------------------------------
# table2.md and index.md, the sensitivity sweep: data/sensitivity.csv and
# data/sensitivity_findings.csv (scripts/sensitivity.py)
# ------------------------------------------------------------------------------------------
SWEEP_CELLS = ("case1_light", "case1_serious", "case2_light", "case2_serious")
#: the sweep's default setting (the paper rig preset) under the name each knob gives it
SWEEP_DEFAULT = {"casing_support": "casing_support=distributed", "dt": "dt=1e-05",
                 "window": "window=2.3"}
#: the settings that change the contact's or the casing's law rather than a number the
#: study leaves open within the preset's model: a tight augmentation band, a point support
SWEEP_OTHER_LAWS = ("augmentation=eps10um", "casing_support=point")


def _signed_span(fractions) -> str:
    """``−7 … +7`` (per cent) of ``fractions``."""
    return " … ".join(f"{100 * f:+.0f}".replace("-", "−")
                      for f in (min(fractions), max(fractions)))


def sensitivity_values() -> dict[str, str]:
    """The sensitivity sweep's findings, one knob at a time around the preset."""
    rows = pd.read_csv(DATA / "sensitivity.csv")
    found = pd.read_csv(DATA / "sensitivity_findings.csv")
    at = rows.set_index(["setting", "cell"])

    def q(setting: str, cell: str, name: str) -> float:
        return float(at.loc[(setting, cell), name])

    def ratio(a: str, b: str, cell: str, name: str) -> float:
        return q(a, cell, name) / q(b, cell, name)

    def severity(settings, name: str) -> str:
        """Case 2 over case 1 at the same gap, over ``settings``."""
        return _span([q(s, f"case2_{g}", name) / q(s, f"case1_{g}", name)
                      for s in settings for g in ("light", "serious")], "{:.1f}")

    settings = list(dict.fromkeys(rows["setting"]))
    within = [s for s in settings if s not in SWEEP_OTHER_LAWS]
    histories = [s for s in settings if s.startswith("gap_ramp=")]
    vs_study = {c: [q(s, c, "casing_max_y_um") / q(s, c, "paper_casing_max_y_um")
                    for s in histories] for c in SWEEP_CELLS}
    late = max(abs(ratio("window=4.3", SWEEP_DEFAULT["window"], c, name) - 1)
               for c in SWEEP_CELLS
               for name in ("rotor_max_y_mm", "casing_max_y_um", "contact1_max_force_n"))

    def present(setting: str, order: str) -> bool:
        return max(q(setting, "case1_serious", f"{p}_amp_{order}")
                   for p in ("shaft", "blade")) > 0

    stick_over_slide = (rows["contact1_mean_force_sticking_n"]
                        / rows["contact1_mean_force_sliding_n"]).min()
    pairs = rows[rows["case"] == 2][["shaft_combo_fa_hz", "shaft_combo_fb_hz"]].dropna()
    point, spread = "casing_support=point", SWEEP_DEFAULT["casing_support"]
    case2 = ("case2_light", "case2_serious")
    entries = [abs(ratio("dt=5e-06", SWEEP_DEFAULT["dt"], c, f"contact1_{kind}_entries") - 1)
               for c in SWEEP_CELLS for kind in ("sliding", "sticking")]
    return {
        "sweep_settings": str(len(settings)),
        "sweep_force_severity": severity(within, "contact1_max_force_n"),
        "sweep_casing_severity": severity(within, "casing_max_y_um"),
        "sweep_force_severity_other": severity(SWEEP_OTHER_LAWS, "contact1_max_force_n"),
        "sweep_casing_severity_other": severity(SWEEP_OTHER_LAWS, "casing_max_y_um"),
        "sweep_stick_force": f"{stick_over_slide:.1f}",
        "sweep_pair_settings": _of(found["b_combination"].sum(), len(found)),
        "sweep_pair_hz": " + ".join(f"{pairs[c].median():.0f}" for c in pairs),
        "sweep_force_vs_study": _signed_span(
            [q(s, c, "contact1_max_force_n") / q(s, c, "paper_contact1_max_force_n") - 1
             for s in histories for c in SWEEP_CELLS]),
        "sweep_casing_vs_study": _span([r for c in SWEEP_CELLS[:3] for r in vs_study[c]],
                                       "{:.2f}"),
        "sweep_casing_vs_study_2serious": _span(vs_study["case2_serious"], "{:.2f}"),
        "sweep_late_window": _percent(late),
        "sweep_7x2_histories": f"{sum(present(s, '3p5x') for s in histories)}/{len(histories)}",
        "sweep_3x2_histories": f"{sum(present(s, '1p5x') for s in histories)}/{len(histories)}",
        "sweep_eps10_force_kn": _span([q("augmentation=eps10um", c, "contact1_max_force_n")
                                       / 1e3 for c in case2], "{:.1f}"),
        "sweep_point_force": _span([100 * (ratio(point, spread, c, "contact1_max_force_n") - 1)
                                    for c in case2], "{:.0f}"),
        "sweep_point_casing": _span([ratio(point, spread, c, "casing_max_y_um") for c in case2],
                                    "{:.1f}"),
        "sweep_point_sidebands": _span([q(point, c, "shaft_sb_4x_delta_hz")
                                        for c in SWEEP_CELLS[:2]], "{:.1f}"),
        "sweep_dt_entries": _percent(max(entries)),
    }


def values() -> dict[str, str]:
    """Every substitution of the validation pages."""
    return {**confuser_values(), **transfer_values(), **learn_values(), **mu_values(),
            **dt_values(), **step_values(), **rig_values(), **sensitivity_values()}
