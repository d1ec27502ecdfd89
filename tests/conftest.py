import os
from pathlib import Path

import pytest

import rubdiag  # first: it pins OpenBLAS's kernels before numpy loads them)

os.environ.setdefault("MPLBACKEND", "Agg")

ROOT = Path(__file__).resolve().parents[1]
DATA = ROOT / "data"


@pytest.fixture(scope="session")
def paper_rig():
    return rubdiag.paper_rig()


@pytest.fixture(scope="session")
def paper_model(paper_rig):
    from rubdiag.assembly import assemble

    return assemble(paper_rig)
