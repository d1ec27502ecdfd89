"""The factors a design may vary, and how one factor is given: levels or a range.

A list is always a set of levels (``case = [1, 2]``, ``gap_mm = [1.9, 2.3]``); a table
``{low, high}`` is a continuous range, which a grid cuts into ``n`` equally spaced levels
(``{low, high, n}``, both ends included). A table ``{bands = [[a, b], [c, d], …]}`` is a
range made of separate bands (``speed_ratio = {bands = [[0.45, 0.55], [0.9, 1.1]]}``:
around half the critical speed and around it): each band owns an equal share of the
sampling axis, as levels do, and is continuous inside it; a grid takes ``n`` levels in
each band. Every value is checked against the factor's physical range when the factor is
made.

Factors (``FACTORS``, in their canonical order) and their physical ranges:

- ``case``: the study's unbalance pattern, 1 (in phase) or 2 (out of phase); levels only.
- ``phase_diff_deg``: the unbalance phase of every second disc along the shaft (deg), the
  others at 0; 0 is case 1's pattern, 180 case 2's. 0 … 360.
- ``speed_ratio``: speed / the case's forward critical speed (the 1st for case 1, the 2nd for
  case 2; see ``Design.critical_speeds_rad_s``). > 0 … 10.
- ``speed_rpm``: speed (rpm). > 0 … 900000.
- ``gap_mm``: blade-casing gap g0 (mm). > 0 … 100.
- ``interference_ratio``: the gap set from the run's own response instead: g0 = the
  largest linear (contact-free) approach of its blades at its speed over this ratio
  (:mod:`rubdiag.dataset._approach`; the row's label ``interference_ratio`` then equals it).
  > 0 … 100. So that a rub run rubs as hard at every speed, case and rig variant.
- ``mu``: friction coefficient μ of the contact law. 0 … 10.
- ``unbalance_scale``: times the rig's unbalance magnitudes. 0 … 100.
- ``normal_stiffness_n_m``: contact normal stiffness k_N (N/m); k_T keeps the rig's ratio
  k_T/k_N. > 0.
- ``contact_stiffness_scale``: times the rig's contact stiffnesses k_N and k_T. > 0.
- ``casing_stiffness_scale``: times the casing support stiffnesses (k_y, k_z, and k_rx when
  the rig sets it; not the dampers). > 0 … 1000.
- ``damping_ratio``: the modal damping ratio ξ of both modes of the Rayleigh fit. > 0 … 1.
- ``disc_mass_scale``: times each disc's mass and inertias. > 0 … 10.
- ``oil_viscosity_scale``, ``bearing_clearance_scale``: times each journal bearing's oil
  viscosity and radial clearance (rigs with journal bearings). > 0 … 10.

  These five are the model-uncertainty factors (:mod:`rubdiag.dataset._rig_factors`).
- ``blade_count``: the number of blades on the bladed disc, 1 … 360; levels only
  (:mod:`rubdiag.dataset._rig_factors`: the casing mesh follows).
- ``fault``: the faults a run carries (:data:`rubdiag.dataset._faults.FAULT_LEVELS`: ``none``,
  ``rub``, ``misalignment``, ``crack``, ``looseness``, ``whirl`` and ``rub+`` each of the
  other four);
  levels only (:mod:`rubdiag.dataset._faults`).
- ``crack_depth_ratio``: the crack's depth a/D, > 0 … 0.5; only in runs with a crack.
- ``misalignment_angle_mrad``: the coupling's angular misalignment α₀ (mrad), 0 … 200;
  only in runs with a misalignment.
- ``looseness_preload_n``: the force (N) still pressing the loose pedestal onto its seat,
  0 … 1e6 (smaller: looser); only in runs with a looseness.
- ``whirl_speed_ratio``: the speed over the rig's threshold of instability on its journal
  bearings, > 0 … 10; only in runs with whirl, whose speed it sets.
- ``rub_kind``: what rubs, ``blade`` (blade tips on the casing) or ``seal`` (the shaft on
  an annular seal, :data:`rubdiag.dataset._fault_levels.RUB_KINDS`); levels only; only in
  runs with rub (:mod:`rubdiag.dataset._faults`).
- ``rubbing_blades``: which blades rub, ``alternate`` (every other blade), ``all`` or
  ``one`` (:data:`rubdiag.dataset._rig_factors.BLADE_SETS`); levels only; only in runs
  with blade rub.

Exclusive pairs (``EXCLUSIVE``): ``case``/``phase_diff_deg``, ``speed_ratio``/``speed_rpm``,
``gap_mm``/``interference_ratio``, ``normal_stiffness_n_m``/``contact_stiffness_scale``.
"""

from __future__ import annotations

import functools
import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass

from rubdiag import _check
from rubdiag.dataset._fault_levels import BLADE_SETS, RUB_KINDS, fault_level

__all__ = ["EXCLUSIVE", "FACTORS", "Factor"]


def _case(name: str, value) -> int:
    return _check.integer(name, value, lo=1, hi=2)


