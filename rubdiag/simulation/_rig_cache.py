"""What a run computes from its rig alone, kept for the next run of the same rig.

The assembled model, the forward critical speeds (the study's running speeds: an
eigenvalue problem) and the threshold of instability on journal bearings (a search over
speeds, which the whirl runs of a design refer to) are kept per process and on disk
(:mod:`rubdiag._cache`, keyed by the rig's content, the code and the environment); the
reduced model has its own cache
(:func:`rubdiag.reduce.reduced_model`). A cached value holds the bits computed on a miss, so
a run gives the same bits either way (``tests/simulation/test_rig_cache.py``).

The model is shared by every run of the rig in the process: nothing may change it in place.
"""

from __future__ import annotations

import functools

import numpy as np

from rubdiag import _cache

__all__ = ["assembled", "damped_model", "forward_critical_speeds", "whirl_threshold_speed"]

#: the model's sparse matrices (CSR), as the disk cache holds them
_MATRICES = ("M", "K", "G", "K_structural", "C_discrete")
_PARTS = ("data", "indices", "indptr")


@functools.lru_cache(maxsize=8)
def assembled(rig):
    """``rubdiag.assembly._assemble(rig)``, once per rig and environment."""
    from rubdiag.assembly import Model, assemble, dof_map
    from rubdiag.model import rig_to_dict

    def compute() -> dict[str, np.ndarray]:
        model = assemble(rig)
        arrays = {f"{name}.{part}": getattr(getattr(model, name), part)
                  for name in _MATRICES for part in _PARTS}
        arrays["rayleigh"] = np.array(model.rayleigh or (), dtype=float)
        return arrays

    names = (*(f"{name}.{part}" for name in _MATRICES for part in _PARTS), "rayleigh")
    arrays, _ = _cache.cached("model", {"rig": rig_to_dict(rig)}, names, compute)
    dofs = dof_map(rig)
    matrices = {name: _csr(*(arrays[f"{name}.{part}"] for part in _PARTS), dofs.n_dof)
                for name in _MATRICES}
    rayleigh = tuple(float(x) for x in arrays["rayleigh"]) or None
    return Model(rig=rig, dofs=dofs, rayleigh=rayleigh, **matrices)


def _csr(data, indices, indptr, n: int):
    import scipy.sparse as sp

    return sp.csr_matrix((data, indices, indptr), shape=(n, n))


@functools.lru_cache(maxsize=8)
def damped_model(rig):
    """``with_rayleigh(assemble(rig))``, once per rig and process."""
    from rubdiag.modal import with_rayleigh

    return with_rayleigh(assembled(rig))


@functools.lru_cache(maxsize=32)
def forward_critical_speeds(rig, n: int) -> tuple[float, ...]:
    """``critical_speeds(assemble(rig), n)`` (rad/s, ascending; fewer than ``n`` when the
    rig has fewer), once per rig, ``n`` and environment."""
    from rubdiag.model import rig_to_dict

    def compute() -> dict[str, np.ndarray]:
        from rubdiag.modal import critical_speeds

        return {"speeds_rad_s": np.asarray(critical_speeds(assembled(rig), n=n), dtype=float)}

    arrays, _ = _cache.cached("critical-speeds", {"rig": rig_to_dict(rig), "n": int(n)},
                              ("speeds_rad_s",), compute)
    return tuple(float(x) for x in arrays["speeds_rad_s"])


def whirl_threshold_speed(rig, critical_rad_s: tuple[float, ...]) -> float | None:
    """The threshold of instability (rad/s) of ``rig`` on its journal bearings, sought
    between half the first and twice the last of ``critical_rad_s``, its forward critical
    speeds (:func:`rubdiag.modal._stability.threshold_speed`; None: stable there), once
    per rig and environment on disk."""
    from rubdiag.model import rig_to_dict

    def compute() -> dict[str, np.ndarray]:
        from rubdiag.assembly import assemble
        from rubdiag.modal import with_rayleigh
        from rubdiag.modal._stability import threshold_speed, whirl_range

        found = threshold_speed(with_rayleigh(assemble(rig)), *whirl_range(critical_rad_s))
        return {"speed_rad_s": np.array(np.nan if found is None else found)}

    depends_on = {"rig": rig_to_dict(rig), "critical_rad_s": [float(x) for x in critical_rad_s]}
    arrays, _ = _cache.cached("whirl-threshold", depends_on, ("speed_rad_s",), compute)
    found = float(arrays["speed_rad_s"])
    return None if np.isnan(found) else found
