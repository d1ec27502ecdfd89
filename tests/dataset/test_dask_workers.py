"""rubdiag.dataset._workers: a worker computes a row with what this process computes it with.

Local workers run every BLAS and OpenMP library on one thread, also those they load later.
Dask workers whose BLAS kernels differ from this process's (as workers started by
``dask worker`` on an AVX-512 machine pick SkylakeX, where rubdiag pins Haswell) are restarted
with this process's kernels before a run is sent, so that their rows are this process's bits
(without that, every row of the design below differs); a worker that cannot be aligned is a
ValueError naming it and what differs, before any run is sent.
"""

import os
from concurrent.futures import ProcessPoolExecutor

import numpy as np
import pytest

from rubdiag._blas import kernels_in_use
from rubdiag.dataset import Design, generate, load
from rubdiag.dataset import _workers as w

TOML = """
[base]
rig = "paper"
duration_s = 0.3
discard_s = 0.1
reduced = true

[sampling]
method = "grid"
seed = 0
replicates = 2

[factors]
case = [2]
speed_ratio = [1.0]
gap_mm = [1.9]
"""

OTHER_KERNELS = "Sandybridge"       # AVX kernels: valid on every x86-64 CPU with AVX


def _thread_settings():
    from threadpoolctl import threadpool_info

    return ({name: os.environ.get(name) for name in w.THREAD_ENVIRON},
            sorted((i["internal_api"], i["num_threads"]) for i in threadpool_info()))


def test_a_local_worker_holds_every_library_to_one_thread_also_those_it_loads_later():
    with ProcessPoolExecutor(1, initializer=w.start_local_worker) as pool:
        environ, pools = pool.submit(_thread_settings).result()
    assert environ == {name: "1" for name in w.THREAD_ENVIRON}
    # numpy's and scipy.linalg's BLAS (loaded by the worker's start if not before)
    assert sum(api == "openblas" for api, _ in pools) >= 1
    assert all(threads == 1 for _, threads in pools), pools


def test_differences_name_each_differing_item_with_both_values():
    here = {"rubdiag": "abc", "numpy": "2.4.6", "blas": [["openblas", "0.3.31", "Haswell"]]}
    there = {"rubdiag": "abc", "numpy": "2.3.0", "blas": [["openblas", "0.3.31", "SkylakeX"]]}
    found = w.differences(here, there)
    assert len(found) == 2
    assert found[0].startswith("blas") and "SkylakeX" in found[0] and "Haswell" in found[0]
    assert found[1] == "numpy '2.3.0' (this process: '2.4.6')"
    assert w.differences(here, dict(here)) == []


class _FakeClient:
    """client.run(signature) answers ``answers``; registering a plugin changes nothing
    (workers without a nanny), or applies ``after`` (workers that restart)."""

    def __init__(self, answers, after=None):
        self.answers, self.after, self.plugins = answers, after, []

    def run(self, function):
        assert function is w.signature
        return dict(self.answers)

    def scheduler_info(self):
        return {"workers": dict.fromkeys(self.answers)}

    def register_plugin(self, plugin):
        self.plugins.append(plugin)
        if self.after is not None:
            self.answers = self.after

    def wait_for_workers(self, n, timeout):
        assert n == len(self.answers)


def test_workers_that_differ_in_more_than_their_kernels_are_refused_before_a_restart():
    pytest.importorskip("distributed")
    here = w.signature()
    client = _FakeClient({"tcp://w1": here, "tcp://w2": {**here, "numpy": "1.0"}})
    with pytest.raises(ValueError, match=r"worker tcp://w2 .*numpy '1\.0' \(this process"):
        w.align_dask_workers(client)
    assert client.plugins == []
    w.align_dask_workers(_FakeClient({"tcp://w1": here}))      # nothing differs: no error


def test_workers_whose_kernels_stay_different_are_refused_naming_the_variable():
    pytest.importorskip("distributed")
    here = w.signature()
    if w._kernels(here["blas"]) is None:
        pytest.skip("no OpenBLAS kernels to pin here")
    other = {**here, "blas": [[api, version, OTHER_KERNELS] for api, version, _ in here["blas"]]}
    client = _FakeClient({"tcp://w1": other})
    with pytest.raises(ValueError, match="OPENBLAS_CORETYPE=") as info:
        w.align_dask_workers(client)
    assert len(client.plugins) == 1 and "tcp://w1" in str(info.value)
    w.align_dask_workers(_FakeClient({"tcp://w1": other}, after={"tcp://w1": here}))


def test_dask_workers_with_other_kernels_give_this_process_rows_bit_for_bit(tmp_path):
    distributed = pytest.importorskip("distributed")
    import dask

    kernels = kernels_in_use()
    if kernels in (None, OTHER_KERNELS):
        pytest.skip(f"this process runs OpenBLAS kernels {kernels}")
    design = Design.from_toml(TOML)
    generate(design, tmp_path / "local", jobs=1, progress=False)
    environ = dict(os.environ)
    # workers started apart from this process: the kernels of their own environment
    spawn = {**dask.config.get("distributed.nanny.pre-spawn-environ"),
             "OPENBLAS_CORETYPE": OTHER_KERNELS}
    os.environ.pop("OPENBLAS_CORETYPE", None)     # the nannies' own environment wins
    try:
        with dask.config.set({"distributed.nanny.pre-spawn-environ": spawn}), \
                distributed.LocalCluster(n_workers=1, threads_per_worker=1, processes=True,
                                         dashboard_address=None) as cluster, \
                distributed.Client(cluster) as client:
            before = set(client.run(kernels_in_use).values())
            generate(design, tmp_path / "dask", client=client, progress=False)
            after = set(client.run(kernels_in_use).values())
    finally:
        os.environ.clear()
        os.environ.update(environ)
    assert before == {OTHER_KERNELS}
    local, dask_rows = (load(tmp_path / name).sort_values("run_id").reset_index(drop=True)
                        for name in ("local", "dask"))
    assert len(local) == 2 and local["rub"].all()
    floats = [c for c in local.columns if local[c].dtype.kind == "f"
              and c not in ("wall_s", "simulate_s")]
    assert len(floats) > 100
    bits = {name: rows[floats].to_numpy().view(np.uint64) for name, rows in
            (("local", local), ("dask", dask_rows))}
    np.testing.assert_array_equal(bits["dask"], bits["local"])
    assert after == {kernels}
