"""The tables the documentation renders from the files in ``data/`` when it is built
(``docs/generate.py``): a test that checks a stored table checks what the pages show."""

from __future__ import annotations

import importlib
import sys
from pathlib import Path

DOCS = Path(__file__).resolve().parents[1] / "docs"
if str(DOCS) not in sys.path:
    sys.path.insert(0, str(DOCS))
generate = importlib.import_module("generate")
table = generate.table
