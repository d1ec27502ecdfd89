"""Damaged dataset files: an empty, truncated, garbled or bit-flipped chunk, or a
truncated journal row, is one line naming the file — from ``load``, ``rubdiag train`` and
``rubdiag.learn._evaluate`` (and, in a slow test, ``rubdiag evaluate`` and ``rubdiag predict
MODEL DATA``) — never a traceback, and the command that line names
(``rubdiag dataset DIR/design.toml --out DIR``) moves the file into ``DIR/broken/``
(kept, byte for byte) and runs again exactly the runs it held: every run ends up once, with
the rows an undamaged folder has. Readers write nothing.

The folder is a 4-run dataset written with a chunk per row (``chunk_rows=1``), so that a
damaged chunk holds one run and the others stay readable."""

import json
import random
import shutil
from pathlib import Path

import pandas as pd
import pytest

from rubdiag.cli import main
from rubdiag.dataset import Design, generate, load
from rubdiag.dataset._rows import PROVENANCE
from rubdiag.learn import cross_validate

TOML = """
[base]
rig = "paper"
duration_s = 0.3
discard_s = 0.1

[sampling]
method = "grid"
replicates = 2

[factors]
case = [2]
speed_ratio = [1.0]
gap_mm = [1.9, 4.0]
"""


@pytest.fixture(scope="module")
def pristine(tmp_path_factory):
    out = tmp_path_factory.mktemp("pristine") / "dataset"
    summary = generate(Design.from_toml(TOML), out, jobs=1, progress=False, chunk_rows=1)
    assert (summary["ok"], summary["failed"]) == (4, 0)
    assert [p.name for p in sorted((out / "features").iterdir())] == [
        f"part-00000{i}.parquet" for i in (1, 2, 3, 4)]
    assert not (out / "journal").exists()
    return out


def comparable(rows: pd.DataFrame) -> pd.DataFrame:
    return rows.drop(columns=list(PROVENANCE)).sort_values("run_id").reset_index(drop=True)


def snapshot(root: Path) -> dict:
    return {p.relative_to(root).as_posix(): (p.stat().st_size, p.stat().st_mtime_ns)
            for p in [root, *root.rglob("*")]}


def chunk_ids(out: Path) -> list[str]:
    return list(pd.read_parquet(out / "features")["run_id"])