def _one_of(choices: tuple[str, ...]):
    def check(name: str, value) -> str:
        if not isinstance(value, str) or value not in choices:
            raise ValueError(f"{name} = {value!r} is out of range (allowed: "
                             f"{', '.join(choices)})")
        return value

    return check


def _range(lo: float, hi: float | None, *, lo_open: bool, unit: str = ""):
    if hi is None:
        return lambda name, value: _check.number(name, value, lo=lo, lo_open=lo_open,
                                                 unit=unit)
    return functools.partial(_check.number, lo=lo, hi=hi, lo_open=lo_open, unit=unit)


#: name -> check of one value (returns it as int or float). The order is the canonical one:
#: the order of a design's factors, of the columns of its points and of its sampling axes.
FACTORS: dict[str, Callable] = {
    "case": _case,
    "phase_diff_deg": _range(0.0, 360.0, lo_open=False, unit="deg"),
    "speed_ratio": _range(0.0, 10.0, lo_open=True),
    "speed_rpm": _range(0.0, 900_000.0, lo_open=True, unit="rpm"),
    "gap_mm": _range(0.0, 100.0, lo_open=True, unit="mm"),
    "interference_ratio": _range(0.0, 100.0, lo_open=True),
    "mu": _range(0.0, 10.0, lo_open=False),
    "unbalance_scale": _range(0.0, 100.0, lo_open=False),
    "normal_stiffness_n_m": _range(0.0, None, lo_open=True, unit="N/m"),
    "contact_stiffness_scale": _range(0.0, None, lo_open=True),
    "casing_stiffness_scale": _range(0.0, 1000.0, lo_open=True),
    "damping_ratio": _range(0.0, 1.0, lo_open=True),
    "disc_mass_scale": _range(0.0, 10.0, lo_open=True),
    "oil_viscosity_scale": _range(0.0, 10.0, lo_open=True),
    "bearing_clearance_scale": _range(0.0, 10.0, lo_open=True),
    "blade_count": functools.partial(_check.integer, lo=1, hi=360),
    "fault": fault_level,
    "crack_depth_ratio": _range(0.0, 0.5, lo_open=True),
    "misalignment_angle_mrad": _range(0.0, 200.0, lo_open=False, unit="mrad"),
    "looseness_preload_n": _range(0.0, 1e6, lo_open=False, unit="N"),
    "whirl_speed_ratio": _range(0.0, 10.0, lo_open=True),
    "rub_kind": _one_of(RUB_KINDS),
    "rubbing_blades": _one_of(BLADE_SETS),
}

#: Factors that say the same thing two ways: a design gives at most one of each pair.
EXCLUSIVE = (("case", "phase_diff_deg"), ("speed_ratio", "speed_rpm"),
             ("gap_mm", "interference_ratio"),
             ("normal_stiffness_n_m", "contact_stiffness_scale"))

#: Factors that take levels only (a range of them means nothing).
_LEVELS_ONLY = ("case", "blade_count", "fault", "rub_kind", "rubbing_blades")
_RANGE_KEYS = ("low", "high", "n", "bands")


