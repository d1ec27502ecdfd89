"""What a run computes from its rig alone is cached per process and on disk: a run
with cached rig results gives the bits of a run without them, the cache key follows the rig's
content, a damaged cache file is ignored and rewritten, and a run's BLAS runs on one thread."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from threadpoolctl import threadpool_info, threadpool_limits

import rubdiag
from rubdiag import _cache
from rubdiag.reduce import Reduction, reduced_model
from rubdiag.reduce import _reduced as reduced
from rubdiag.simulation import Run, simulate
from rubdiag.simulation import _rig_cache as rig_cache
from rubdiag.simulation import _simulation as simulation_module

ARRAYS = ("boundary", "T", "mode_frequencies_hz", "M", "K", "C", "G")


def _forget_in_process():
    for cached in (reduced._reduced_model, rig_cache.assembled, rig_cache.damped_model,
                   rig_cache.forward_critical_speeds):
        cached.cache_clear()


@pytest.fixture
def cache_dir(tmp_path, monkeypatch):
    """A disk cache of the test's own, and nothing kept in the process before or after."""
    folder = tmp_path / "cache"
    monkeypatch.setenv(_cache.ENV, str(folder))
    _forget_in_process()
    yield folder
    _forget_in_process()


def _arrays(model) -> dict[str, np.ndarray]:
    basis = model.basis
    return {"boundary": basis.boundary, "T": basis.T,
            "mode_frequencies_hz": basis.mode_frequencies_hz,
            "M": model.M, "K": model.K, "C": model.C, "G": model.G}


def _assert_same_bits(a: dict, b: dict):
    assert set(a) == set(b)
    for name in a:
        assert a[name].dtype == b[name].dtype, name
        assert a[name].shape == b[name].shape, name
        assert a[name].tobytes() == b[name].tobytes(), name


def _uncached(monkeypatch, make):
    """``make()`` with the disk cache off and nothing kept in the process."""
    with monkeypatch.context() as m:
        m.setenv(_cache.ENV, "")
        _forget_in_process()
        value = make()
    _forget_in_process()
    return value


def _short(reduction=None) -> Run:
    return Run.paper_case(2, 1.9, duration_s=0.03, discard_s=0.0, gap_ramp_s=0.0,
                          reduction=reduction)


def _result_arrays(result) -> dict[str, np.ndarray]:
    out = {}
    for f in dataclasses.fields(result.system):
        value = getattr(result.system, f.name)
        if isinstance(value, np.ndarray):
            out[f.name] = value
        elif dataclasses.is_dataclass(value):     # the event logs
            out.update({f"{f.name}.{g.name}": getattr(value, g.name)
                        for g in dataclasses.fields(value)})
    return out


def test_a_reduced_model_read_from_disk_has_the_bits_of_the_reduction(cache_dir, monkeypatch):
    rig = rubdiag.paper_rig()
    built = reduced_model(rig)
    assert not built.from_disk and len(list(cache_dir.glob("reduced-model-*.npz"))) == 1
    _forget_in_process()
    # a hit never reduces: the reduction must not run
    monkeypatch.setattr(reduced, "craig_bampton", _must_not_run)
    loaded = reduced_model(rig)
    assert loaded.from_disk
    _assert_same_bits(_arrays(loaded), _arrays(built))
    assert loaded.basis.first_dropped_hz == built.basis.first_dropped_hz
    monkeypatch.undo()
    # and both are what the reduction gives without any cache
    _assert_same_bits(_arrays(_uncached(monkeypatch, lambda: reduced_model(rig))),
                      _arrays(built))


def _must_not_run(*args, **kwargs):
    raise AssertionError("a cache hit computed the value again")


@pytest.mark.parametrize("reduction", [None, Reduction()], ids=["full", "reduced"])
def test_runs_with_cached_rig_results_give_the_bits_of_runs_without(cache_dir, monkeypatch,
                                                                    reduction):
    reference = _uncached(monkeypatch, lambda: _result_arrays(simulate(_short(reduction))))
    cold = _result_arrays(simulate(_short(reduction)))     # computes and stores
    _forget_in_process()
    kinds = {p.name.rsplit("-", 1)[0] for p in cache_dir.iterdir()}
    assert kinds == {"model", "critical-speeds"} | ({"reduced-model"} if reduction else set())
    from rubdiag.assembly import assemble as real_assemble

    monkeypatch.setattr("rubdiag.assembly._assemble", _must_not_run)
    monkeypatch.setattr("rubdiag.modal.critical_speeds", _must_not_run)
    warm = _result_arrays(simulate(_short(reduction)))     # reads everything from disk
    monkeypatch.setattr("rubdiag.assembly._assemble", real_assemble)
    for name in ("q", "contact_fn", "contact_status", "episodes.peak_normal_force"):
        assert reference[name].size > 0, name
    assert reference["contact_fn"].max() > 0        # the run touches: the contact law ran
    _assert_same_bits(cold, reference)
    _assert_same_bits(warm, reference)


