"""The dataset design file (TOML): its tables and keys, read into a Design and written back.

A design file has three tables::

    [base]
    rig = "paper"             # a preset (rubdiag.model.PRESETS; default "paper", the
                              # study's), a rig TOML path, or a rig table (the resolved form)
    duration_s = 2.3          # Run.duration_s (default 2.3; not with [ramp])
    discard_s = 0.3           # Run.discard_s (default 0.3)
    reduced = false           # true: every run simulates the reduced-order model
    reduction_cutoff_hz = 2000.0  # optional, implies reduced: the Craig–Bampton cutoff (Hz)
    step_error = 1e-5         # long steps' error tolerance (Run.step_error; 0: every step
                              # at most 10 µs); default DEFAULT_STEP_ERROR
    gravity_m_s2 = 9.81       # optional: gravity along -y in every run (default 0: none);
                              # with the fault settings (rubdiag.dataset._faults.FaultSettings)

    [ramp]                    # optional: every run sweeps its speed (rubdiag.dataset._ramp)
    rate_rpm_s = 300          # > 0
    span = 0.15               # from speed·(1 - span) to speed·(1 + span); 0 < span < 1
    direction = "up"          # "up" (a run-up, default) | "down" (a coast-down)

    [sampling]
    method = "lhs"            # "grid" (default) | "lhs" | "sobol" | "random"
    n = 200                   # design points; ignored by "grid" (the product of the levels)
    seed = 7                  # default 0
    replicates = 1            # start histories per design point (default 1, at most 65)

    [labels]                  # optional: the label thresholds (rubdiag.dataset._labels)
    severity_threshold = 1.37 # interference ratio from which a rub is serious
    full_contact_share = 0.95 # share of the window in contact from which a rub is full

    [noise]                   # optional: noise floors (rubdiag.dataset._noise), SI units
    displacement_m = 1e-6

    [[sensors]]               # optional, repeated: the channels (default: default_sensors)
    point = "shaft 11"
    direction = "y"
    quantity = "displacement" # | "velocity" | "acceleration" | "reaction"

    [factors]
    case = [1, 2]                              # a list: levels
    speed_ratio = {low = 0.8, high = 1.2}      # a table: a continuous range
                                               # ({bands = [[0.45, 0.55], [0.9, 1.1]]}:
                                               # separate bands, an equal share each)
    gap_mm = {low = 0.5, high = 4.0, n = 8}    # n: the grid's levels of a range
    fault = ["none", "rub", "crack"]           # optional: rubdiag.dataset._faults
    crack_depth_ratio = [0.25, 0.45]           # a fault's severity: only its runs

The factors, their physical ranges and the exclusive pairs are listed in
:mod:`rubdiag.dataset._factors`. A design needs an unbalance pattern (``case`` or
``phase_diff_deg``) and a speed (``speed_ratio`` or ``speed_rpm``); a single level
(``case = [1]``) fixes a factor. ``speed_ratio`` is relative to the case's critical speed, so
it needs ``case``. Factors not given keep the rig's values (its nominal gap, contact law,
casing support and unbalance magnitudes). A rig path is relative to the design file's folder.

**Sampling.** ``grid`` makes every combination of the levels (a range gives ``n`` equally
spaced levels, both ends included), the last factor varying fastest. ``lhs``, ``sobol`` and
``random`` draw ``n`` points in the unit hypercube (:func:`rubdiag.dataset._sampling.unit_samples`)
with one axis per factor that varies, in the canonical factor order whatever the order in the
file; single-level factors take no axis. Coordinate u of a range is ``low + u·(high-low)``;
of a factor with k levels it is level ``floor(u·k)``, so each level owns 1/k of the axis (with
``lhs`` and n a multiple of k, exactly n/k points each). Sampling needs at least one range
(levels alone would repeat points: use ``grid``); ``sobol`` needs n a power of 2.

**Replicates** are start histories as in :mod:`rubdiag.paper._ensemble`: replicate r has
gap-ramp length ``gap_ramps_s(replicates, duration_s)[r]`` — the standard 0.1 s, then
-1 %, +1 %, -2 %, +2 % (five replicates are the paper's ensemble), then halving steps inside
±2 % (:func:`rubdiag.dataset._sampling.ramp_offsets`). ``discard_s`` must be at least the
longest ramp, so that no analysis window holds the ramp's transient.

**Speed ramp.** With ``[ramp]`` (:mod:`rubdiag.dataset._ramp`) the design point's speed is
the middle of a sweep: each run holds ``speed·(1 ∓ span)`` for ``discard_s`` (its gap ramp,
the replicate's start history, happens there), then ramps at ``rate_rpm_s`` to
``speed·(1 ± span)`` and ends. Its length is derived — ``discard_s + 2·span·speed /
rate_rpm_s``, so ``base.duration_s`` is not given (an error names both keys) — its analysis
window is the whole ramp, and every replicate has the standard gap ramp (0.1 s, ±2 %,
``gap_ramps_s(replicates)``). The ramp must hold at least ``MIN_REVOLUTIONS`` +
``ORDER_TRACK_LOST_REVOLUTIONS`` (13) revolutions at the design's slowest speed
(:mod:`rubdiag.dataset._window`): the
features are measured on the window's order-tracked record
(:func:`rubdiag.runs._features.order_tracked`), which loses up to 3 at its ends; and the
fastest speed must keep the features' 8.25× below 0.2 × the output rate
(:func:`~rubdiag.runs._features.max_tracked_rpm`: 14545 rpm at 10 kHz). Rows of a ramp
design say so (:mod:`rubdiag.dataset._rows`).

**Model.** ``reduced = true`` makes every run ``Run(..., reduction=Reduction())``: the
Craig–Bampton model of :mod:`rubdiag.reduce` with its default cutoff (2 kHz);
``reduction_cutoff_hz`` sets another cutoff and implies ``reduced`` (with ``reduced = false``
it is an error). Every row says which model made it (its ``model`` column).

**Steps.** Every run takes steps longer than its 10-µs base step where nothing is in contact
and the local error estimate allows (``Run.step_error``, relative to the largest recorded
displacement; up to 40 µs): ``step_error`` sets the tolerance,
:data:`~rubdiag.dataset._design.DEFAULT_STEP_ERROR` by default, ``0`` keeps every step at
10 µs or shorter. A closed contact is always integrated at 10 µs or shorter. With the default,
against the same runs at 10 µs, the labels are the same and the spectral features change by
less than a quarter of the scatter between start histories; a rubbing run's contact
statistics, which are chaotic, change by about that scatter (documentation: "Steps sized by
error"). The resolved form writes it only when it is not the default.

**Resolved form.** :meth:`~rubdiag.dataset.Design.to_dict` /
:meth:`~rubdiag.dataset.Design.to_toml` write everything a run depends on: the model
(``reduced = true`` and the cutoff; nothing for the full model, so that the resolved form of
a design made before reductions existed is unchanged), the ``[ramp]`` table after ``[base]``
(only when set, and then no ``duration_s``), the rig as a table (a rig file may change; a
resolved design does not), the factors in canonical order with numbers as floats, the grid's
point count as ``n``, the seed, and the critical speeds that ``speed_ratio`` refers to
(``critical_speeds_rad_s``, computed once from the rig, so that the resolved design makes
bit-identical runs on any machine). ``Design.from_toml(d.to_toml()) == d`` and the text
round-trips exactly.

**Checks.** Every value is checked when the design is made (:mod:`rubdiag.dataset._design`),
with one-line ``ValueError`` messages, and nothing is solved then: what takes an eigenvalue
search — the critical speeds ``speed_ratio`` refers to when ``critical_speeds_rad_s`` is not
given (and the analysis window's revolutions at them), each model-uncertainty or whirl
rotor's speeds — is computed when the runs are expanded
(:meth:`~rubdiag.dataset.Design.runs`, :mod:`rubdiag.dataset._expansion`) or the resolved
form written, before any run is simulated.
"""

