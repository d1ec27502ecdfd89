"""The ``rubdiag`` command line: a thin layer over the Python API.

Each command lives in its own module and exposes ``register(subparsers)``, which adds its
parser and sets ``func`` to a function ``(args) -> int``. Expected failures (bad input, a
missing file) print one line on stderr and exit with status 2, never a traceback.
"""

from __future__ import annotations

import argparse
import importlib
import sys

from rubdiag._version import __version__

# Modules that register commands, in the order they appear in --help.
_COMMAND_MODULES = ("rubdiag.cli.paper", "rubdiag.cli.linear", "rubdiag.cli.simulate",
                    "rubdiag.cli.signal")


class _Parser(argparse.ArgumentParser):
    """ArgumentParser whose usage errors are one line and exit status 2."""

    def error(self, message: str):
        self.exit(2, f"{self.prog}: error: {message}\n")


def build_parser() -> argparse.ArgumentParser:
    parser = _Parser(
        prog="rubdiag",
        description="Blade-rotor-casing rub-impact: modal analysis, contact simulation, rub "
        "signatures and the study's Table 2.",
    )
    parser.add_argument("--version", action="version", version=f"rubdiag {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=_Parser)
    sub.required = True
    for name in _COMMAND_MODULES:
        importlib.import_module(name).register(sub)
    return parser


def main(argv: list[str] | None = None) -> int:
    args = build_parser().parse_args(argv)
    try:
        return int(args.func(args) or 0)
    except (ValueError, FileNotFoundError, IsADirectoryError, PermissionError) as exc:
        message = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
        print(f"rubdiag {args.command}: error: {message}", file=sys.stderr)
        return 2
    except BrokenPipeError:   # e.g. `rubdiag features x.csv | head`: the reader left
        import os

        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return 0
    except KeyboardInterrupt:
        print(f"rubdiag {args.command}: interrupted", file=sys.stderr)
        return 130


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
