"""Model description layer: what the rig is, in frozen SI dataclasses, and its TOML files."""

from rubdiag.model._bearings import Bearing, JournalFilm, Pedestal
from rubdiag.model._contacts import BladeContact, Blades, Casing, StatorContact
from rubdiag.model._io import load_rig, paper_rig, rig_from_dict, rig_to_dict, save_rig
from rubdiag.model._loading import Loading, Unbalance
from rubdiag.model._rig import Damping, Rig
from rubdiag.model._rotor import Disc, Material, Shaft
from rubdiag.model.presets import PRESETS, preset_rig

__all__ = [
    "PRESETS",
    "Bearing",
    "BladeContact",
    "Blades",
    "Casing",
    "Damping",
    "Disc",
    "JournalFilm",
    "Loading",
    "Material",
    "Pedestal",
    "Rig",
    "Shaft",
    "StatorContact",
    "Unbalance",
    "load_rig",
    "paper_rig",
    "preset_rig",
    "rig_from_dict",
    "rig_to_dict",
    "save_rig",
]
