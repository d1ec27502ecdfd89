#!/usr/bin/env python
"""Regenerate the sample outputs of the documentation's pages, or check that they are still
what the tool prints.

A sample block in a page (:attr:`Sample.page`) is a named pair of HTML comments around
generated text::

    <!-- sample: simulate -->
    ```console
    $ rubdiag simulate --case 2 --gap-mm 1.9 --out c2.npz
    case 2, g0 = 1.9 mm at 5700 rpm: Reached t = 2.3 s in 230000 steps. (2.7 s wall)
    ...
    ```
    <!-- /sample -->

Each sample (:data:`SAMPLES`) runs its commands as ``python -m rubdiag …`` in a fresh temporary
folder (so paths are short and relative) and shows what they print on stdout. Fields that
change from run to run (wall-clock times, :data:`MASKS`) are masked when comparing, so that
only a change in what the tool computes or says counts as drift.

Usage::

    python scripts/doc_samples.py                 # rewrite every block of the pages
    python scripts/doc_samples.py --check         # exit 1 with a diff if a page drifted
    python scripts/doc_samples.py --skip-slow     # leave out table2 (a ≈ 30-s run)
    python scripts/doc_samples.py --only modal    # some samples only
"""

from __future__ import annotations

import argparse
import difflib
import os
import re
import shlex
import subprocess
import sys
import tempfile
from dataclasses import dataclass
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


@dataclass(frozen=True)
class Command:
    argv: tuple[str, ...]          # after ``rubdiag``
    comment: str = ""              # shown after the command, e.g. the other options


@dataclass(frozen=True)
class Sample:
    page: str                      # the page that shows it, from the repository's root
    commands: tuple[Command, ...]
    fence: str | None = "console"  # None: the output is Markdown, shown as is, no commands
    slow: bool = False             # left out by --skip-slow (and by the default test suite)


SAMPLES = {
    "modal": Sample("docs/explanation/model.md", (Command(("modal",)),)),
    "simulate": Sample("docs/explanation/contact-and-integrator.md", (
        Command(("simulate", "--case", "2", "--gap-mm", "1.9", "--out", "c2.npz"),
                "# --speed-rpm, --duration-s, --discard-s, --dt-s, --output-rate-hz, --mu, "
                "--rig, --json"),
        Command(("features", "c2.npz", "--summary"),
                "# in words; without --summary every feature follows"),
    )),
    "table2": Sample("docs/validation/table2.md", (Command(("table2", "--out", "out")),),
                     fence=None, slow=True),
}

#: (pattern, replacement) applied to both sides before comparing: what varies between runs.
MASKS = (
    (re.compile(r"\(\d+(?:\.\d+)? s wall\)"), "(… s wall)"),
)

_BLOCK = re.compile(r"(<!-- sample: (?P<name>[\w-]+) -->\n)(?P<body>.*?)(<!-- /sample -->)",
                    re.DOTALL)
_COMMENT_COLUMN = 60


def blocks(text: str) -> dict[str, str]:
    """The sample blocks of a page's text: name -> the text between the markers."""
    found = {}
    for m in _BLOCK.finditer(text):
        if m["name"] in found:
            raise ValueError(f"sample {m['name']!r} appears twice in the page")
        found[m["name"]] = m["body"]
    return found


def run(argv, cwd: Path) -> str:
    """stdout of ``rubdiag argv`` run in ``cwd``; a failing command is an error."""
    env = dict(os.environ, MPLBACKEND="Agg", COLUMNS="100")
    proc = subprocess.run([sys.executable, "-m", "rubdiag", *argv], cwd=cwd, env=env,
                          capture_output=True, text=True)
    if proc.returncode != 0:
        raise RuntimeError(f"`rubdiag {shlex.join(argv)}` failed ({proc.returncode}): "
                           f"{proc.stderr.strip()}")
    return proc.stdout


def render(sample: Sample) -> str:
    """The block text of a sample: its commands run now, in a fresh temporary folder."""
    lines = []
    with tempfile.TemporaryDirectory(prefix="rubdiag-sample-") as tmp:
        for command in sample.commands:
            if sample.fence is not None:
                shown = "$ rubdiag " + shlex.join(command.argv)
                if command.comment:
                    shown = f"{shown.ljust(_COMMENT_COLUMN - 1)} {command.comment}"
                lines.append(shown)
            lines += [ln.rstrip() for ln in run(command.argv, Path(tmp)).rstrip().splitlines()]
    body = "\n".join(lines) + "\n"
    return body if sample.fence is None else f"```{sample.fence}\n{body}```\n"


def mask(text: str) -> str:
    for pattern, replacement in MASKS:
        text = pattern.sub(replacement, text)
    return text


def compare(text: str, generated: dict[str, str], where: str = "the page") -> list[str]:
    """Differences between a page's blocks (its ``text``) and freshly ``generated`` ones
    (masked), one unified diff per drifted sample; also a sample with no block in it."""
    present = blocks(text)
    problems = []
    for name, new in generated.items():
        if name not in present:
            problems.append(f"{where} has no block <!-- sample: {name} -->")
            continue
        old = mask(present[name])
        if old != mask(new):
            diff = difflib.unified_diff(old.splitlines(), mask(new).splitlines(),
                                        f"{where} ({name})", f"generated ({name})",
                                        lineterm="")
            problems.append("\n".join(diff))
    return problems


def update(text: str, generated: dict[str, str]) -> str:
    """A page's ``text`` with the ``generated`` blocks put in."""
    missing = set(generated) - set(blocks(text))
    if missing:
        raise ValueError(f"the page has no block for: {', '.join(sorted(missing))}")

    def put(m: re.Match) -> str:
        body = generated.get(m["name"], m["body"])
        return m.group(1) + body + m.group(4)

    return _BLOCK.sub(put, text)


def generate(names) -> dict[str, str]:
    return {name: render(SAMPLES[name]) for name in names}


def selected(only=None, skip_slow: bool = False) -> list[str]:
    names = list(only) if only else list(SAMPLES)
    unknown = [n for n in names if n not in SAMPLES]
    if unknown:
        raise SystemExit(f"unknown sample(s): {', '.join(unknown)} (known: "
                         f"{', '.join(SAMPLES)})")
    return [n for n in names if not (skip_slow and SAMPLES[n].slow)]


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--check", action="store_true",
                        help="compare instead of writing; exit 1 if a page drifted")
    parser.add_argument("--only", nargs="+", metavar="NAME", help="these samples only")
    parser.add_argument("--skip-slow", action="store_true", help="leave out slow samples")
    args = parser.parse_args(argv)
    names = selected(args.only, args.skip_slow)
    generated = generate(names)
    problems = []
    for page in dict.fromkeys(SAMPLES[n].page for n in names):
        path = ROOT / page
        text = path.read_text(encoding="utf-8")
        mine = {n: generated[n] for n in names if SAMPLES[n].page == page}
        if args.check:
            problems += compare(text, mine, page)
        else:
            path.write_text(update(text, mine), encoding="utf-8")
            print(f"wrote {', '.join(mine)} to {page}", file=sys.stderr)
    if args.check:
        for problem in problems:
            print(problem)
        print(f"{len(names) - len(problems)} of {len(names)} sample(s) current "
              f"({', '.join(names)})", file=sys.stderr)
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
