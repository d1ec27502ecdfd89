"""The ``rubdiag`` command line: a thin layer over the Python API.

Each command lives in its own module and exposes ``register(subparsers)``, which adds its
parser and sets ``func`` to a function ``(args) -> int``. Expected failures (bad input, a
missing file) print one line on stderr and exit with status 2, never a traceback (``--debug``:
the full traceback, still status 2). A run starts here: OpenBLAS's kernels are pinned before
numpy loads (:func:`rubdiag.pin_blas_kernels`). Figures are drawn on matplotlib's Agg canvas
and written to files (``rubdiag/_figures.py``): no backend is chosen or needed, no window
opens.
"""

from __future__ import annotations

import argparse
import importlib
import os
import re
import sys
import traceback
import warnings

from rubdiag._blas import no_threads_in_this_process, pin_blas_kernels
from rubdiag._version import __version__

# Modules that register commands, in the order they appear in --help.
_COMMAND_MODULES = ("rubdiag.cli.paper", "rubdiag.cli.linear", "rubdiag.cli.simulate",
                    "rubdiag.cli.runup", "rubdiag.cli.faults", "rubdiag.cli.signal",
                    "rubdiag.cli.dataset",
                    "rubdiag.cli.learn", "rubdiag.cli.cache")


# argparse takes "-1e-5" or "-inf" for an option (its own pattern knows only "-1" and
# "-1.5") and answers "expected one argument": every spelling of a negative float is a value.
_NEGATIVE_NUMBER = re.compile(r"^-(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?$|^-(inf|infinity|nan)$",
                              re.IGNORECASE)


class _Parser(argparse.ArgumentParser):
    """ArgumentParser whose usage errors are one line and exit status 2, and which reads
    negative numbers in any float spelling as values (then refused by range checks)."""

    def __init__(self, *args, **kwargs):
        super().__init__(*args, **kwargs)
        self._negative_number_matcher = _NEGATIVE_NUMBER

    def error(self, message: str):
        self.exit(2, f"{self.prog}: error: {message}\n")


def build_parser() -> argparse.ArgumentParser:
    parser = _Parser(
        prog="rubdiag",
        description="Blade-rotor-casing rub-impact: modal analysis, contact simulation, rub "
        "signatures and the study's Table 2.",
    )
    parser.add_argument("--version", action="version", version=f"rubdiag {__version__}")
    parser.add_argument("--debug", action="store_true",
                        help="on an error, print the full traceback instead of one line (and "
                             "warnings as Python shows them)")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=_Parser)
    sub.required = True
    for name in _COMMAND_MODULES:
        importlib.import_module(name).register(sub)
    return parser


#: commands that make one simulation: OpenBLAS's idle threads would only cost it time. Told
#: before parsing, since parsing reads option defaults from the library (which loads numpy).
_ONE_RUN_COMMANDS = ("simulate",)


def main(argv: list[str] | None = None) -> int:
    pin_blas_kernels()    # first: before anything loads numpy (rubdiag/_blas.py)
    words = [a for a in (sys.argv[1:] if argv is None else argv) if not a.startswith("-")]
    if words and words[0] in _ONE_RUN_COMMANDS:
        no_threads_in_this_process()
    args = build_parser().parse_args(argv)
    with warnings.catch_warnings():   # restores the caller's warning display afterwards
        if not args.debug:
            warnings.showwarning = _one_line_warning(args.command)
        return _run(args)


def _run(args) -> int:
    try:
        return int(args.func(args) or 0)
    except BrokenPipeError:   # e.g. `rubdiag features x.csv | head`: the reader left
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return 0
    except (ValueError, OSError) as exc:   # OSError: files (missing, a folder, no access …)
        if args.debug:
            traceback.print_exc()
        else:
            print(f"rubdiag {args.command}: error: {_one_line(exc)}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print(f"rubdiag {args.command}: interrupted", file=sys.stderr)
        return 130


def _one_line_warning(command: str):
    """Warnings as one line on stderr, as errors are (not Python's file:line + source)."""
    def show(message, category, filename, lineno, file=None, line=None):
        text = str(message).splitlines()[0] if str(message) else category.__name__
        print(f"rubdiag {command}: warning: {text}", file=sys.stderr if file is None else file)
    return show


def _one_line(exc: Exception) -> str:
    """The first line of an error message; ``[Errno 2] No such file or directory: 'x'``
    becomes ``x: No such file or directory``."""
    if isinstance(exc, OSError) and exc.strerror and exc.filename is not None:
        return f"{exc.filename}: {exc.strerror}"
    text = str(exc)
    return text.splitlines()[0] if text else type(exc).__name__


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
