"""The project stands on its own: nothing it ships points a user at a file they do not have.

rubdiag's design notes and the study's reference files live outside the repository, with
the people who wrote them; what the project takes from them is written, in its own words,
into its README, docstrings and notebooks. A citation of those files is a dead end for a
user, so it fails here.
"""

import re
import subprocess
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
#: How a citation of the outside notes reads: the file name, its item numbers, the folder.
OUTSIDE = re.compile(r"DESIGN\.md|DESIGN item|DESIGN's|\.\./shared")


def shipped_files() -> list[Path]:
    listed = subprocess.run(["git", "ls-files"], cwd=ROOT, capture_output=True, text=True,
                            check=True).stdout.split()
    return [ROOT / name for name in listed
            if name != "tests/test_self_contained.py" and (ROOT / name).is_file()]


def test_no_file_cites_the_outside_design_notes():
    files = shipped_files()
    assert len(files) > 100                     # the listing found the project
    cites = [f"{path.relative_to(ROOT)}:{n}"
             for path in files if path.suffix in {".py", ".md", ".ipynb", ".toml", ".txt"}
             for n, line in enumerate(path.read_text(errors="replace").splitlines(), 1)
             if OUTSIDE.search(line)]
    assert not cites, "cites files a user does not have: " + ", ".join(cites)


# --- the README and the documentation speak to users -----------------------------------------
#: The README is a front page; the manual is the documentation.
README_MAX_LINES = 250
#: How a work item, a date, a machine load or a working session reads in prose.
WORK_ITEM = re.compile(r"\bissues?\b|\bwork items?\b", re.IGNORECASE)
NOTEBOOK_WORDS = re.compile(r"\b20\d\d-[01]\d-[0-3]\d\b|\bload (?:average|≈|~|<|\d)|"
                            r"\bthis session\b", re.IGNORECASE)
#: Test and benchmark functions, by their names.
NAMED = re.compile(r"^\s*def ((?:test|bench)\w*)", re.MULTILINE)


def prose_files() -> list[Path]:
    """The shipped prose: the README, the documentation's pages, the data's README and its
    TOML files (their comments), and the benchmarks' README."""
    return [p for p in shipped_files() if p.suffix in {".md", ".toml"} and (
        p in (ROOT / "README.md", ROOT / "benchmarks" / "README.md")
        or p.is_relative_to(ROOT / "docs") or p.is_relative_to(ROOT / "data"))]


def test_the_readme_is_a_front_page():
    lines = (ROOT / "README.md").read_text(encoding="utf-8").splitlines()
    assert len(lines) <= README_MAX_LINES, f"README.md has {len(lines)} lines"
    text = "\n".join(lines)
    for command in ("make run", "make test", ".venv/bin/rubdiag", "source .venv/bin/activate"):
        assert command in text, command


def test_no_shipped_prose_names_a_work_item_a_date_or_a_load():
    """No shipped prose names a work item; nor a date or a machine load, except where the
    benchmarks' README says where and under what load a figure was measured."""
    files = prose_files()
    assert {ROOT / "README.md", ROOT / "data" / "README.md", ROOT / "benchmarks" / "README.md",
            ROOT / "docs" / "index.md"} <= set(files)
    found = [f"{path.relative_to(ROOT)}:{n}: {line.strip()[:80]}"
             for path in files
             for n, line in enumerate(path.read_text(encoding="utf-8").splitlines(), 1)
             if (path.suffix == ".md" or line.lstrip().startswith("#"))
             and (WORK_ITEM.search(line) or (NOTEBOOK_WORDS.search(line)
                  and path != ROOT / "benchmarks" / "README.md"))]
    assert not found, "shipped prose names a work item, a date or a load:\n" + "\n".join(found)


def test_no_test_or_benchmark_is_named_after_a_work_item():
    names = [f"{path.relative_to(ROOT)}" + (f"::{name}" if name else "")
             for path in shipped_files() if path.suffix == ".py"
             and path.parts[len(ROOT.parts)] in ("tests", "benchmarks")
             for name in ["", *NAMED.findall(path.read_text(encoding="utf-8"))]]
    assert len(names) > 100
    assert not [n for n in names if WORK_ITEM.search(n.replace("_", " "))]
