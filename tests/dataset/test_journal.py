"""Rows stored as they come: each finished row goes into the folder's journal and
is moved into a Parquet chunk later. Killed at any file operation of that move — or of a
retried run's replacing its old row — the folder reads every run once with its newest
row, ``pandas.read_parquet`` never sees a run twice where it was once, and the next job's
compaction leaves every run in exactly one chunk; ``load`` beside a job that compacts while
it reads still sees every run once. The progress line counts a run only once its row is
stored, a line per run in a log.

The rows here are made up (no simulation): a run id, a status and a value."""

import io
import math
import os
from pathlib import Path

import pandas as pd
import pytest

from rubdiag.dataset._chunks import row_schema
from rubdiag.dataset._generation import _Progress, _Writer
from rubdiag.dataset._store import DatasetFolder, load


class Killed(BaseException):
    """Where the process dies: nothing after it runs (a BaseException, as a kill is not an
    error any code could catch)."""


def row(run_id: str, value: float, status: str = "ok") -> dict:
    return {"run_id": run_id, "status": status, "value": value}


def new_folder(root: Path) -> DatasetFolder:
    folder = DatasetFolder(root)
    folder.create("[base]\n")
    folder.set_schema(row_schema(row("a", 0.0)))
    return folder


def raw_ids(folder: DatasetFolder) -> list[str]:
    """Every run id as the chunk files hold them, as pandas reads the folder."""
    if not folder.chunk_paths():
        return []
    return sorted(pd.read_parquet(folder.chunks_dir)["run_id"])


def values(root: Path) -> dict[str, float]:
    rows = load(root)
    assert not rows["run_id"].duplicated().any()
    return dict(zip(rows["run_id"], rows["value"], strict=True))


def snapshot(root: Path) -> dict:
    return {p.relative_to(root).as_posix(): (p.stat().st_size, p.stat().st_mtime_ns)
            for p in [root, *root.rglob("*")]}


@pytest.fixture
def kill_at(monkeypatch):
    """kill_at(n): the n-th file operation (a rename or a removal) raises Killed instead
    of running; returns the list of operations done so far."""
    done = []
    real_replace, real_unlink = os.replace, Path.unlink

    def arm(n: int) -> list:
        done.clear()

        def replace(src, dst):
            if len(done) + 1 == n:
                raise Killed
            done.append(("replace", Path(dst).name))
            real_replace(src, dst)

        def unlink(self, missing_ok=False):
            if len(done) + 1 == n:
                raise Killed
            done.append(("unlink", self.name))
            real_unlink(self, missing_ok=missing_ok)

        monkeypatch.setattr(os, "replace", replace)
        monkeypatch.setattr(Path, "unlink", unlink)
        return done

    yield arm
    monkeypatch.undo()


def crash_points(prepare, compact, expected: dict[str, float], may_double: set[str],
                 tmp_path, kill_at) -> int:
    """For n = 1, 2, …: a fresh folder (prepare), its compaction killed at the n-th file
    operation; then the checks of the module docstring (``may_double``: the runs whose old
    row pandas may read beside the new one until the next job). The number of operations
    of a whole compaction."""
    for n in range(1, 50):
        folder = prepare(tmp_path / f"kill{n}")
        ids_before = set(raw_ids(folder))
        done = kill_at(n)
        try:
            compact(folder)
            finished = True
        except Killed:
            finished = False
        kill_at(0)                                           # the next job runs in full
        before = snapshot(folder.root)
        assert values(folder.root) == expected, (n, done)
        assert snapshot(folder.root) == before                # load wrote nothing
        seen = raw_ids(folder)
        assert {i for i in seen if seen.count(i) > 1} <= may_double, (n, done, seen)
        assert ids_before <= set(seen), (n, done)          # pandas loses nothing either
        folder.compact(final=True)                           # what the next job does first
        assert raw_ids(folder) == sorted(expected), (n, done)
        assert values(folder.root) == expected
        assert not folder.journal_dir.exists()
        if finished:
            return n - 1
    raise AssertionError("the compaction never finished")


def test_a_compaction_killed_anywhere_loses_and_doubles_nothing(tmp_path, kill_at):
    def prepare(root):
        folder = new_folder(root)
        folder.write_chunk([row("a", 1.0)], row_schema(row("a", 0.0)))
        for run_id, value in (("b", 2.0), ("c", 3.0), ("d", 4.0)):
            folder.journal(row(run_id, value))
        return folder

    expected = {"a": 1.0, "b": 2.0, "c": 3.0, "d": 4.0}
    operations = crash_points(prepare, lambda f: f.compact(), expected, set(), tmp_path,
                              kill_at)
    assert operations == 4              # the chunk's rename, then the three journal rows


