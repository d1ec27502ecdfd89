"""An :class:`~rubdiag.learn._evaluate.Evaluation` as JSON (``metrics.json``) and as
Markdown (``report.md``): the numbers first, then what they should be compared with."""

from __future__ import annotations

import math

import pandas as pd

from rubdiag.learn._metrics import Score

__all__ = ["confuser_markdown", "confuser_records", "evaluation_dict", "evaluation_markdown"]


def _plain(value):
    if isinstance(value, Score):              # its bounds are NaN without bootstrap draws
        return {k: _plain(v) for k, v in value.to_dict().items()}
    if isinstance(value, float) and math.isnan(value):
        return None
    if hasattr(value, "item"):
        return _plain(value.item())
    return value


def _records(frame: pd.DataFrame | None, index: str) -> list | None:
    if frame is None:
        return None
    return [{index: str(i), **{k: _plain(v) for k, v in row.items()}}
            for i, row in frame.iterrows()]


def evaluation_dict(ev) -> dict:
    """Everything of an evaluation, in JSON types (Scores as ``{value, lo, hi}``)."""
    return {
        "target": ev.target, "split": ev.split, "estimator": ev.estimator,
        "channels": ev.channels, "families": ev.families, "classes": ev.classes,
        "class_counts": ev.class_counts, "n_rows": ev.n_rows, "folds": ev.folds,
        "unscored": ev.unscored,
        "scores": {k: _plain(v) for k, v in ev.scores.items()},
        "per_class": _records(ev.per_class, "class"),
        "confusion": {"classes": ev.classes, "counts": ev.confusion.to_numpy().tolist()},
        "importances": _records(ev.importances, "feature"),
        "channel_importances": _records(ev.channel_importances, "channel"),
        "baselines": _records(ev.baselines, "baseline"),
        "casing": None if ev.casing is None else {k: _plain(v) for k, v in ev.casing.items()},
        "shuffled": None if ev.shuffled is None else {
            k: [{kk: _plain(vv) for kk, vv in run.items()} for run in v] if k == "shuffles"
            else _plain(v) for k, v in ev.shuffled.items()},
        "audit": None if ev.audit is None else ev.audit.to_dict(orient="records"),
        "confusers": confuser_records(ev.confusers),
        "notes": ev.notes,
        "channels_left_out": _left_out(ev),
        "warnings": ev.warnings,
    }


def confuser_records(table: pd.DataFrame | None) -> list | None:
    """The confuser table (:mod:`rubdiag.learn._confusers`) as JSON records (NaN: null)."""
    if table is None:
        return None
    return [{k: _plain(v) for k, v in row.items()} for row in table.to_dict(orient="records")]


def confuser_markdown(table: pd.DataFrame) -> list[str]:
    """The confuser section of a report: a line of what it is, then the table."""
    out = ["## Rub against the faults that look like it", "",
           "False rub alarm: the share of held-out runs without rub, with the fault named "
           "(none: healthy), that the model calls rubbing. Rub recall: the share of those "
           "that rubbed beside it that it calls rubbing. 95 % interval over design points.",
           "", "| measure | faults | runs | called rub | rate [95 % CI] |", "|---|---|---|---|---|"]
    for r in table.itertuples():
        rate = f"{r.rate:.3f} [{r.lo:.3f}, {r.hi:.3f}]" if r.n else "–"
        out.append(f"| {r.measure} | {r.faults} | {r.n} | {r.n_called_rub} | {rate} |")
    return [*out, ""]


def _left_out(ev) -> dict:
    """What the default channels left out: ``{"channels": {name: dB over the floor},
    "margin_db", "n_rubbing", "note"}`` (empty channels when nothing was left out)."""
    from rubdiag.learn._channel_choice import NOISE_MARGIN_DB

    choice = ev.channel_choice
    if choice is None:
        return {"channels": {}, "margin_db": NOISE_MARGIN_DB, "n_rubbing": 0, "note": ""}
    return {"channels": choice.left_out_json(), "margin_db": NOISE_MARGIN_DB,
            "n_rubbing": choice.n_rubbing, "note": choice.describe()}


def _score(value: Score) -> str:
    """A score as the report shows it; "–" for one that was not measured (NaN)."""
    return str(value) if math.isfinite(value.value) else "–"


