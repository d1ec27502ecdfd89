"""Rig presets: the study's rig (package data, ``paper.toml``) and the variants built on it.

``paper``
    The study's blade-rotor-casing rig (calibrated to its critical speeds, 1500 and 5700
    rpm).
``paper-pedestal``
    The same rig with its drive-end bearing (bearing 0, shaft node 4) on a 20 kg pedestal
    standing on 20 MN/m, 500 N·s/m supports in y and z: the rig of the multi-fault designs,
    where a loose pedestal (:class:`rubdiag.simulation._faults.Looseness`) is one of the faults.
    The pedestal adds a pedestal mode far above the rotor's (the critical speeds move by
    under 0.1 %: 1499.7 and 5696.6 rpm); the same rig carries every fault level, so that
    the rig never gives the class away.
``paper-journal``
    ``paper-pedestal`` on two plain journal bearings (:class:`~rubdiag.model.JournalFilm`,
    :data:`FILM`): journals of 10 mm radius, 10 mm long (L/D = 0.5, the upper end of the
    short-bearing approximation), 300 µm radial clearance, oil of 0.2 Pa·s (an ISO VG 220
    mineral oil near 40 °C), each carrying its share of the rotor's weight under gravity
    along -y (:data:`JOURNAL_LOADS_N`); the unbalance a tenth of the study's
    (1.56e-5 kg·m per disc), which keeps the journals inside their clearance at both
    critical speeds. The films lower the critical speeds (the undamped critical speed map:
    about 1410 and 4480 rpm) and make the first mode whip above about 4350 rpm, inside the
    second case's speed range (``rubdiag modal --rig paper-journal`` prints them).
"""

from __future__ import annotations

import dataclasses
import functools

__all__ = ["FILM", "JOURNAL_LOADS_N", "JOURNAL_UNBALANCE_SCALE", "PRESETS", "preset_rig"]

#: preset name -> one line on what it is
PRESETS = {
    "paper": "the study's blade-rotor-casing rig",
    "paper-pedestal": "the study's rig with bearing 0 on a 20 kg pedestal (20 MN/m)",
    "paper-journal": "paper-pedestal on two plain journal bearings (oil whip in case 2)",
}

#: the films of ``paper-journal`` (SI), without their loads
FILM = {"viscosity_pa_s": 0.2, "radius_m": 0.01, "length_m": 0.01, "clearance_m": 300e-6}
#: the share of the paper rig's rotor weight each bearing carries under 9.81 m/s² along -y
#: (N; the casing's own weight rests on its supports): its static reactions on rigid
#: bearings, checked against the assembled rig in tests/model/test_presets.py
JOURNAL_LOADS_N = (7.421, 6.900)
#: ``paper-journal``'s unbalance, relative to the study's
JOURNAL_UNBALANCE_SCALE = 0.1

#: the pedestal of ``paper-pedestal``: heavy and stiff enough to leave the rotor's modes
#: where they were, soft enough that a loose seat shows in the shaft's response
PEDESTAL = {"mass_kg": 20.0, "k_y_n_m": 20e6, "k_z_n_m": 20e6, "c_y_ns_m": 500.0,
            "c_z_ns_m": 500.0}


@functools.cache
def preset_rig(name: str):
    """The rig preset ``name`` (:data:`PRESETS`).

    Parameters
    ----------
    name : str
        A key of :data:`PRESETS`.

    Returns
    -------
    Rig
        The preset (cached: the same object each call).
    """
    from rubdiag import _check
    from rubdiag.model._bearings import Pedestal
    from rubdiag.model._io import paper_rig

    _check.choice("rig", name, tuple(PRESETS))
    rig = paper_rig()
    if name == "paper":
        return rig
    drive_end = dataclasses.replace(rig.bearings[0], pedestal=Pedestal(**PEDESTAL))
    pedestal = dataclasses.replace(rig, bearings=(drive_end, *rig.bearings[1:]), name=name)
    if name == "paper-pedestal":
        return pedestal
    from rubdiag.model._bearings import Bearing, JournalFilm

    bearings = tuple(
        Bearing(b.node, 0.0, 0.0, pedestal=b.pedestal, journal=JournalFilm(**FILM, load_n=load))
        for b, load in zip(pedestal.bearings, JOURNAL_LOADS_N, strict=True))
    loading = dataclasses.replace(rig.loading, unbalance_kg_m=tuple(
        JOURNAL_UNBALANCE_SCALE * u for u in rig.loading.unbalance_kg_m))
    return dataclasses.replace(pedestal, bearings=bearings, loading=loading)
