"""``data/tolerances.toml``: the bands the documentation states and the tests apply."""

from __future__ import annotations

import tomllib
from pathlib import Path

PATH = Path(__file__).resolve().parents[1] / "data" / "tolerances.toml"
TOLERANCES = tomllib.loads(PATH.read_text(encoding="utf-8"))
