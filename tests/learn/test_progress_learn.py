"""Progress of ``train`` and ``cross_validate``: on a terminal a bar over the fits (every fold of
every cross-prediction, of the importances and of the audit, then the final fit) or over
evaluate's steps, reaching its total; off a terminal or with ``--quiet``, nothing on stderr
but the warnings. On the tiny dataset (12 runs), with logistic regression for speed."""

from fake_terminal import as_terminal, counts

from rubdiag.cli import main

FOLDS = 2
QUICK = ["--estimator", "logreg", "--quick", "--n-splits", str(FOLDS)]


def test_train_counts_every_fit(tiny_dataset, tmp_path, monkeypatch):
    terminal = as_terminal(monkeypatch)
    assert main(["train", str(tiny_dataset), "--out", str(tmp_path / "m"), *QUICK]) == 0
    # --quick: per fold the model and the 5 shuffled-label controls; then the final fit
    fits = FOLDS * (1 + 5) + 1
    assert counts(terminal.getvalue())[-1] == f"{fits}/{fits}"


def test_train_and_evaluate_write_no_progress_off_a_terminal(tiny_dataset, tmp_path, capsys):
    model = tmp_path / "m"
    assert main(["train", str(tiny_dataset), "--out", str(model), *QUICK]) == 0
    err = capsys.readouterr().err.splitlines()
    assert all(line.startswith("rubdiag train: warning: ") for line in err), err
    assert main(["evaluate", str(model), str(tiny_dataset)]) == 0
    err = capsys.readouterr().err.splitlines()
    assert all(line.startswith("rubdiag evaluate: warning: ") for line in err), err


def test_evaluate_counts_its_steps_and_quiet_silences_them(tiny_dataset, tmp_path, monkeypatch):
    model = tmp_path / "m"
    assert main(["train", str(tiny_dataset), "--out", str(model), *QUICK]) == 0
    terminal = as_terminal(monkeypatch)
    assert main(["evaluate", str(model), str(tiny_dataset)]) == 0
    # reading the model, reading the data, predicting, scoring
    assert counts(terminal.getvalue())[-1] == "4/4"
    terminal = as_terminal(monkeypatch)
    assert main(["evaluate", str(model), str(tiny_dataset), "--quiet"]) == 0
    lines = terminal.getvalue().splitlines()
    assert lines and all(line.startswith("rubdiag evaluate: warning: ") for line in lines)


def test_a_full_evaluation_counts_each_part_s_folds(tiny_dataset, monkeypatch):
    """Per fold: the model, the importances, three baselines, the model with or without the
    casing channels, five shuffled-label controls and the audit (a part with nothing to
    fit counts as done)."""
    from rubdiag.learn import cross_validate

    terminal = as_terminal(monkeypatch)
    cross_validate(tiny_dataset, estimator="logreg", n_splits=FOLDS, n_repeats=1, n_bootstrap=20,
             n_null=20, progress=True)
    fits = FOLDS * (1 + 1 + 3 + 1 + 5 + 1)
    assert counts(terminal.getvalue())[-1] == f"{fits}/{fits}"
