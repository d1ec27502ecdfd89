"""When a contact episode is a rub and when a graze: one rule for the labels and the contact
statistics (``rubdiag.dataset._labels``, ``rubdiag.runs._contact_stats``), kept here so that
both read it without importing each other's layers."""

from __future__ import annotations

#: An episode closed for less than this (s) is a graze: a single 10-µs step is, two are not,
#: nor is a 10-µs step with a 5-µs one. Stated in time, not in steps, so that it means the
#: same whatever the step (the rule was "at least 2 steps" when no step was longer than
#: 10 µs; steps longer than that are never taken while a contact is closed).
MIN_EPISODE_S = 15e-6


def closed_time(episodes):
    """Each episode's closed time (s): its steps' lengths, sliding and sticking (an
    :class:`~rubdiag.simulation._result.EpisodeLog` or anything with those arrays)."""
    return episodes.slide_time + episodes.stick_time
