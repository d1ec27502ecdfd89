"""The per-step status-segment log against the episode log and the sampled status."""

import numpy as np

from rubdiag._kernels.records import OPEN


def _segments_of(seg, k):
    mine = seg.element == k
    return seg.status[mine], seg.t_start[mine], seg.t_end[mine]


def test_segments_tile_every_episode_and_count_its_entries(penalty_run):
    _, res = penalty_run
    ep, seg = res.episodes, res.status_segments
    assert len(ep) >= 5 and len(seg) >= len(ep)
    assert set(np.unique(seg.status)) <= {2, 3}
    for k in np.unique(ep.element):
        status, t0, t1 = _segments_of(seg, k)
        order = np.argsort(t0, kind="stable")
        status, t0, t1 = status[order], t0[order], t1[order]
        mine = np.flatnonzero(ep.element == k)
        for i in mine:
            inside = (t0 >= ep.t_start[i]) & (t1 <= ep.t_end[i])
            s, a, b = status[inside], t0[inside], t1[inside]
            assert a[0] == ep.t_start[i] and b[-1] == ep.t_end[i]
            np.testing.assert_array_equal(a[1:], b[:-1])           # no gap, no overlap
            assert np.all(s[1:] != s[:-1])                          # maximal runs
            assert (s == 2).sum() == ep.n_slide_entries[i]
            assert (s == 3).sum() == ep.n_stick_entries[i]
        # every segment belongs to one episode
        assert sum(((t0 >= ep.t_start[i]) & (t1 <= ep.t_end[i])).sum() for i in mine) == t0.size


def test_sampled_status_is_the_segment_covering_each_sample(penalty_run):
    """Samples are step ends and a step counts with its end-of-step status, so the status
    sampled at t_k is that of the segment covering the instant just before t_k."""
    _, res = penalty_run
    seg = res.status_segments
    probe = res.t[1:] - 1e-3 * res.output_dt
    for e in range(res.contact_status.shape[1]):
        status, t0, t1 = _segments_of(seg, e + 1)
        expected = np.full(probe.size, OPEN)
        for s, a, b in zip(status, t0, t1, strict=True):
            expected[(probe > a) & (probe < b)] = s
        np.testing.assert_array_equal(res.contact_status[1:, e], expected)


def test_segments_do_not_depend_on_the_output_rate(penalty_run, make_rub_run):
    """Gathered at every step: sampling every 100 steps instead of every step leaves the log
    unchanged, including the segments far shorter than an output interval."""
    _, fine = penalty_run
    _, coarse = make_rub_run(output_dt=1e-3)
    a, b = fine.status_segments, coarse.status_segments
    assert ((b.t_end - b.t_start) < 0.1 * coarse.output_dt).sum() >= 3
    for name in ("element", "status", "t_start", "t_end"):
        np.testing.assert_array_equal(getattr(a, name), getattr(b, name))