# each damage: (what it does to the folder) -> the damaged file; the chunk damaged is the
# second, which holds one run; the journal row stands for the fourth run's row, its chunk
# gone (a job killed before it moved the row, then a disk that lost the row's end)
def truncated(out: Path) -> Path:
    path = out / "features" / "part-000002.parquet"
    data = path.read_bytes()
    path.write_bytes(data[:len(data) // 2])
    return path


def empty(out: Path) -> Path:
    path = out / "features" / "part-000002.parquet"
    path.write_bytes(b"")
    return path


def garbage(out: Path) -> Path:
    path = out / "features" / "part-000002.parquet"
    path.write_bytes(random.Random(24).randbytes(4096))
    return path


def flipped(out: Path) -> Path:
    """Eight bytes inverted in the first column's data: the size, the header and the footer
    are intact, so only the page checksums can tell."""
    path = out / "features" / "part-000002.parquet"
    data = bytearray(path.read_bytes())
    for i in range(64, 72):
        data[i] ^= 0xFF
    path.write_bytes(bytes(data))
    return path


def journal_row(out: Path) -> Path:
    chunk = out / "features" / "part-000004.parquet"
    row = pd.read_parquet(chunk).iloc[0].to_dict()
    chunk.unlink()
    text = json.dumps({k: (v.item() if hasattr(v, "item") else v) for k, v in row.items()})
    path = out / "journal" / "row-000001.json"
    path.parent.mkdir()
    path.write_text(text[:len(text) // 2])
    return path


DAMAGES = [truncated, empty, garbage, flipped, journal_row]


@pytest.fixture(params=DAMAGES, ids=lambda f: f.__name__)
def damaged(request, pristine, tmp_path):
    out = tmp_path / "dataset"
    shutil.copytree(pristine, out)
    return out, request.param(out)


def test_load_names_the_file_in_one_line_and_writes_nothing(damaged):
    out, path = damaged
    before = snapshot(out)
    with pytest.raises(ValueError) as info:
        load(out)
    message = str(info.value)
    assert "\n" not in message
    assert message.startswith(f"{path}: unreadable (")
    assert message.endswith(f"; `rubdiag dataset {out / 'design.toml'} --out {out}` moves it "
                            f"into {out / 'broken'} and runs its runs again")
    with pytest.raises(ValueError, match="unreadable"):
        cross_validate(out)                                    # rubdiag.learn reads through load
    assert snapshot(out) == before


def test_train_says_it_in_one_line_and_exit_2(damaged, capsys, tmp_path):
    out, path = damaged
    code = main(["train", str(out), "--out", str(tmp_path / "model")])
    err = capsys.readouterr().err
    assert code == 2
    assert err.count("\n") == 1 and err.startswith(f"rubdiag train: error: {path}: unreadable")
    assert not (tmp_path / "model").exists()


def test_the_named_command_sets_it_aside_and_runs_its_run_again(damaged, pristine, capsys):
    out, path = damaged
    data = path.read_bytes()
    code = main(["dataset", str(out / "design.toml"), "--out", str(out), "--jobs", "1",
                 "--no-progress"])
    captured = capsys.readouterr()
    assert code == 0, captured.err
    kept = out / "broken" / path.name
    assert captured.err.count("\n") == 1
    assert captured.err.startswith(f"rubdiag dataset: warning: {path}: unreadable (")
    assert captured.err.endswith(f"); moved to {kept}, its runs run again\n")
    assert kept.read_bytes() == data                  # kept as it was, for a look
    # exactly the damaged file's run ran again
    assert "4 runs, 3 already stored, 1 ok and 0 failed now" in captured.out
    rows = load(out)
    pd.testing.assert_frame_equal(comparable(rows), comparable(load(pristine)),
                                  check_exact=True)
    assert sorted(chunk_ids(out)) == sorted(rows["run_id"])    # each run in one chunk
    assert not (out / "journal").exists()
    # and the folder is whole: nothing more to do, nothing more set aside
    assert main(["dataset", str(out / "design.toml"), "--out", str(out), "--jobs", "1",
                 "--no-progress"]) == 0
    assert "4 runs, 4 already stored, 0 ok" in capsys.readouterr().out
    assert sorted(p.name for p in (out / "broken").iterdir()) == [path.name]


def test_a_dry_run_counts_its_runs_to_run_and_writes_nothing(pristine, tmp_path, capsys):
    out = tmp_path / "dataset"
    shutil.copytree(pristine, out)
    path = truncated(out)
    before = snapshot(out)
    code = main(["dataset", str(out / "design.toml"), "--out", str(out), "--dry-run"])
    stdout = capsys.readouterr().out
    assert code == 0
    assert "4 runs; 1 to run (3 stored in" in stdout
    assert f"unreadable, to be moved into {out / 'broken'}" in stdout and str(path) in stdout
    assert snapshot(out) == before


@pytest.mark.slow
def test_evaluate_and_predict_name_the_file_too(tmp_path, capsys):
    """A model trained on 16 runs (``--quick``; about a minute in all), then the dataset's
    second chunk emptied: ``rubdiag evaluate`` and ``predict MODEL DATA`` end on the same
    one-line error (exit 2); after the named command, both read the folder again."""
    toml = TOML.replace("speed_ratio = [1.0]", "speed_ratio = [1.0, 1.05]").replace(
        "gap_mm = [1.9, 4.0]", "gap_mm = [1.9, 2.6, 3.2, 4.0]")
    out, model = tmp_path / "dataset", tmp_path / "model"
    generate(Design.from_toml(toml), out, jobs=2, progress=False, chunk_rows=4)
    assert main(["train", str(out), "--out", str(model), "--quick"]) == 0
    path = empty(out)
    capsys.readouterr()
    for command in ("evaluate", "predict"):
        assert main([command, str(model), str(out)]) == 2
        errors = [line for line in capsys.readouterr().err.splitlines() if "error" in line]
        assert len(errors) == 1
        assert errors[0].startswith(f"rubdiag {command}: error: {path}: unreadable (")
    assert main(["dataset", str(out / "design.toml"), "--out", str(out), "--jobs", "1",
                 "--no-progress"]) == 0
    assert "16 runs, 12 already stored, 4 ok" in capsys.readouterr().out
    for command in ("evaluate", "predict"):
        assert main([command, str(model), str(out)]) == 0


def test_a_damaged_dataset_json_is_named(pristine, tmp_path, capsys):
    """dataset.json (the format, the columns, how the channels were measured) garbled:
    train and dataset name it in one line (they said only "Expecting value: line 1 …")."""
    out = tmp_path / "dataset"
    shutil.copytree(pristine, out)
    (out / "dataset.json").write_bytes(b"\x00garbage")
    for argv in (["train", str(out), "--out", str(tmp_path / "model")],
                 ["dataset", str(out / "design.toml"), "--out", str(out), "--jobs", "1"]):
        assert main(argv) == 2
        err = capsys.readouterr().err
        assert err.count("\n") == 1
        assert f"error: {out / 'dataset.json'}: unreadable (" in err
    assert (out / "dataset.json").read_bytes() == b"\x00garbage"     # left as it was
