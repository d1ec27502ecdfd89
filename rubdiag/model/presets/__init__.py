"""Rig presets: the study's rig (package data, ``paper.toml``) and the variants built on it.

``paper``
    The study's blade-rotor-casing rig (calibrated to its critical speeds, 1500 and 5700
    rpm).
``paper-pedestal``
    The same rig with its drive-end bearing (bearing 0, shaft node 4) on a 20 kg pedestal
    standing on 20 MN/m, 500 N·s/m supports in y and z: the rig of the multi-fault designs,
    where a loose pedestal (:class:`rubdiag.simulate.faults.Looseness`) is one of the faults.
    The pedestal adds a pedestal mode far above the rotor's (the critical speeds move by
    under 0.1 %: 1499.7 and 5696.6 rpm); the same rig carries every fault level, so that
    the rig never gives the class away.
"""

from __future__ import annotations

import dataclasses
import functools

__all__ = ["PRESETS", "preset_rig"]

#: preset name -> one line on what it is
PRESETS = {
    "paper": "the study's blade-rotor-casing rig",
    "paper-pedestal": "the study's rig with bearing 0 on a 20 kg pedestal (20 MN/m)",
}

#: the pedestal of ``paper-pedestal``: heavy and stiff enough to leave the rotor's modes
#: where they were, soft enough that a loose seat shows in the shaft's response
PEDESTAL = {"mass_kg": 20.0, "k_y_n_m": 20e6, "k_z_n_m": 20e6, "c_y_ns_m": 500.0,
            "c_z_ns_m": 500.0}


@functools.cache
def preset_rig(name: str):
    """The rig preset ``name`` (:data:`PRESETS`)."""
    from rubdiag import _check
    from rubdiag.model.io import paper_rig
    from rubdiag.model.rig import Pedestal

    _check.choice("rig", name, tuple(PRESETS))
    rig = paper_rig()
    if name == "paper":
        return rig
    drive_end = dataclasses.replace(rig.bearings[0], pedestal=Pedestal(**PEDESTAL))
    return dataclasses.replace(rig, bearings=(drive_end, *rig.bearings[1:]), name=name)
