"""The disk cache's folder, switch and housekeeping (rubdiag/_cache.py), and ``rubdiag cache``."""

from __future__ import annotations

import sys

import numpy as np
import pytest

from rubdiag import _cache
from rubdiag.cli import main


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="the XDG default is Linux's")
def test_the_default_folder_is_the_platforms_cache_folder(tmp_path, monkeypatch):
    monkeypatch.delenv(_cache.ENV, raising=False)
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "xdg"))
    assert _cache.folder() == tmp_path / "xdg" / "rubdiag"
    monkeypatch.delenv("XDG_CACHE_HOME")
    monkeypatch.setenv("HOME", str(tmp_path / "home"))
    assert _cache.folder() == tmp_path / "home" / ".cache" / "rubdiag"


def test_the_variable_moves_the_cache_and_empty_switches_it_off(tmp_path, monkeypatch, capsys):
    monkeypatch.setenv(_cache.ENV, str(tmp_path / "here"))
    written = _cache.store("thing", {"a": 1.5}, {"x": np.arange(3.0)})
    assert written.parent == tmp_path / "here"
    np.testing.assert_array_equal(_cache.load("thing", {"a": 1.5}, ("x",))["x"], [0, 1, 2])
    assert _cache.load("thing", {"a": 1.5 + 2**-40}, ("x",)) is None     # another input
    monkeypatch.setenv(_cache.ENV, "")
    assert _cache.folder() is None
    assert _cache.store("thing", {"a": 1.5}, {"x": np.arange(3.0)}) is None
    assert _cache.load("thing", {"a": 1.5}, ("x",)) is None
    assert main(["cache"]) == 0
    assert capsys.readouterr().out == f"disk cache off ({_cache.ENV} is empty)\n"


def test_cached_computes_once_and_reads_after(tmp_path, monkeypatch):
    monkeypatch.setenv(_cache.ENV, str(tmp_path))
    calls = []

    def compute():
        calls.append(1)
        return {"v": np.array([1.0, 2.0])}

    first, from_disk_1 = _cache.cached("thing", {"n": 2}, ("v",), compute)
    second, from_disk_2 = _cache.cached("thing", {"n": 2}, ("v",), compute)
    assert (from_disk_1, from_disk_2, len(calls)) == (False, True, 1)
    assert second["v"].tobytes() == first["v"].tobytes()


def test_a_kind_outside_file_name_characters_is_refused():
    with pytest.raises(ValueError, match=r"^kind = '\.\./x' is not allowed \(allowed: "):
        _cache.key("../x", {})


def test_rubdiag_cache_shows_and_clears_only_its_own_files(tmp_path, monkeypatch, capsys):
    monkeypatch.setenv(_cache.ENV, str(tmp_path))
    for n in range(2):
        _cache.store("thing", {"n": n}, {"x": np.zeros(1000)})
    (tmp_path / "notes.txt").write_text("a user's file in the same folder")
    assert main(["cache"]) == 0
    lines = capsys.readouterr().out.splitlines()
    assert lines[0].startswith(f"{tmp_path} ")
    assert lines[1] == "2 files, 0.0 MB"             # 2 × 8 kB of arrays and their keys
    assert main(["cache", "--clear"]) == 0
    assert capsys.readouterr().out == f"removed 2 files from {tmp_path}\n"
    assert [p.name for p in tmp_path.iterdir()] == ["notes.txt"]


def test_rubdiag_cache_on_a_file_says_it_is_not_a_folder(tmp_path, monkeypatch, capsys):
    """RUBDIAG_CACHE_DIR naming a file: nothing can be cached there, which ``rubdiag cache``
    says in one line (exit 2) instead of "0 files"; the file is left alone."""
    target = tmp_path / "a-file"
    target.write_text("not a folder")
    monkeypatch.setenv(_cache.ENV, str(target))
    for argv in (["cache"], ["cache", "--clear"]):
        assert main(argv) == 2
        captured = capsys.readouterr()
        assert captured.out == "" and captured.err.count("\n") == 1
        assert f"error: {target}: not a folder, so nothing is cached" in captured.err
    assert target.read_text() == "not a folder"