from __future__ import annotations

import dataclasses
import tomllib
from collections.abc import Mapping
from pathlib import Path

from rubdiag import _check
from rubdiag.dataset._factors import FACTORS, Factor
from rubdiag.dataset._faults import KEYS as FAULT_KEYS
from rubdiag.dataset._faults import FaultSettings
from rubdiag.dataset._labels import LabelRules
from rubdiag.dataset._noise import NoiseFloors
from rubdiag.dataset._ramp import KEYS as RAMP_KEYS
from rubdiag.dataset._ramp import SpeedRamp
from rubdiag.model import Rig
from rubdiag.reduce import Reduction

__all__ = ["SECTIONS", "from_dict", "from_toml", "to_dict", "to_toml"]

#: The tables of a design file and the keys each may hold.
SECTIONS = {
    "base": ("rig", "duration_s", "discard_s", "reduced", "reduction_cutoff_hz",
             "step_error", "critical_speeds_rad_s", *FAULT_KEYS),
    "ramp": RAMP_KEYS,
    "sampling": ("method", "n", "seed", "replicates"),
    "factors": tuple(FACTORS),
    "labels": ("severity_threshold", "full_contact_share"),
    "noise": ("displacement_m", "velocity_m_s", "acceleration_m_s2", "force_n"),
    "sensors": ("point", "direction", "quantity", "name"),
}


