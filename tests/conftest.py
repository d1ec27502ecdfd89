import atexit
import os
import shutil
import tempfile
from pathlib import Path

import pytest

import rubdiag  # first: it pins OpenBLAS's kernels before numpy loads them)

os.environ.setdefault("MPLBACKEND", "Agg")
# the disk cache of rig-only results (rubdiag/_cache.py) of this session, and of the commands
# it runs, lives in a folder of its own: never the user's cache
_CACHE = tempfile.mkdtemp(prefix="rubdiag-test-cache-")
os.environ["RUBDIAG_CACHE_DIR"] = _CACHE
atexit.register(shutil.rmtree, _CACHE, ignore_errors=True)

ROOT = Path(__file__).resolve().parents[1]
DATA = ROOT / "data"


@pytest.fixture(scope="session")
def paper_rig():
    return rubdiag.paper_rig()


@pytest.fixture(scope="session")
def paper_model(paper_rig):
    from rubdiag.assembly import assemble

    return assemble(paper_rig)
