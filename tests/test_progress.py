"""rubdiag._progress: a bar on a terminal that reaches its total, nothing anywhere else."""

import io

import pytest
from fake_terminal import Terminal, counts

from rubdiag import _progress


def last_count(text: str) -> str:
    """The ``n/total`` of the last state a bar drew."""
    return counts(text)[-1]


def test_a_bar_on_a_terminal_reaches_its_total():
    stream = Terminal()
    items = list(_progress.steps(range(7), "work", stream=stream))
    assert items == list(range(7))
    assert last_count(stream.getvalue()) == "7/7"
    assert stream.getvalue().endswith("\n")          # the finished bar stays on screen


@pytest.mark.parametrize("stream, enabled", [(io.StringIO(), True), (Terminal(), False)])
def test_no_bar_off_a_terminal_or_when_quiet(stream, enabled):
    with _progress.bar(3, "work", enabled=enabled, stream=stream) as bar:
        bar.update(3)
    assert list(_progress.steps(range(3), "work", enabled=enabled, stream=stream)) == [0, 1, 2]
    with _progress.simulated(2.0, "run", enabled=enabled, stream=stream) as bar:
        assert _progress.following(bar, 0.0, 2.0) is None    # simulate runs in one piece
    assert stream.getvalue() == ""


def test_a_simulated_time_bar_follows_runs_one_after_the_other():
    """Two runs of 1 s and 1.5 s on one bar: the second starts where the first ended, and
    a run's last report puts the bar at its end whatever its own duration."""
    stream = Terminal()
    with _progress.simulated(2.5, "runs", stream=stream) as bar:
        first = _progress.following(bar, 0.0, 1.0)
        first(0.4, 1.0)
        assert bar.n == pytest.approx(0.4)
        first(1.0, 1.0)
        second = _progress.following(bar, 1.0, 1.5)
        second(0.05, 0.1)                          # the kernel's own clock: half-way
        assert bar.n == pytest.approx(1.75)
        second(0.1, 0.1)
    assert last_count(stream.getvalue()) == "2.50/2.50"
    assert "s simulated" in stream.getvalue()


def test_a_shared_bar_counts_the_callee_s_steps_on_the_caller_s():
    stream = Terminal()
    with _progress.bar(1, "train", unit="fit", stream=stream) as outer:
        with _progress.shared(outer, 4, "evaluate") as inner:
            assert inner is outer and outer.total == 5
            inner.update(4)
        outer.update()
    assert last_count(stream.getvalue()) == "5/5"
    assert "evaluate" not in stream.getvalue()         # one bar, the caller's


@pytest.mark.parametrize("progress, shown", [(True, True), (False, False)])
def test_shared_opens_its_own_bar_when_given_a_flag(progress, shown):
    stream = Terminal()
    with _progress.shared(progress, 2, "evaluate", stream=stream) as bar:
        bar.update(2)
    assert (last_count(stream.getvalue()) == "2/2") if shown else stream.getvalue() == ""


def test_a_line_written_during_a_bar_lands_above_it():
    stream = Terminal()
    with _progress.bar(2, "work", stream=stream) as bar:
        bar.update()
        _progress.write("case 1: done", stream)
        bar.update()
    text = stream.getvalue()
    assert "case 1: done\n" in text and text.rindex("case 1: done") < text.rindex("2/2")


def test_counted_calls_back_after_each_item_whatever_the_body_does():
    calls, seen = [], []
    for item in _progress.counted(range(4), lambda: calls.append(len(seen))):
        if item % 2:
            continue                     # a skipped item is counted too
        seen.append(item)
    # called after the body: the first call sees item 0 in ``seen`` already
    assert calls == [1, 1, 2, 2]


def test_a_part_counts_the_steps_it_skipped_when_it_ends():
    stream = Terminal()
    with _progress.bar(5, "work", stream=stream) as bar:
        with _progress.part(bar, 4) as tick:
            tick()                       # one of its four steps done, three skipped
            assert bar.n == 1
        assert bar.n == 4
        with _progress.part(bar, 1) as tick:
            tick()
        assert bar.n == 5
    assert last_count(stream.getvalue()) == "5/5"


def test_a_label_shows_beside_the_bar_at_once():
    stream = Terminal()
    with _progress.bar(2, "work", stream=stream) as bar:
        _progress.label(bar, "reading the data")
        assert stream.getvalue().rstrip().endswith("reading the data]")
        bar.update(2)
