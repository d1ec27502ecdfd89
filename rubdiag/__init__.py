"""rubdiag: blade-rotor-casing rub-impact simulation and diagnosis.

The top level is light: ``import rubdiag`` loads no numerical library and changes nothing of
its process. Each public name is imported from its submodule on first use.
:func:`pin_blas_kernels`, called before numpy is imported, pins OpenBLAS's kernels, so that
runs give the same bits on every x86-64 CPU (``rubdiag/_blas.py``); the command line calls it.
"""

from __future__ import annotations

import importlib

from rubdiag._blas import pin_blas_kernels
from rubdiag._version import __version__

# public name -> submodule that defines it
_LAZY = {
    "Rig": "rubdiag.model",
    "load_rig": "rubdiag.model",
    "paper_rig": "rubdiag.model",
    "save_rig": "rubdiag.model",
    "Unbalance": "rubdiag.model",
    "assemble": "rubdiag.assembly",
    "Model": "rubdiag.assembly",
    "DofMap": "rubdiag.assembly",
    "rayleigh_coefficients": "rubdiag.assembly",
    "modes": "rubdiag.modal",
    "campbell": "rubdiag.modal",
    "critical_speeds": "rubdiag.modal",
    "unbalance_response": "rubdiag.modal",
    "harmonic_response": "rubdiag.modal",
    "calibrate": "rubdiag.modal",
    "Run": "rubdiag.simulation",
    "simulate": "rubdiag.simulation",
    "SimulationResult": "rubdiag.simulation",
    "load_result": "rubdiag.simulation",
    "features": "rubdiag.runs",
    "RubFeatures": "rubdiag.signal",
    "amplitude_spectrum": "rubdiag.signal",
    "spectral_lines": "rubdiag.signal",
    "combination_pairs": "rubdiag.signal",
    "contact_statistics": "rubdiag.runs",
    "Design": "rubdiag.dataset",
    "prefixed_features": "rubdiag.signal",
    "feature_names": "rubdiag.signal",
    "read_signals": "rubdiag.signal",
    "tacho_speed": "rubdiag.signal",
    "dominant_speed": "rubdiag.signal",
    "SpeedProfile": "rubdiag.simulation",
    "ramp_run": "rubdiag.runs",
    "runup_orders": "rubdiag.runs",
    "runup_summary": "rubdiag.runs",
    "tacho_angle": "rubdiag.signal",
    "order_track": "rubdiag.signal",
    "order_spectrum": "rubdiag.signal",
    "rpm_order_map": "rubdiag.signal",
    "waterfall": "rubdiag.signal",
    "features_by_revolution": "rubdiag.signal",
}

__all__ = ["__version__", "pin_blas_kernels", *sorted(_LAZY)]


def __getattr__(name: str):
    try:
        module = _LAZY[name]
    except KeyError:
        raise AttributeError(f"module 'rubdiag' has no attribute {name!r}") from None
    value = getattr(importlib.import_module(module), name)
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return __all__
