"""The ``--quiet`` option of the commands that show their progress."""

from __future__ import annotations

QUIET_HELP = ("no progress bar (a bar with an ETA is drawn on stderr only when stderr is a "
              "terminal)")


def add_quiet_option(p, *aliases: str, help: str = QUIET_HELP) -> None:
    """Add ``--quiet`` (and ``aliases``, e.g. an older option's name) to a command's parser;
    the command reads ``args.quiet``."""
    p.add_argument("--quiet", *aliases, dest="quiet", action="store_true", help=help)
