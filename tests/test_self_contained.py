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
