"""``rubdiag train``, ``rubdiag evaluate`` and ``rubdiag predict``: rub classifiers.

Everything heavy is imported inside the commands, and ``predict`` imports nothing of the
simulator: it runs on a machine's measurements with the model folder alone.
"""

from __future__ import annotations

import json
import math
import sys
from pathlib import Path

from rubdiag.cli._defaults import FromLibrary
from rubdiag.cli._quiet import add_quiet_option

#: the function ``train`` calls, whose keywords the options stand for
_TRAIN = "rubdiag.learn._train:train."


def register(sub) -> None:
    """Add the ``train``, ``evaluate`` and ``predict`` commands."""
    p = sub.add_parser(
        "train", help="train a rub classifier on a dataset and save it as a model folder",
        description="Evaluate a classifier on the dataset (cross-validated on --split: "
        "held-out scores with 95 % intervals, baselines, shuffled-label control, leakage "
        "audit), fit it on every run and write MODEL_DIR: model.skops and model.json (what "
        "prediction needs), metrics.json, report.md, confusion.png, importances.png and "
        "importances.csv. The default model — target rub, a random forest, split by design "
        "point, the shaft channels that carry more than their noise floor — needs no "
        "tuning and does not lean on the casing channel, which in this model moves only "
        "through contact. Warnings (a class with too few runs, a class never recognised, "
        "no margin over the best baseline or chance, a shuffled-label control above "
        "chance) are printed on stderr and written into the report, metrics.json and "
        "model.json: the same list. See the documentation, 'Classifiers'.")
    p.add_argument("dataset", type=Path, metavar="DATASET_DIR",
                   help="dataset folder (rubdiag dataset)")
    p.add_argument("--out", type=Path, metavar="MODEL_DIR", required=True,
                   help="model folder to write (new or empty; --overwrite replaces a model)")
    p.add_argument("--target", metavar="LABEL", action=FromLibrary,
                   default_of=_TRAIN + "target", choices_of="rubdiag.learn:TARGETS",
                   help="label to predict, one of {choices} (default: {default}; rub, on a "
                   "dataset with other faults, is rub against everything else); fault: the "
                   "faults that acted (none, rub, crack, rub+crack …: a dataset with a fault "
                   "factor)")
    p.add_argument("--estimator", metavar="NAME", action=FromLibrary,
                   default_of=_TRAIN + "estimator", choices_of="rubdiag.learn:ESTIMATORS",
                   help="one of {choices}: random forest, gradient boosting, RBF SVM or "
                   "logistic regression (default: {default})")
    p.add_argument("--split", action=FromLibrary, default_of=_TRAIN + "split",
                   help="evaluation split: group (by design point) or a design factor held "
                   "out band by band (speed_ratio, gap_mm, case …); default {default}")
    p.add_argument("--channels", metavar="NAME,…", action=FromLibrary,
                   default_of=_TRAIN + "channels",
                   shows={"margin": "rubdiag.learn._channel_choice:NOISE_MARGIN_DB"},
                   help="input channels: auto (the shaft channels whose median power over "
                   "the rubbing runs is {margin} dB or more above their noise floor), shaft (every "
                   "channel not on the casing), all, or comma-separated names; default "
                   "{default}")
    p.add_argument("--families", metavar="NAME,…", action=FromLibrary,
                   shows={"families": "rubdiag.learn._features:FAMILIES",
                          "default_families": _TRAIN + "families"},
                   help="feature families, comma-separated, of {families} (default: "
                   "{default_families})")
    p.add_argument("--n-splits", type=int, metavar="K", action=FromLibrary,
                   default_of="rubdiag.learn._splits:folds.n_splits",
                   help="folds of the group split (default: {default})")
    p.add_argument("--seed", type=int, action=FromLibrary, default_of=_TRAIN + "seed",
                   help="seed of folds and models (default {default})")
    p.add_argument("--quick", action="store_true",
                   help="skip the permutation importances, baselines and leakage audit "
                   "(no importances files)")
    p.add_argument("--overwrite", action="store_true",
                   help="replace the model already in MODEL_DIR")
    p.add_argument("--leave-out", metavar="FACTOR=LO:HI",
                   help="train without the runs whose design factor FACTOR lies in LO..HI "
                   "(both included), to score the model on them with rubdiag evaluate "
                   "--band: a level of a model-uncertainty factor, a speed band, a case")
    add_quiet_option(p)
    p.set_defaults(func=_train)

    p = sub.add_parser(
        "evaluate", help="score a saved model on another dataset or on labelled records",
        description="Predict every run of the dataset DATA (or of one band of it, --band), "
        "or every file of the labelled record list DATA, with the model of MODEL_DIR and "
        "score it: "
        "macro-F1 and balanced accuracy with 95 % bootstrap intervals over design points "
        "(records: each its own), per-class precision and recall, the confusion matrix and, "
        "for a rub or fault model, the false rub alarm rate and the rub recall per confuser "
        "(a dataset with faults beside rub) and per kind of run or record, with Wilson "
        "intervals. A record list is a CSV: file (a signal file, its path absolute or "
        "relative to the list), a label column (rub, severity, rub_state, or faults: none, "
        "rub, crack, rub+crack ...), optionally kind (any words; the per-kind scores) and "
        "speed_rpm (empty: the tacho or the estimate); each file is predicted as rubdiag "
        "predict does, by the majority of its windows. Runs of a class the model does not "
        "know are counted, not scored.")
    p.add_argument("model", type=Path, metavar="MODEL_DIR", help="model folder (rubdiag train)")
    p.add_argument("dataset", type=Path, metavar="DATA",
                   help="dataset folder, or labelled record list (.csv)")
    p.add_argument("--band", metavar="FACTOR=LO:HI",
                   help="score only the runs whose design factor FACTOR lies in LO..HI "
                   "(both included): the band a model was trained without (rubdiag train "
                   "--leave-out)")
    p.add_argument("--json", action="store_true", help="print the scores as JSON")
    add_quiet_option(p)
    p.set_defaults(func=_evaluate)

    p = sub.add_parser(
        "predict", help="classify measured signals (or a dataset's runs) with a saved model",
        description="Cut each signal file into windows of the model's training length, "
        "compute the features of the model's channels at each window's speed and print, "
        "per window, the class and the class probabilities, then per input the majority "
        "(window 'all'). A speed or features outside the training ranges is told on stderr "
        "(one warning line each); the prediction is then an extrapolation. A dataset "
        "folder's stored runs are predicted one row each. Many files go in one call (the "
        "model is loaded once): a folder, a quoted glob pattern, or a list. Each file's "
        "speed is the first of: its row in --speeds, its tacho (--tacho, or a column named "
        "tacho when --speed-rpm is not given), --speed-rpm, the estimate per window; the "
        "table's speed_source column says which, and speed_ambiguous flags an estimate "
        "whose 1x may be a line at 1/2 or 1/3 of the strongest (a warning line says so). "
        "The model's training warnings are told once per call.")
    p.add_argument("model", type=Path, metavar="MODEL_DIR", help="model folder (rubdiag train)")
    p.add_argument("inputs", nargs="+", metavar="INPUT",
                   help="signal file (.csv/.txt with a header row, .npz, .parquet; a time "
                   "column t/time/time_s/t_s gives fs), folder of signal files (all of them, "
                   "sorted by name), glob pattern in quotes ('plant/*.csv'; '**' for "
                   "subfolders), or dataset folder")
    p.add_argument("--column", action="append", default=[], metavar="COLUMN=CHANNEL",
                   help="the file's COLUMN holds the model's CHANNEL (repeatable)")
    p.add_argument("--unit", action="append", default=[], metavar="CHANNEL=UNIT",
                   help="CHANNEL's values are in UNIT (default: the model's, SI): m, mm, "
                   "um, µm, mil; m/s, mm/s, in/s; m/s^2, mm/s^2, g; N, kN (repeatable)")
    p.add_argument("--fs", type=float, metavar="HZ", help="sampling frequency in Hz")
    speed = p.add_mutually_exclusive_group()
    speed.add_argument("--speed-rpm", type=float, metavar="RPM",
                       help="running speed of every file (default: from a tacho column, else "
                       "the dominant line of the model's channels, per window)")
    speed.add_argument("--tacho", metavar="COLUMN",
                       help="once-per-revolution pulse column giving the speed "
                       "(default: a column 'tacho'); with --speeds, of the files it leaves "
                       "without a speed")
    p.add_argument("--speeds", type=Path, metavar="FILE.csv",
                   help="each file's running speed: a CSV with the columns file (its path "
                   "as given, or its file name) and speed_rpm (rpm; empty: that file's tacho "
                   "or estimate). Every input file needs a row; rows of other files are "
                   "ignored. Not with --speed-rpm")
    p.add_argument("--out", type=Path, metavar="TABLE",
                   help="write the table to TABLE (.csv, .parquet or .json) instead of "
                   "printing it; a folder or pattern among the inputs leaves TABLE and the "
                   "--speeds file out")
    p.add_argument("--json", action="store_true", help="print the table as JSON records")
    add_quiet_option(p)
    p.set_defaults(func=_predict)


