"""rubdiag: blade-rotor-casing rub-impact simulation and diagnosis.

The top level is light: ``import rubdiag`` loads no numerical library and changes nothing of
its process. Each public name is imported from its submodule on first use.
:func:`pin_blas_kernels`, called before numpy is imported, pins OpenBLAS's kernels, so that
runs give the same bits on every x86-64 CPU (``rubdiag/_blas.py``); the command line calls it.
"""

from __future__ import annotations

import importlib

from rubdiag._blas import pin_blas_kernels
from rubdiag._deprecation import moved_names
from rubdiag._version import __version__

# public name -> the subpackage that defines it, by workflow
_LAZY = {
    # describe a rig
    "Rig": "rubdiag.model", "paper_rig": "rubdiag.model", "load_rig": "rubdiag.model",
    "save_rig": "rubdiag.model", "Unbalance": "rubdiag.model",
    # its linear behaviour
    "assemble": "rubdiag.assembly", "modes": "rubdiag.modal", "campbell": "rubdiag.modal",
    "critical_speeds": "rubdiag.modal", "unbalance_response": "rubdiag.modal",
    "calibrate": "rubdiag.modal",
    # simulate a run
    "Run": "rubdiag.simulation", "SpeedProfile": "rubdiag.simulation",
    "simulate": "rubdiag.simulation", "SimulationResult": "rubdiag.simulation",
    "load_result": "rubdiag.simulation", "ramp_run": "rubdiag.runs",
    # features: one function per input kind
    "read_signals": "rubdiag.signal", "amplitude_spectrum": "rubdiag.signal",
    "signal_features": "rubdiag.signal", "orbit_features": "rubdiag.signal",
    "revolution_features": "rubdiag.signal", "run_features": "rubdiag.runs",
    "RubFeatures": "rubdiag.signal", "waterfall": "rubdiag.signal",
    "order_track": "rubdiag.signal",
    # a labelled dataset
    "Design": "rubdiag.dataset", "generate": "rubdiag.dataset", "load": "rubdiag.dataset",
    # classifiers
    "cross_validate": "rubdiag.learn", "train": "rubdiag.learn", "evaluate": "rubdiag.learn",
    "predict": "rubdiag.learn", "load_model": "rubdiag.learn",
    # the study's Table 2
    "table2": "rubdiag.paper",
}

# old top-level names: one release of DeprecationWarning, then only in their subpackage
_MOVED = {
    "DofMap": "rubdiag.assembly.DofMap",
    "Model": "rubdiag.assembly.Model",
    "rayleigh_coefficients": "rubdiag.assembly.rayleigh_coefficients",
    "harmonic_response": "rubdiag.modal.harmonic_response",
    "features": ("rubdiag.runs._features.features_of_anything",
                 "use rubdiag.signal_features for measured signals and "
                 "rubdiag.run_features for simulated runs"),
    "prefixed_features": ("rubdiag.signal._table.prefixed_features",
                          "use rubdiag.run_features for simulated runs, or "
                          "rubdiag.signal_features for named signals"),
    "features_by_revolution": "rubdiag.revolution_features",
    "feature_names": "rubdiag.signal.feature_names",
    "spectral_lines": "rubdiag.signal.spectral_lines",
    "combination_pairs": "rubdiag.signal.combination_pairs",
    "contact_statistics": "rubdiag.runs.contact_statistics",
    "tacho_speed": "rubdiag.signal.tacho_speed",
    "dominant_speed": "rubdiag.signal.dominant_speed",
    "tacho_angle": "rubdiag.signal.tacho_angle",
    "order_spectrum": "rubdiag.signal.order_spectrum",
    "rpm_order_map": "rubdiag.signal.rpm_order_map",
    "runup_orders": "rubdiag.runs.runup_orders",
    "runup_summary": "rubdiag.runs.runup_summary",
}

__all__ = ["__version__", "pin_blas_kernels", *sorted(_LAZY)]


def _lazy(name: str):
    try:
        module = _LAZY[name]
    except KeyError:
        raise AttributeError(f"module 'rubdiag' has no attribute {name!r}") from None
    value = getattr(importlib.import_module(module), name)
    globals()[name] = value
    return value


__getattr__ = moved_names("rubdiag", _MOVED, fallback=_lazy)


def __dir__() -> list[str]:
    return __all__
