"""A stream that says it is a terminal, for the progress bars (rubdiag._progress)."""

import io
import re
import sys


class Terminal(io.StringIO):
    """A stream whose ``isatty()`` is True: a progress bar draws on it."""

    def isatty(self):
        return True


def counts(text: str) -> list[str]:
    """Every ``n/total`` a bar drew on a stream, in order (``"7/7"``, ``"2.50/2.50"``)."""
    return re.findall(r"(\d+(?:\.\d+)?/\d+(?:\.\d+)?)", text)


def as_terminal(monkeypatch) -> Terminal:
    """Replace stderr by a terminal and return it. Call it inside the test, not in a
    fixture: pytest's capture puts its own stderr back between a fixture's setup and the
    test."""
    stream = Terminal()
    monkeypatch.setattr(sys, "stderr", stream)
    return stream
