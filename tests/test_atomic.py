"""rubdiag._atomic: a file is whole or absent, whatever fails on the way."""

import os

import pytest

from rubdiag import _atomic


def test_a_write_replaces_the_file_and_leaves_no_temporary(tmp_path):
    target = tmp_path / "a.json"
    target.write_text("old")
    assert _atomic.write_text(target, "new ünïcode") == target
    assert target.read_bytes() == "new ünïcode".encode()
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a.json"]


def test_a_failed_rename_keeps_the_old_file_and_removes_the_temporary(tmp_path, monkeypatch):
    target = tmp_path / "a.bin"
    target.write_bytes(b"old")

    def fail(src, dst):
        assert os.path.basename(src).startswith(".a.bin.")    # hidden, beside the target
        raise OSError("disk full")

    monkeypatch.setattr(_atomic.os, "replace", fail)
    with pytest.raises(OSError, match="disk full"):
        _atomic.write_bytes(target, b"new")
    assert target.read_bytes() == b"old"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a.bin"]
