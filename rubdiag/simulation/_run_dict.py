"""A :class:`~rubdiag.simulation.Run` as plain JSON-ready data, and back: what result files
store and run ids hash (the rule that writes it: :mod:`rubdiag.simulation._described`)."""

from __future__ import annotations

from rubdiag.model import BladeContact, Unbalance, rig_from_dict
from rubdiag.reduce import Reduction
from rubdiag.simulation._described import described
from rubdiag.simulation._faults import Crack, Faults, Looseness
from rubdiag.simulation._misalignment import Misalignment
from rubdiag.simulation._run import Run
from rubdiag.simulation._sensors import Sensor
from rubdiag.simulation._speed_profile import SpeedProfile
from rubdiag.simulation._static_load import StaticLoad

__all__ = ["run_from_dict", "run_to_dict"]


def run_to_dict(run: Run) -> dict:
    """``run`` as plain JSON-ready data (the rig as in its TOML file, SI units): what result
    files store and run ids hash; :func:`run_from_dict` reads it back. Every field is
    written but those added after the first release, which are written only when set
    (:mod:`rubdiag.simulation._described`): a run that does not use them keeps its id."""
    return described(run)


def _faults_from_dict(data: dict) -> Faults:
    parts = {"misalignment": Misalignment, "crack": Crack, "looseness": Looseness}
    return Faults(**{name: None if data.get(name) is None else kind(**data[name])
                     for name, kind in parts.items()})


def run_from_dict(data: dict) -> Run:
    """The :class:`Run` of :func:`run_to_dict`'s data (no ``reduction``: the full model; a
    reduction without ``tip_rotations`` was saved before the option, which it lacked)."""
    data = dict(data)
    if data.get("reduction") is not None:
        data["reduction"] = Reduction(**{"tip_rotations": False, **data["reduction"]})
    if data.get("speed_profile") is not None:
        data["speed_profile"] = SpeedProfile(**data["speed_profile"])
    if data.get("static_load") is not None:
        data["static_load"] = StaticLoad(**data["static_load"])
    if data.get("faults") is not None:
        data["faults"] = _faults_from_dict(data["faults"])
    data["sensors"] = tuple(Sensor(**s) for s in data.get("sensors", ()))
    data["rig"] = rig_from_dict(data["rig"])
    u = data["unbalance"]
    data["unbalance"] = Unbalance(tuple(u["magnitudes_kg_m"]), tuple(u["phases_rad"]))
    if data.get("contact") is not None:
        c = dict(data["contact"])
        c["blades"] = tuple(c["blades"])
        data["contact"] = BladeContact(**c)
    return Run(**data)