def test_a_model_read_from_disk_equals_the_assembled_one(cache_dir):
    from rubdiag.assembly import assemble

    rig = rubdiag.paper_rig()
    rig_cache.assembled(rig)
    _forget_in_process()
    loaded, fresh = rig_cache.assembled(rig), assemble(rig)
    assert loaded.rayleigh == fresh.rayleigh and loaded.dofs == fresh.dofs
    for name in ("M", "K", "G", "K_structural", "C_discrete"):
        a, b = getattr(loaded, name), getattr(fresh, name)
        assert (a != b).nnz == 0, name
        _assert_same_bits({"data": a.data, "indices": a.indices, "indptr": a.indptr},
                          {"data": b.data, "indices": b.indices, "indptr": b.indptr})


def test_the_cache_key_follows_the_rigs_content(cache_dir):
    rig = rubdiag.paper_rig()
    heavier = _heavier(rig)
    first, second = reduced_model(rig), reduced_model(heavier)
    assert not second.from_disk                     # another rig is another entry
    assert len(list(cache_dir.glob("reduced-model-*.npz"))) == 2
    # every mass 1 % higher (all come from the density): the fixed-interface frequencies
    # ∝ 1/√ρ — what the changed rig gives, not the cached entry of the first
    np.testing.assert_allclose(second.basis.mode_frequencies_hz,
                               first.basis.mode_frequencies_hz / np.sqrt(1.01), rtol=1e-9)
    # the same content, built again as another object, is the same entry
    same = rubdiag.model.rig_from_dict(rubdiag.model.rig_to_dict(rig))
    assert same is not rig
    _forget_in_process()
    assert reduced_model(same).from_disk
    # another cutoff is another entry
    assert not reduced_model(rig, Reduction(cutoff_hz=3000.0)).from_disk


def _heavier(rig):
    material = dataclasses.replace(rig.material,
                                   density_kg_m3=1.01 * rig.material.density_kg_m3)
    return dataclasses.replace(rig, material=material)


def test_another_environment_is_another_entry(cache_dir, monkeypatch):
    depends_on = {"rig": "r"}
    here = _cache.path("x", depends_on)
    other = dict(_cache.environment(), blas=[["openblas", "0.3.30", "SkylakeX"]])
    monkeypatch.setattr(_cache, "environment", lambda: other)
    assert _cache.path("x", depends_on) != here
    monkeypatch.setattr(_cache, "environment", lambda: dict(other, rubdiag="99.0"))
    assert len({here, _cache.path("x", depends_on)}) == 2


@pytest.mark.parametrize("damage", ["truncated", "empty", "garbage", "another key"])
def test_a_damaged_cache_file_is_ignored_and_rewritten(cache_dir, damage):
    rig = rubdiag.paper_rig()
    built = _arrays(reduced_model(rig))
    [file] = cache_dir.glob("reduced-model-*.npz")
    content = file.read_bytes()
    if damage == "truncated":
        file.write_bytes(content[: len(content) // 2])
    elif damage == "empty":
        file.write_bytes(b"")
    elif damage == "garbage":
        file.write_bytes(b"not a cache file " * 100)
    else:    # a readable entry of another rig under this file's name
        reduced_model(_heavier(rig))
        [other] = set(cache_dir.glob("reduced-model-*.npz")) - {file}
        other.replace(file)
    _forget_in_process()
    again = reduced_model(rig)
    assert not again.from_disk
    _assert_same_bits(_arrays(again), built)
    _forget_in_process()
    assert reduced_model(rig).from_disk             # the file was rewritten, whole


def test_an_unwritable_cache_folder_costs_nothing_but_the_cache(tmp_path, monkeypatch):
    blocker = tmp_path / "a file"
    blocker.write_text("")
    monkeypatch.setenv(_cache.ENV, str(blocker / "cache"))   # cannot be created
    _forget_in_process()
    try:
        assert not reduced_model(rubdiag.paper_rig()).from_disk
    finally:
        _forget_in_process()


def _blas_threads() -> set[int]:
    return {i["num_threads"] for i in threadpool_info() if i["user_api"] == "blas"}


def test_a_runs_blas_runs_on_one_thread(cache_dir, monkeypatch):
    seen = []
    real_rig_system = simulation_module.rig_system
    real_craig_bampton = reduced.craig_bampton

    def rig_system(run, model):    # the run's set-up: steady state, reduction
        seen.append(("run", _blas_threads()))
        return real_rig_system(run, model)

    def craig_bampton(*args):      # the reduction's eigenproblem and solves
        seen.append(("reduction", _blas_threads()))
        return real_craig_bampton(*args)

    monkeypatch.setattr(simulation_module, "rig_system", rig_system)
    monkeypatch.setattr(reduced, "craig_bampton", craig_bampton)
    with threadpool_limits(limits=2, user_api="blas"):   # a 2-thread pool around the run
        assert _blas_threads() == {2}
        simulate(_short(Reduction()))
        after = _blas_threads()
        _forget_in_process()
        _cache.clear()
        reduced_model(rubdiag.paper_rig())    # called on its own, outside a run
    assert seen == [("run", {1}), ("reduction", {1}), ("reduction", {1})]
    assert after == {2}                       # the caller's setting is back after the run