def from_toml(cls, source: str | Path):
    """A design of class ``cls`` from a TOML file (a :class:`~pathlib.Path`, or a string
    without ``=`` or a line break) or from TOML text (a string with one): ``Design.from_toml``.

    Parameters
    ----------
    cls : type
        :class:`~rubdiag.dataset.Design`.
    source : str or Path
        The file or the text.

    Returns
    -------
    Design
        The design; a ValueError names the file and the key of a bad value.
    """
    is_text = isinstance(source, str) and ("\n" in source or "=" in source)
    if is_text:
        text, root, prefix = source, None, ""
    else:
        path = Path(source)
        text, root, prefix = path.read_text(encoding="utf-8"), path.parent, f"{path.name}: "
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise ValueError(f"{prefix}not valid TOML ({exc})") from None
    try:
        return from_dict(cls, data, root=root)
    except ValueError as exc:
        raise ValueError(f"{prefix}{exc}") from None


def from_dict(cls, data: Mapping, root: str | Path | None = None):
    """A design of class ``cls`` from parsed TOML (the tables of :data:`SECTIONS`); a rig
    path is relative to ``root`` (default: the working folder): ``Design.from_dict``.

    Parameters
    ----------
    cls : type
        :class:`~rubdiag.dataset.Design`.
    data : mapping
        Table name -> table.
    root : str or Path or None
        The folder a rig path is relative to.

    Returns
    -------
    Design
        The design.
    """
    if not isinstance(data, Mapping):
        raise _check.wrong_type("design", data, "a table")
    for section, value in data.items():
        if section not in SECTIONS:
            raise ValueError(f"unknown table [{section}] (allowed: "
                             f"{', '.join(SECTIONS)})")
        tables = value if section == "sensors" and isinstance(value, list) else [value]
        for table in tables:
            if not isinstance(table, Mapping):
                raise _check.wrong_type(section, table, "a table")
            for key in table:
                if key not in SECTIONS[section]:
                    what = "factor" if section == "factors" else "key"
                    raise ValueError(f"unknown {what} '{section}.{key}' "
                                     f"(allowed: {', '.join(SECTIONS[section])})")
    base = dict(data.get("base", {}))
    if "ramp" in data:
        base["ramp"] = SpeedRamp.from_dict(data["ramp"])
    base["rig"] = _rig(base.get("rig", "paper"), root)
    base["reduction"] = _reduction(base.pop("reduced", None),
                                   base.pop("reduction_cutoff_hz", None))
    factors = tuple(Factor.from_spec(k, v) for k, v in data.get("factors", {}).items())
    base["fault_settings"] = FaultSettings(**{k: base.pop(k) for k in FAULT_KEYS
                                              if k in base})
    sensors = data.get("sensors")
    if isinstance(sensors, Mapping):
        sensors = [sensors]
    return cls(factors=factors, **base, **data.get("sampling", {}),
               labels=LabelRules(**data.get("labels", {})),
               noise=NoiseFloors(**data.get("noise", {})), sensors=sensors)


def to_dict(design) -> dict:
    """The resolved form of ``design`` as plain TOML-ready data (module docstring):
    ``Design.to_dict``. Computes the critical speeds ``speed_ratio`` refers to when the
    design was not given them.

    Parameters
    ----------
    design : Design
        The design.

    Returns
    -------
    dict
        Table name -> table.
    """
    from rubdiag.model import rig_to_dict

    base = {"duration_s": design.duration_s, "discard_s": design.discard_s}
    if design.ramp is not None:
        del base["duration_s"]          # derived, run by run
    if design.reduction is not None:
        base["reduced"] = True
        base["reduction_cutoff_hz"] = float(design.reduction.cutoff_hz)
    if design.step_error != _default(design, "step_error"):
        base["step_error"] = design.step_error
    base.update(design.fault_settings.to_dict())     # only what differs from the defaults
    speeds = design.resolved_critical_speeds_rad_s()
    if speeds is not None:
        base["critical_speeds_rad_s"] = list(speeds)
    base["rig"] = rig_to_dict(design.rig)
    ramp = {} if design.ramp is None else {"ramp": design.ramp.to_dict()}
    return {"base": base, **ramp,
            "sampling": {"method": design.method, "n": design.n, "seed": design.seed,
                         "replicates": design.replicates},
            "factors": {f.name: f.to_spec() for f in design.factors},
            "labels": design.labels.to_dict(),
            "noise": design.noise.to_dict(),
            "sensors": [dataclasses.asdict(s) for s in design.sensors]}