def _names(text: str | None, option: str) -> list[str] | None:
    if text is None:
        return None
    names = [n.strip() for n in text.split(",") if n.strip()]
    if not names:
        raise ValueError(f"{option} {text!r} names nothing (allowed: comma-separated names)")
    return names


def _pairs(values: list[str], option: str, what: str) -> dict[str, str]:
    out = {}
    for value in values:
        key, sep, item = value.partition("=")
        if not sep or not key.strip() or not item.strip():
            raise ValueError(f"{option} {value!r} is not {what}")
        out[key.strip()] = item.strip()
    return out


def _band(text: str | None, option: str):
    """``FACTOR=LO:HI`` as ``(factor, lo, hi)``; None for None."""
    if text is None:
        return None
    factor, sep, span = text.partition("=")
    lo, colon, hi = span.partition(":")
    try:
        if not (sep and colon and factor.strip()):
            raise ValueError
        return factor.strip(), float(lo), float(hi)
    except ValueError:
        raise ValueError(f"{option} {text!r} is not FACTOR=LO:HI (e.g. "
                         "bearing_clearance_scale=1.05:1.05)") from None


def _train(args) -> int:
    from rubdiag.learn._train import check_out

    out = check_out(args.out, args.overwrite, option="--out")   # before any work
    if args.n_splits < 2:
        raise ValueError(f"--n-splits = {args.n_splits} is out of range (allowed: >= 2)")
    from rubdiag.learn import DEFAULT_FAMILIES, train
    from rubdiag.learn._channel_choice import CHANNEL_SETS

    channels = args.channels if args.channels in CHANNEL_SETS else _names(
        args.channels, "--channels")
    families = _names(args.families, "--families") or DEFAULT_FAMILIES
    extras = {"importances": False, "baselines": False, "audit": False} if args.quick else {}
    model = train(args.dataset, out, target=args.target, estimator=args.estimator,
                  split=args.split, channels=channels, seed=args.seed, families=families,
                  overwrite=args.overwrite, n_splits=args.n_splits,
                  progress=not args.quiet, leave_out=_band(args.leave_out, "--leave-out"),
                  **extras)
    meta = model.meta
    f1 = meta["scores"]["macro_f1"]
    print(f"{out}: {meta['target']} classifier ({meta['estimator']}; channels "
          f"{', '.join(model.channels)}), trained on {meta['dataset']['n_rows']} runs; "
          f"held-out macro-F1 {f1['value']:.3f} [{f1['lo']:.3f}, {f1['hi']:.3f}] on split "
          f"{meta['split']}")
    left_out = meta.get("channels_left_out") or {}
    if left_out:
        from rubdiag.learn._channel_choice import NOISE_MARGIN_DB, decibels

        shown = ", ".join(f"{c} {decibels(db)}" if db is not None else f"{c} (reads 0)"
                          for c, db in left_out.items())
        print(f"left out (median power over the rubbing runs within {NOISE_MARGIN_DB:g} dB "
              f"of the noise floor): {shown}; --channels names the channels to use")
    if meta.get("confusers"):
        import pandas as pd

        from rubdiag.learn._confusers import confuser_lines

        table = pd.DataFrame(meta["confusers"]).astype({"rate": float, "lo": float, "hi": float})
        print("held out, rub against the faults that look like it (rate [95 % interval]):")
        for line in confuser_lines(table):
            print(f"  {line}")
    for w in meta.get("warnings", []):
        _warn("train", w)
    print(f"wrote {', '.join(sorted(p.name for p in out.iterdir()))}; the evaluation is in "
          f"{out / 'report.md'}")
    return 0


