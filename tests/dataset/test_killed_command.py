"""Nothing finished is lost: ``rubdiag dataset`` on two worker processes,
SIGKILLed — with its workers — as soon as its progress line reports k ≥ 8 of 16 runs done,
keeps at least those k rows (as they were: the resume does not run them again); the same
command then reports at least k runs already stored and ends with every run of the design
exactly once, in the chunks as well as for ``load``.

16 runs of 0.3 s (case 2 at and just above its critical speed, gaps from serious rub to
none, two start histories): about 0.6 s each on an idle core."""

import os
import re
import signal
import subprocess
import sys
import threading

import pandas as pd

from rubdiag.dataset import Design, load

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
speed_ratio = [1.0, 1.05]
gap_mm = [1.9, 2.6, 3.2, 4.0]
"""
KILL_AT = 8
DONE = re.compile(r"^(\d+)/16 done, ")


def command(design, out):
    return [sys.executable, "-m", "rubdiag", "dataset", str(design), "--out", str(out),
            "--jobs", "2"]


def test_a_killed_job_keeps_every_run_it_counted(tmp_path):
    design = tmp_path / "design.toml"
    design.write_text(TOML)
    run_ids = {item.run_id for item in Design.from_toml(TOML).runs()}
    assert len(run_ids) == 16
    out = tmp_path / "dataset"

    # the job and its workers in a process group of their own, killed together
    proc = subprocess.Popen(command(design, out), stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True, start_new_session=True)
    watchdog = threading.Timer(600, os.killpg, (proc.pid, signal.SIGKILL))
    watchdog.start()
    counted, lines = 0, []
    try:
        for line in proc.stderr:          # a line per finished run (stderr is not a terminal)
            lines.append(line)
            if match := DONE.match(line):
                counted = int(match.group(1))
                if counted >= KILL_AT:
                    os.killpg(proc.pid, signal.SIGKILL)
                    break
        proc.wait(timeout=60)
    finally:
        watchdog.cancel()
        proc.stdout.close()
        proc.stderr.close()
    assert proc.returncode == -signal.SIGKILL, "".join(lines)
    assert counted >= KILL_AT

    kept = load(out)                      # what the killed job left: every run it counted
    assert len(kept) >= counted and not kept["run_id"].duplicated().any()
    assert set(kept["run_id"]) <= run_ids and (kept["status"] == "ok").all()

    resumed = subprocess.run(command(design, out), capture_output=True, text=True,
                             timeout=600)
    assert resumed.returncode == 0, resumed.stderr
    stored = int(re.search(r": 16 runs, (\d+) already stored, ", resumed.stdout).group(1))
    assert stored == len(kept) >= counted
    assert f"{16 - stored} ok and 0 failed now" in resumed.stdout
    assert resumed.stderr.splitlines()[0] == f"{stored} runs already stored, {16 - stored} to run"

    rows = load(out)
    assert sorted(rows["run_id"]) == sorted(run_ids)
    assert sorted(pd.read_parquet(out / "features")["run_id"]) == sorted(run_ids)
    assert not (out / "journal").exists()
    assert [p for p in out.rglob(".*")] == []
    # the kept rows were not made again: the same values, wall time included
    again = rows.set_index("run_id").loc[kept["run_id"]].reset_index()
    pd.testing.assert_frame_equal(again, kept, check_exact=True)


def _alive(pid: int) -> bool:
    """True while ``pid`` runs (a zombie, or a process that is gone, is not running)."""
    try:
        with open(f"/proc/{pid}/stat") as fh:
            return fh.read().rsplit(")", 1)[1].split()[0] != "Z"
    except FileNotFoundError:
        return False


def test_workers_end_when_the_job_alone_is_killed(tmp_path):
    """``kill -9`` of the job's own process (not its group, as a user does): its workers
    end within a few seconds (they waited for their parent for ever, blocked on its
    queues, and kept their memory)."""
    import time

    import pytest

    if not os.path.isdir("/proc"):
        pytest.skip("reads the process table in /proc")
    design = tmp_path / "design.toml"
    design.write_text(TOML)
    proc = subprocess.Popen(command(design, tmp_path / "dataset"), stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True, start_new_session=True)
    watchdog = threading.Timer(600, os.killpg, (proc.pid, signal.SIGKILL))
    watchdog.start()
    workers: list[int] = []
    try:
        for line in proc.stderr:
            if DONE.match(line):              # the workers are running
                break
        with open(f"/proc/{proc.pid}/task/{proc.pid}/children") as fh:
            workers = [int(pid) for pid in fh.read().split()]
        assert len(workers) == 2
        proc.kill()
        proc.wait(timeout=60)
        deadline = time.monotonic() + 20
        while any(map(_alive, workers)) and time.monotonic() < deadline:
            time.sleep(0.2)
        assert not any(map(_alive, workers))
    finally:
        watchdog.cancel()
        if any(map(_alive, workers)):
            os.killpg(proc.pid, signal.SIGKILL)
        proc.stdout.close()
        proc.stderr.close()
