"""The Numba cache of a kernel package is dropped when any of its sources changes."""

import subprocess
import sys

from rubdiag._numba import drop_stale_cache


def test_cache_dropped_only_when_a_source_changes(tmp_path):
    (tmp_path / "law.py").write_text("x = 1\n")
    (tmp_path / "loop.py").write_text("y = 2\n")
    cache = tmp_path / "__pycache__"
    cache.mkdir()
    entries = [cache / "loop.kernel-1.py311.nbi", cache / "loop.kernel-1.py311.1.nbc"]
    for entry in entries:
        entry.write_text("stale")
    assert drop_stale_cache(tmp_path)                 # no fingerprint yet: dropped
    assert not any(e.exists() for e in entries)
    for entry in entries:
        entry.write_text("fresh build")
    assert not drop_stale_cache(tmp_path)             # nothing changed: kept
    assert all(e.exists() for e in entries)
    (tmp_path / "law.py").write_text("x = 3\n")       # a *called* file changed
    assert drop_stale_cache(tmp_path)
    assert not any(e.exists() for e in entries)


def test_importing_the_kernels_touches_no_cache():
    # the check is explicit (once per process, before the first kernel call), never a side
    # effect of an import that every parallel worker performs
    code = (
        "import rubdiag._numba as nb\n"
        "calls = []\n"
        "nb.drop_stale_cache = lambda package: calls.append(package)\n"
        "import rubdiag._kernels, rubdiag._kernels.newmark, rubdiag.simulation\n"
        "assert calls == [], calls\n"
        "rubdiag._kernels.ensure_fresh_cache(); rubdiag._kernels.ensure_fresh_cache()\n"
        "assert len(calls) == 1, calls\n"
    )
    subprocess.run([sys.executable, "-c", code], check=True)