def _evaluate(args) -> int:
    band = _band(args.band, "--band")          # before any work
    from rubdiag import _progress
    from rubdiag.learn import evaluate, load_model

    with _progress.bar(1, "evaluate", "step", not args.quiet) as bar:   # and its own steps
        _progress.label(bar, "reading the model")
        model = load_model(args.model)
        bar.update()
        result = evaluate(model, args.dataset, progress=bar, band=band)
    _model_warnings("evaluate", args.model, model.meta.get("warnings", []))
    for w in result.warnings:
        _warn("evaluate", w)
    if args.json:
        json.dump(result.to_dict(), sys.stdout, indent=1)
        print()
    else:
        print(result.to_text())
    return 0


def _predict(args) -> int:
    from rubdiag.cli._paths import output_file

    out = None if args.out is None else output_file(args.out)       # before any work
    if out is not None:
        _table_format(out)
        if args.json:
            raise ValueError("--json prints the table; --out writes it (allowed: one of them)")
    if args.speeds is not None and args.speed_rpm is not None:
        raise ValueError("--speeds and --speed-rpm exclude each other (allowed: one of them; "
                         "a file whose speed_rpm is empty in --speeds takes its tacho or the "
                         "estimate)")
    from rubdiag.learn import load_model, predict
    from rubdiag.learn._inputs import expand_inputs, read_speeds

    speeds = None if args.speeds is None else read_speeds(args.speeds)
    left_out = [p for p in (args.speeds, out) if p is not None]
    files = [str(f) for f, _ in expand_inputs(args.inputs, exclude=left_out)]
    model = load_model(args.model)
    table = predict(model, files,
                    columns=_pairs(args.column, "--column", "COLUMN=CHANNEL"),
                    units=_pairs(args.unit, "--unit", "CHANNEL=UNIT"), fs=args.fs,
                    speed_rpm=args.speed_rpm if speeds is None else speeds,
                    tacho=args.tacho, progress=not args.quiet)
    # with a prediction (a bad input is one line), once per call, not the small-class counts
    _model_warnings("predict", args.model, table.attrs["model_warnings"])
    for row in table.itertuples():
        if row.warnings and row.window != "all":
            _warn("predict", f"{row.input}, window {row.window}: {row.warnings}")
    if out is not None:
        _write_table(table, out)
        inputs = table.loc[table["window"] == "all", "input"].nunique()
        print(f"wrote {out}: {len(table)} rows ({inputs} files, their windows and "
              "majorities)" if inputs else f"wrote {out}: {len(table)} rows")
        return 0
    if args.json:
        json.dump(_records(table), sys.stdout, indent=1, default=_plain)
        print()
        return 0
    import pandas as pd

    shown = table.drop(columns=["warnings"])
    with pd.option_context("display.max_rows", None, "display.max_columns", None,
                           "display.width", 200, "display.float_format", "{:.3f}".format):
        print(shown.to_string(index=False))
    if model.meta["target"] == "fault":
        for line in _fault_verdicts(table):
            print(line)
    return 0


