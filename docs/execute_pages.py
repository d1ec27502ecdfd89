"""Execute the documentation's notebooks and code-cell pages, several at a time, into the
cache that the Sphinx build reads (``make docs`` runs this first).

myst-nb executes the pages one after another while Sphinx reads them; with the cache full
it only reads their stored outputs. This fills the cache the way myst-nb would (same
notebook, same working folder, same environment), :data:`WORKERS` pages at once, so a fresh
build executes in parallel and the Sphinx build that follows finds every page cached. A
page already in the cache is not executed again; a page that fails is reported with its
traceback and the command exits with status 1.

Usage::

    python docs/execute_pages.py [--workers N]
"""

from __future__ import annotations

import argparse
import os
import sys
import time
from concurrent.futures import ProcessPoolExecutor, as_completed
from pathlib import Path

DOCS = Path(__file__).resolve().parent
ROOT = DOCS.parent
CACHE = DOCS / "_build" / "jupyter_cache"
#: where Sphinx reads the tutorials (``conf.py`` copies ``notebooks/`` there)
TUTORIALS = DOCS / "_generated" / "tutorials"
#: what every executed page sees: the tutorials' small inputs, no display
ENVIRONMENT = {"RUBDIAG_QUICK": "1", "MPLBACKEND": "Agg"}
#: seconds a cell may run
TIMEOUT_S = 900
#: pages executed at once: the machine's cores
WORKERS = os.cpu_count() or 1


def pages() -> list[tuple[Path, Path]]:
    """``(source, working folder)`` of every page that myst-nb executes: the notebooks of
    ``notebooks/`` (read as the tutorials) and the Markdown pages with code cells."""
    from myst_nb.core.read import is_myst_markdown_notebook

    found = [(nb, TUTORIALS) for nb in sorted((ROOT / "notebooks").glob("*.ipynb"))]
    for page in sorted(DOCS.rglob("*.md")):
        if {"_build", "_generated"} & set(page.relative_to(DOCS).parts):
            continue
        if is_myst_markdown_notebook(page.read_text(encoding="utf-8")):
            found.append((page, page.parent))
    return found


def read(source: Path):
    """The notebook myst-nb makes of ``source``."""
    import nbformat
    from myst_nb.core.read import myst_nb_reader_plugin

    if source.suffix == ".ipynb":
        return nbformat.reads(source.read_text(encoding="utf-8"), as_version=4)
    return myst_nb_reader_plugin(str(source))


def execute(source: Path, cwd: Path):
    """``(notebook, seconds, error)``: ``source`` executed in ``cwd``."""
    from jupyter_cache.executors.utils import single_nb_execution

    for name, value in ENVIRONMENT.items():
        os.environ.setdefault(name, value)
    notebook = read(source)
    result = single_nb_execution(notebook, cwd=str(cwd), timeout=TIMEOUT_S,
                                 allow_errors=False, meta_override=True)
    return notebook, result.time, result.exc_string if result.err else None


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--workers", type=int, default=WORKERS,
                        help=f"pages executed at once (default: {WORKERS}, the cores)")
    args = parser.parse_args(argv)
    if args.workers < 1:
        parser.error(f"--workers must be at least 1, got {args.workers}")
    from jupyter_cache import get_cache
    from jupyter_cache.base import CacheBundleIn

    cache = get_cache(str(CACHE))
    todo = []
    for source, cwd in pages():
        try:
            cache.match_cache_notebook(read(source))
        except KeyError:
            todo.append((source, cwd))
    if not todo:
        return 0
    TUTORIALS.mkdir(parents=True, exist_ok=True)
    start, failed = time.perf_counter(), []
    print(f"executing {len(todo)} pages, {args.workers} at a time", flush=True)
    with ProcessPoolExecutor(max_workers=args.workers) as pool:
        jobs = {pool.submit(execute, source, cwd): source for source, cwd in todo}
        for done in as_completed(jobs):
            source = jobs[done].relative_to(ROOT)
            notebook, seconds, error = done.result()
            if error:
                failed.append(source)
                print(f"{source}: failed\n{error}", file=sys.stderr, flush=True)
                continue
            cache.cache_notebook_bundle(
                CacheBundleIn(notebook, str(jobs[done]), data={"execution_seconds": seconds}),
                check_validity=False, overwrite=True)
            print(f"{source}: {seconds:.0f} s", flush=True)
    print(f"{len(todo) - len(failed)} of {len(todo)} pages executed in "
          f"{time.perf_counter() - start:.0f} s", flush=True)
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
