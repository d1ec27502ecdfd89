"""Rig files: TOML in, TOML out.

A rig file has one table per :class:`~rubdiag.model.Rig` field (``[shaft]``,
``[[bearings]]``, ``[[discs]]``, ``[blades]``, ``[casing]``, ``[contact]``,
``[[stator_contacts]]``, ``[loading]``, ``[material]``, ``[damping]``) whose keys are the
dataclass field names, in SI units. At this edge a key may also be given in a named
non-SI unit, converted on reading: ``…_mm`` for ``…_m``, ``…_deg`` for ``…_rad`` and
``…_rpm`` for ``…_rad_s``. Unknown keys and wrong types are errors. Files are written in SI.

A bearing may sit on a pedestal (:class:`~rubdiag.model.Pedestal`), a sub-table of its
``[[bearings]]`` entry (absent: the bearing is grounded, as in the paper rig)::

    [[bearings]]
    node = 4
    k_y_n_m = 500e6
    k_z_n_m = 200e6
    [bearings.pedestal]
    mass_kg = 20.0
    k_y_n_m = 50e6
    k_z_n_m = 50e6
    c_y_ns_m = 1e3
    c_z_ns_m = 1e3
"""

from __future__ import annotations

import dataclasses
import functools
import math
import tomllib
import types
import typing
from importlib import resources
from pathlib import Path

from rubdiag.model._rig import Rig

__all__ = ["load_rig", "paper_rig", "rig_from_dict", "rig_to_dict", "save_rig"]

# edge unit suffix -> (SI suffix, factor to SI)
_EDGE_UNITS = {
    "_mm": ("_m", 1e-3),
    "_deg": ("_rad", math.pi / 180.0),
    "_rpm": ("_rad_s", math.pi / 30.0),
}


def load_rig(path: str | Path) -> Rig:
    """Read a rig from a TOML file (see the module docstring for the format).

    Parameters
    ----------
    path : str or Path
        The TOML file.

    Returns
    -------
    Rig
        The validated rig.

    Raises
    ------
    ValueError
        If the file is not valid TOML, or a key is unknown, of the wrong type or out of range.
    """
    path = Path(path)
    try:
        with path.open("rb") as fh:
            data = tomllib.load(fh)
    except tomllib.TOMLDecodeError as exc:
        raise ValueError(f"{path}: not valid TOML ({exc})") from None
    try:
        return rig_from_dict(data)
    except ValueError as exc:
        raise ValueError(f"{path.name}: {exc}") from None


@functools.cache
def paper_rig() -> Rig:
    """The study's blade-rotor-casing rig, calibrated to 1500 and 5700 rpm (package data)."""
    text = resources.files("rubdiag.model.presets").joinpath("paper.toml").read_text("utf-8")
    return rig_from_dict(tomllib.loads(text))


def save_rig(rig: Rig, path: str | Path) -> Path:
    """Write ``rig`` as TOML (SI units); ``load_rig`` reads it back equal.

    Parameters
    ----------
    rig : Rig
        The rig to write.
    path : str or Path
        The TOML file, written atomically.

    Returns
    -------
    Path
        The file written.
    """
    import tomli_w

    from rubdiag._atomic import write_text

    return write_text(path, tomli_w.dumps(rig_to_dict(rig)))


def rig_to_dict(rig: Rig) -> dict:
    """The rig as plain TOML-ready data (``None`` fields left out).

    Parameters
    ----------
    rig : Rig
        The rig.

    Returns
    -------
    dict
        Nested tables and lists, one key per set field, in SI units.
    """
    return _to_plain(rig)


def rig_from_dict(data: dict) -> Rig:
    """Build a validated :class:`Rig` from parsed TOML data.

    Parameters
    ----------
    data : dict
        Parsed TOML: the tables of a rig file (module docstring); keys may use the edge units.

    Returns
    -------
    Rig
        The validated rig.
    """
    return _build(Rig, data, "")


def _to_plain(value):
    if dataclasses.is_dataclass(value):
        return {f.name: _to_plain(getattr(value, f.name)) for f in dataclasses.fields(value)
                if getattr(value, f.name) is not None}
    if isinstance(value, tuple):
        return [_to_plain(v) for v in value]
    return value


def _field_name(key: str, names: set[str]) -> tuple[str, float]:
    if key in names:
        return key, 1.0
    for suffix, (si_suffix, factor) in _EDGE_UNITS.items():
        if key.endswith(suffix) and key[: -len(suffix)] + si_suffix in names:
            return key[: -len(suffix)] + si_suffix, factor
    return "", 0.0


def _build(cls, data, where: str):
    label = where or cls.__name__
    if not isinstance(data, dict):
        raise ValueError(f"[{label}] has the wrong type (expected a table)")
    hints = typing.get_type_hints(cls)
    names = {f.name for f in dataclasses.fields(cls)}
    kwargs = {}
    for key, raw in data.items():
        name, factor = _field_name(key, names)
        if not name:
            allowed = ", ".join(sorted(names))
            raise ValueError(f"unknown key '{_join(where, key)}' (allowed: {allowed})")
        value = _convert(hints[name], raw, _join(where, key))
        kwargs[name] = _scale(value, factor) if factor != 1.0 else value
    try:
        return cls(**kwargs)
    except TypeError as exc:  # a required field is missing
        raise ValueError(f"[{label}] {exc}".replace("__init__() ", "")) from None
    except ValueError as exc:
        raise ValueError(f"[{label}] {exc}" if where else str(exc)) from None


def _join(where: str, key: str) -> str:
    return f"{where}.{key}" if where else key


def _scale(value, factor: float):
    if isinstance(value, tuple):
        return tuple(v * factor for v in value)
    return value * factor


def _convert(hint, raw, where: str):
    """Check ``raw`` against the type hint and convert lists to tuples."""
    options = typing.get_args(hint) if isinstance(hint, types.UnionType) else (hint,)
    options = [o for o in options if o is not type(None)]
    errors = []
    for option in options:
        try:
            return _convert_one(option, raw, where)
        except (TypeError, ValueError) as exc:
            errors.append(exc)
    if len(errors) == 1 and isinstance(errors[0], ValueError):
        raise errors[0]
    expected = " or ".join(_describe(o) for o in options)
    raise ValueError(f"{where} = {raw!r} has the wrong type (expected {expected})")


def _convert_one(hint, raw, where: str):
    origin = typing.get_origin(hint)
    if dataclasses.is_dataclass(hint):
        return _build(hint, raw, where)
    if origin is tuple:
        if not isinstance(raw, list):
            raise TypeError
        item = typing.get_args(hint)[0]
        return tuple(_convert_one(item, v, f"{where}[{i}]") for i, v in enumerate(raw))
    if hint is float:
        if isinstance(raw, bool) or not isinstance(raw, (int, float)):
            raise TypeError
        return float(raw)
    if hint is int or hint is bool or hint is str:
        if type(raw) is not hint:
            raise TypeError
        return raw
    raise TypeError(f"unsupported field type {hint!r}")


def _describe(hint) -> str:
    if dataclasses.is_dataclass(hint):
        return "a table"
    if typing.get_origin(hint) is tuple:
        return f"a list of {_describe(typing.get_args(hint)[0])}s"
    return {float: "number", int: "integer", bool: "true/false", str: "string"}.get(
        hint, str(hint))