#: ``--out`` suffix -> table format
_TABLE_FORMATS = {".csv": "csv", ".parquet": "parquet", ".pq": "parquet", ".json": "json"}


def _table_format(path: Path) -> str:
    fmt = _TABLE_FORMATS.get(path.suffix.lower())
    if fmt is None:
        raise ValueError(f"--out {path}: unknown table format {path.suffix or '(none)'!r} "
                         f"(allowed: {', '.join(_TABLE_FORMATS)})")
    return fmt


def _records(table) -> list[dict]:
    """The table's rows as JSON records (NaN as null)."""
    return [{k: (None if isinstance(v, float) and math.isnan(v) else v) for k, v in r.items()}
            for r in table.to_dict(orient="records")]


def _write_table(table, path: Path) -> None:
    """``table`` to ``path`` as its suffix says (written whole or not at all); in parquet
    the ``window`` column is text ("0", "1" …, "all"): a column holds one type there."""
    import io

    from rubdiag._atomic import write_bytes, write_text

    fmt = _table_format(path)
    if fmt == "csv":
        write_text(path, table.to_csv(index=False))
    elif fmt == "json":
        write_text(path, json.dumps(_records(table), indent=1, default=_plain) + "\n")
    else:
        sink = io.BytesIO()
        table.astype({"window": str}).to_parquet(sink, index=False)
        write_bytes(path, sink.getvalue())


def _fault_verdicts(table) -> list[str]:
    """A fault model's verdict per input (its "all" row; a dataset's runs one by one): the
    most likely fault, P(rub), and where rub is likely the most likely fault without it."""
    from rubdiag.learn._predict import RUB_LIKELY

    whole = set(table.loc[table["window"] == "all", "input"])
    lines = []
    for r in table.itertuples():
        if r.window != "all" and r.input in whole:
            continue
        line = (f"{r.input}: most likely {r.predicted} (p = {r.p_predicted:.2f}); "
                f"P(rub) = {r.p_rubbing:.2f}")
        if r.p_rubbing >= RUB_LIKELY and r.confuser:
            line += (f": rub likely; the most likely fault without rub is {r.confuser} "
                     f"(p = {r.p_confuser:.2f})")
        lines.append(line)
    return lines


def _model_warnings(command: str, folder, warnings: list) -> None:
    """What the model's training warned of (``warnings``), once each, on stderr."""
    for w in warnings:
        _warn(command, f"model {folder} (from its training, see its report.md): {w}")


def _warn(command: str, text: str) -> None:
    print(f"rubdiag {command}: warning: {text}", file=sys.stderr)


def _plain(value):
    try:
        return value.item()
    except AttributeError:
        return str(value)