def test_a_retried_run_killed_anywhere_keeps_its_newest_row(tmp_path, kill_at):
    """Run a timed out (its row in the first chunk, beside b's) and ran again: its new row
    is in the journal. The compaction writes it into a chunk, rewrites the first chunk
    without the old row, and removes the journal row."""
    def prepare(root):
        folder = new_folder(root)
        folder.write_chunk([row("a", math.nan, "timeout"), row("b", 2.0)],
                           row_schema(row("a", 0.0)))
        folder.journal(row("a", 1.0))
        return folder

    operations = crash_points(prepare, lambda f: f.compact(stored={"a"}),
                              {"a": 1.0, "b": 2.0}, {"a"}, tmp_path, kill_at)
    assert operations == 3              # the new chunk, the old one rewritten, the journal row


def test_load_reads_the_journal_and_pandas_only_the_chunks(tmp_path):
    folder = new_folder(tmp_path / "d")
    folder.write_chunk([row("a", 1.0)], row_schema(row("a", 0.0)))
    folder.journal(row("b", 2.0))
    folder.journal(row("c", math.inf))
    assert values(folder.root) == {"a": 1.0, "b": 2.0, "c": math.inf}
    assert list(load(folder.root)["run_id"]) == ["a", "b", "c"]      # as written
    assert raw_ids(folder) == ["a"]
    # a float goes through the journal bit for bit
    x = 0.1 + 0.2
    folder.journal(row("e", x))
    assert values(folder.root)["e"] == x and x != 0.3


def test_failed_rows_wait_in_the_journal_for_the_columns(tmp_path):
    """Before the first successful row the feature columns are unknown: failed rows are
    stored (in the journal) and counted, moved into a chunk once a row succeeded."""
    folder = DatasetFolder(tmp_path / "d")
    folder.create("[base]\n")
    writer = _Writer(folder, chunk_rows=1, flush_s=1e9, retried=set())
    failed = {"run_id": "f", "status": "timeout", "value": None}
    writer.add(failed)
    assert folder.chunk_paths() == [] and len(folder.journal_paths()) == 1
    assert load(folder.root)["status"].tolist() == ["timeout"]
    writer.add(row("g", 5.0))
    assert folder.journal_paths() == []
    rows = pd.read_parquet(folder.chunks_dir)
    assert rows["run_id"].tolist() == ["f", "g"] and rows["value"].dtype == float


def test_the_writer_moves_the_journal_every_chunk_rows_rows(tmp_path):
    folder = new_folder(tmp_path / "d")
    writer = _Writer(folder, chunk_rows=3, flush_s=1e9, retried=set())
    for i in range(7):
        writer.add(row(f"r{i}", float(i)))
        # each row stored the moment add() returns
        assert set(values(folder.root)) == {f"r{j}" for j in range(i + 1)}
    assert [len(pd.read_parquet(p)) for p in folder.chunk_paths()] == [3, 3]
    assert len(folder.journal_paths()) == 1
    writer.compact(final=True)
    assert raw_ids(folder) == [f"r{i}" for i in range(7)]


def test_the_progress_prints_a_line_per_run_in_a_log():
    stream = io.StringIO()
    clock = iter([0.0, 10.0, 20.0, 30.0]).__next__
    bar = _Progress(3, 5, stream=stream, clock=clock)
    for ok in (True, False, True):
        bar.update(ok)
    assert stream.getvalue().splitlines() == [
        "5 runs already stored, 3 to run",
        "1/3 done, 0 failed, 2 remaining, ETA 0:20",
        "2/3 done, 1 failed, 1 remaining, ETA 0:10",
        "3/3 done, 1 failed, 0 remaining, ETA 0:00"]


@pytest.mark.parametrize("moment", ["while a journal row is read", "after the first listing"])
def test_load_beside_a_compaction_sees_every_row(tmp_path, monkeypatch, moment):
    """A reader beside a running job: the job moves the journal into a chunk while load
    reads a journal row, or between load's listing of one kind of file and of the other
    (whichever it lists first); load still returns every run once."""
    import rubdiag.dataset._store as store

    folder = new_folder(tmp_path / "d")
    folder.write_chunk([row("a", 1.0)], row_schema(row("a", 0.0)))
    for run_id, value in (("b", 2.0), ("c", 3.0)):
        folder.journal(row(run_id, value))
    job = DatasetFolder(folder.root)
    moved = []

    def compact_once():
        if not moved:                         # once, and not from inside the compaction
            moved.append(None)
            moved[0] = job.compact()

    if moment == "while a journal row is read":
        real = store.read_journal_row

        def read_journal_row(path):
            compact_once()
            return real(path)

        monkeypatch.setattr(store, "read_journal_row", read_journal_row)
    else:
        def after(real):
            def listing(self):
                found = real(self)
                compact_once()
                return found
            return listing

        for name in ("chunk_paths", "journal_paths"):
            monkeypatch.setattr(DatasetFolder, name, after(getattr(DatasetFolder, name)))
    assert values(folder.root) == {"a": 1.0, "b": 2.0, "c": 3.0}
    assert moved and moved[0] is not None and folder.journal_paths() == []