def _table(frame: pd.DataFrame, floatfmt: str = ".3f") -> str:
    head = "| " + " | ".join([frame.index.name or "", *map(str, frame.columns)]) + " |"
    rule = "|" + "---|" * (len(frame.columns) + 1)
    lines = [head, rule]
    for i, *row in frame.itertuples(name=None):     # keeps each column's type (counts)
        cells = [format(v, floatfmt) if isinstance(v, float) else str(v) for v in row]
        lines.append("| " + " | ".join([str(i), *cells]) + " |")
    return "\n".join(lines)


def evaluation_markdown(ev, top: int = 15) -> str:
    """A report a person reads: scores, baselines, chance, audit, importances."""
    counts = ", ".join(f"{c} {n}" for c, n in ev.class_counts.items())
    out = [f"# {ev.target}: {ev.estimator}, split {ev.split}", "",
           f"{ev.n_rows} runs ({counts}); channels: {', '.join(ev.channels)}; feature "
           f"families: {', '.join(ev.families)}; {len(ev.folds)} folds.", ""]
    if ev.channel_choice is not None and ev.channel_choice.describe():
        out += [ev.channel_choice.describe(), ""]
    if ev.warnings:
        out += ["## Warnings: the model may have learnt little", ""]
        out += [f"- {w}" for w in ev.warnings] + [""]
    if ev.unscored:
        out += ["Not scored (class absent from the training fold): "
                + ", ".join(f"{c} {n}" for c, n in ev.unscored.items()) + ".", ""]
    out += ["## Held-out scores (95 % bootstrap interval over design points)", "",
            "| metric | value |", "|---|---|"]
    out += [f"| {k} | {v} |" for k, v in ev.scores.items()]
    out += ["", _table(ev.per_class), "", "Confusion (rows true, columns predicted):", "",
            _table(ev.confusion, "d"), ""]
    if ev.baselines is not None:
        out += ["## Baselines (same estimator, same folds)", "", "| baseline | macro_f1 | "
                "balanced_accuracy |", "|---|---|---|"]
        out += [f"| {name} | {_score(row['macro_f1'])} | {_score(row['balanced_accuracy'])} |"
                for name, row in ev.baselines.iterrows()]
        scored = [s.value for s in ev.baselines["macro_f1"] if math.isfinite(s.value)]
        if scored:
            out += ["", f"Model minus best baseline: "
                    f"{ev.scores['macro_f1'].value - max(scored):+.3f} macro-F1."]
        left_out = {name: row["left_out"] for name, row in ev.baselines.iterrows()
                    if row.get("left_out")}
        out += [f"Left out of \"{name}\": {unused} — blank by design for some levels "
                "(where a factor is blank tells the level)." for name, unused in left_out.items()]
        out += [""]
    if ev.casing is not None:
        out += [f"Casing channels: macro-F1 with {ev.casing['with']}, without "
                f"{ev.casing['without']}.", ""]
    if ev.confusers is not None:
        out += confuser_markdown(ev.confusers)
    if ev.shuffled is not None:
        s = ev.shuffled
        verdict = "chance, as it must be" if s["inside"] else \
            "more than chance allows (see Warnings)"
        out += ["## Shuffled labels", "", f"{s['n_shuffles']} shuffles between design points: "
                f"median macro-F1 {s['macro_f1']:.3f}, median permutation-null interval "
                f"[{s['null_lo']:.3f}, {s['null_hi']:.3f}]; {s['n_outside']} outside their "
                f"interval (chance allows {s['allowed_outside']}) — {verdict}.", ""]
    if ev.audit is not None:
        out += ["## Leakage audit: single columns that separate the classes", ""]
        if ev.audit.empty:
            out += ["None.", ""]
        else:
            shown = ev.audit.head(top)
            out += ["| column | kind | macro_f1 |", "|---|---|---|"]
            out += [f"| {r.column} | {r.kind} | {r.macro_f1:.3f} |" for r in shown.itertuples()]
            more = len(ev.audit) - len(shown)
            out += [f"\n{more} more in metrics.json." if more > 0 else "", ""]
    if ev.importances is not None:
        out += ["## Permutation importances (held-out macro-F1 drop)", "",
                _table(ev.importances.head(top), ".4f"), ""]
        if ev.channel_importances is not None:
            out += [_table(ev.channel_importances, ".4f"), ""]
    out += [f"- {n}" for n in ev.notes]
    return "\n".join(out).rstrip() + "\n"