@dataclass(frozen=True)
class Factor:
    """One factor of a design: ``levels`` (a tuple), or a range ``low`` < ``high`` with an
    optional number of grid levels ``n`` (>= 2; used by ``method = "grid"`` only), or
    ``bands``: ``((low, high), …)`` ranges in increasing order that do not overlap (then
    ``low`` and ``high`` are the first band's low and the last band's high, and ``n``
    counts grid levels per band).

    Parameters
    ----------
    name : str
        The factor's name (a design key).
    levels : tuple or None
        The levels.
    low, high : float or None
        The range.
    n : int or None
        Grid levels over the range (or per band).
    bands : tuple of (float, float) or None
        Ranges of the factor.
    """

    name: str
    levels: tuple | None = None
    low: float | None = None
    high: float | None = None
    n: int | None = None
    bands: tuple | None = None

    def __post_init__(self):
        if self.bands is not None:
            self._check_bands()
            return
        if self.name not in FACTORS:
            raise ValueError(f"unknown factor 'factors.{self.name}' "
                             f"(allowed: {', '.join(FACTORS)})")
        where = f"factors.{self.name}"
        check = FACTORS[self.name]
        if self.levels is not None:
            if any(v is not None for v in (self.low, self.high, self.n)):
                raise ValueError(f"{where} has levels and a range (allowed: one of them)")
            if isinstance(self.levels, str | bytes | Mapping) or not hasattr(
                    self.levels, "__iter__"):
                raise _check.wrong_type(where, self.levels, "a list of levels")
            levels = tuple(check(f"{where}[{i}]", v) for i, v in enumerate(self.levels))
            if not levels:
                raise ValueError(f"{where} is empty (allowed: at least one level)")
            if len(set(levels)) != len(levels):
                raise ValueError(f"{where} = {_check.plain(levels)} lists a level twice")
            object.__setattr__(self, "levels", levels)
            return
        if self.name in _LEVELS_ONLY:
            raise _check.wrong_type(where, {"low": self.low, "high": self.high},
                                    "a list of levels, e.g. [1, 2]")
        for key in ("low", "high"):
            if getattr(self, key) is None:
                raise ValueError(f"{where}.{key} is missing (a range needs low and high)")
        low = check(f"{where}.low", self.low)
        high = check(f"{where}.high", self.high)
        if not low < high:
            raise _check.out_of_range(f"{where}.low", low, f"< high = {_check.plain(high)}")
        object.__setattr__(self, "low", low)
        object.__setattr__(self, "high", high)
        if self.n is not None:
            _check.integer(f"{where}.n", self.n, lo=2)

    def _check_bands(self) -> None:
        where = f"factors.{self.name}"
        if self.levels is not None or self.low is not None or self.high is not None:
            raise ValueError(f"{where} has bands and levels or low/high (allowed: one of "
                             "them)")
        if self.name in _LEVELS_ONLY:
            raise _check.wrong_type(where, {"bands": self.bands}, "a list of levels")
        allowed = "a list of [low, high] pairs, e.g. [[0.45, 0.55], [0.9, 1.1]]"
        if isinstance(self.bands, str | bytes | Mapping) or not hasattr(self.bands,
                                                                          "__iter__"):
            raise _check.wrong_type(f"{where}.bands", self.bands, allowed)
        bands = []
        for i, band in enumerate(self.bands):
            if isinstance(band, str | bytes | Mapping) or not hasattr(band, "__iter__") \
                    or len(band) != 2:
                raise _check.wrong_type(f"{where}.bands[{i}]", band, allowed)
            low, high = (FACTORS[self.name](f"{where}.bands[{i}][{j}]", v)
                         for j, v in enumerate(band))
            if not low < high:
                raise _check.out_of_range(f"{where}.bands[{i}][0]", low,
                                          f"< its high = {_check.plain(high)}")
            if bands and low <= bands[-1][1]:
                raise _check.out_of_range(f"{where}.bands[{i}][0]", low,
                                          f"> the previous band's high = "
                                          f"{_check.plain(bands[-1][1])} (bands in "
                                          "increasing order, apart)")
            bands.append((float(low), float(high)))
        if len(bands) < 2:
            raise ValueError(f"{where}.bands has {len(bands)} band(s) (allowed: at least "
                             "2; one range is {low, high})")
        object.__setattr__(self, "bands", tuple(bands))
        object.__setattr__(self, "low", bands[0][0])
        object.__setattr__(self, "high", bands[-1][1])
        if self.n is not None:
            _check.integer(f"{where}.n", self.n, lo=2)

    @classmethod
    def from_spec(cls, name: str, spec) -> Factor:
        """A factor from its TOML form: a list of levels or a table ``{low, high[, n]}``."""
        if name not in FACTORS:
            return cls(name)        # raises: the unknown-factor message
        if isinstance(spec, Mapping):
            unknown = sorted(set(spec) - set(_RANGE_KEYS))
            if unknown:
                raise ValueError(f"unknown key 'factors.{name}.{unknown[0]}' "
                                 f"(allowed: {', '.join(_RANGE_KEYS)})")
            return cls(name, **spec)
        if isinstance(spec, list | tuple):
            return cls(name, levels=tuple(spec))
        raise _check.wrong_type(f"factors.{name}", spec,
                                "a list of levels or a table {low, high}")

    def to_spec(self):
        """The TOML form: a list of levels, ``{low, high[, n]}`` or ``{bands[, n]}``."""
        if self.levels is not None:
            return list(self.levels)
        spec = ({"low": self.low, "high": self.high} if self.bands is None
                else {"bands": [list(b) for b in self.bands]})
        return spec if self.n is None else {**spec, "n": self.n}

    @property
    def is_range(self) -> bool:
        return self.levels is None

    @property
    def is_constant(self) -> bool:
        """A single level: the same value in every point, and no sampling axis."""
        return self.levels is not None and len(self.levels) == 1

    def grid_levels(self) -> tuple:
        """The values a grid takes: the levels, or ``n`` equally spaced values of the
        range, both ends included."""
        if self.levels is not None:
            return self.levels
        if self.n is None:
            raise ValueError(f"factors.{self.name}.n is missing (method = 'grid' needs the "
                             "number of levels of each {low, high} factor)")
        return tuple(v for low, high in self.bands or ((self.low, self.high),)
                     for v in _spaced(low, high, self.n))

    def from_unit(self, u: float):
        """The value at unit-interval coordinate ``u`` in [0, 1): ``low + u·(high - low)``
        for a range; for k levels, level ``floor(u·k)`` — each level owns an equal share of
        the interval, in the order the levels are listed; for k bands, band ``floor(u·k)``
        at ``low + (u·k - floor(u·k))·(high - low)``."""
        if self.bands is not None:
            k = len(self.bands)
            i = min(math.floor(u * k), k - 1)
            low, high = self.bands[i]
            return low + (u * k - i) * (high - low)
        if self.levels is None:
            return self.low + u * (self.high - self.low)
        k = len(self.levels)
        return self.levels[min(math.floor(u * k), k - 1)]


def _spaced(low: float, high: float, n: int) -> list[float]:
    """``n`` equally spaced values from ``low`` to ``high``, both ends exact."""
    step = (high - low) / (n - 1)
    return [low + i * step for i in range(n - 1)] + [high]
