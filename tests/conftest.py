import atexit
import os
import shutil
import tempfile
from pathlib import Path

import pytest

import rubdiag

rubdiag.pin_blas_kernels()  # first: before numpy loads OpenBLAS (the references' kernels)

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


@pytest.hookimpl(optionalhook=True)     # a hook of pytest-xdist's
def pytest_xdist_make_scheduler(config, log):
    """``--dist loadfile`` (make test) with the classifier tests' folder as one unit: its
    session fixtures simulate datasets (tests/learn/conftest.py, half a minute each), which
    one worker then makes once instead of each worker making them."""
    if config.getvalue("dist") != "loadfile":
        return None
    from xdist.scheduler import LoadFileScheduling

    class Scheduler(LoadFileScheduling):
        def _split_scope(self, nodeid: str) -> str:
            scope = super()._split_scope(nodeid)
            return "tests/learn" if scope.startswith("tests/learn/") else scope

    return Scheduler(config, log)