def to_toml(design) -> str:
    """The resolved form of ``design`` as TOML text: ``[base]``, ``[sampling]`` and
    ``[factors]`` as a person writes them, then the rig as ``[base.rig]``
    (``Design.to_toml``).

    Parameters
    ----------
    design : Design
        The design.

    Returns
    -------
    str
        The text; :func:`from_toml` reads it into an equal design.
    """
    import tomli_w

    data = to_dict(design)
    rig = data["base"].pop("rig")
    lines = ["# rubdiag dataset design, resolved: everything its runs depend on is written",
             "# out (the rig itself, the point count, the seed, speed_ratio's reference",
             "# speeds), so that the same runs can be made again anywhere."]
    sensors = data.pop("sensors")
    for section, table in data.items():
        lines += ["", f"[{section}]"]
        lines += [f"{key} = {_toml_value(value)}" for key, value in table.items()]
    for sensor in sensors:
        lines += ["", "[[sensors]]"]
        lines += [f"{key} = {_toml_value(value)}" for key, value in sensor.items()]
    return "\n".join(lines) + "\n\n" + tomli_w.dumps({"base": {"rig": rig}})


def _default(design, name: str):
    """The default of the design's field ``name`` (the resolved form leaves it out)."""
    return type(design).__dataclass_fields__[name].default


def _rig(value, root) -> Rig:
    from rubdiag.model import PRESETS, load_rig, preset_rig, rig_from_dict

    if isinstance(value, Rig):
        return value
    if isinstance(value, Mapping):
        try:
            return rig_from_dict(dict(value))
        except ValueError as exc:
            raise ValueError(f"base.rig: {exc}") from None
    if not isinstance(value, str):
        raise _check.wrong_type("base.rig", value, "a preset name, a rig TOML path or a table")
    if value in PRESETS:
        return preset_rig(value)
    path = Path(value) if root is None else Path(root) / value
    if not path.is_file():
        raise ValueError(f"base.rig = {value!r} is neither a preset nor a file (allowed: "
                         f"{', '.join(map(repr, PRESETS))} or a rig TOML path)")
    try:
        return load_rig(path)
    except ValueError as exc:
        raise ValueError(f"base.rig: {exc}") from None


def _reduction(reduced, cutoff_hz) -> Reduction | None:
    """The reduction of ``[base] reduced`` and ``reduction_cutoff_hz`` (see the module
    docstring), or None: the full model."""
    if reduced is not None and not isinstance(reduced, bool):
        raise _check.wrong_type("base.reduced", reduced, "true or false")
    if cutoff_hz is None:
        return Reduction() if reduced else None
    if reduced is False:
        raise ValueError(f"base.reduction_cutoff_hz = {_check.plain(cutoff_hz)} is given with "
                         "base.reduced = false (allowed: reduced = true, or no "
                         "reduction_cutoff_hz for the full model)")
    try:
        return Reduction(cutoff_hz=cutoff_hz)
    except ValueError as exc:      # "cutoff_hz = … is out of range": name the design's key
        text = str(exc)
        raise type(exc)(f"base.reduction_{text}" if text.startswith("cutoff_hz")
                        else f"base.reduction_cutoff_hz: {text}") from None


def _toml_value(value) -> str:
    if isinstance(value, dict):
        return "{" + ", ".join(f"{k} = {_toml_value(v)}" for k, v in value.items()) + "}"
    if isinstance(value, list):
        return "[" + ", ".join(_toml_value(v) for v in value) + "]"
    if isinstance(value, str):
        return f'"{value}"'
    if isinstance(value, bool):
        return "true" if value else "false"
    return repr(value)   # int, or float in its shortest round-trip form (valid TOML)
