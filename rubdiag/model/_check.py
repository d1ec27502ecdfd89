"""Field validation shared by the rig dataclasses.

Every check raises ``ValueError`` with one line naming the field, the value and the allowed
range, e.g. ``Shaft.element_lengths_m[3] = -0.01 is out of range (allowed: > 0)``.
"""

from __future__ import annotations

import math
from collections.abc import Iterable


def _fail(name: str, value, allowed: str) -> ValueError:
    return ValueError(f"{name} = {value!r} is out of range (allowed: {allowed})")


def number(name: str, value, *, lo: float | None = None, hi: float | None = None,
           lo_open: bool = False, hi_open: bool = False) -> float:
    """Return ``value`` as a float after checking it is finite and inside [lo, hi]."""
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise ValueError(f"{name} = {value!r} has the wrong type (expected a number)")
    value = float(value)
    parts = []
    if lo is not None:
        parts.append(f"{'>' if lo_open else '>='} {lo:g}")
    if hi is not None:
        parts.append(f"{'<' if hi_open else '<='} {hi:g}")
    allowed = " and ".join(parts) or "a finite number"
    if not math.isfinite(value):
        raise _fail(name, value, allowed)
    if lo is not None and (value < lo or (lo_open and value == lo)):
        raise _fail(name, value, allowed)
    if hi is not None and (value > hi or (hi_open and value == hi)):
        raise _fail(name, value, allowed)
    return value


def positive(name: str, value) -> float:
    return number(name, value, lo=0.0, lo_open=True)


def non_negative(name: str, value) -> float:
    return number(name, value, lo=0.0)


def integer(name: str, value, *, lo: int | None = None, hi: int | None = None) -> int:
    if isinstance(value, bool) or not isinstance(value, int):
        raise ValueError(f"{name} = {value!r} has the wrong type (expected an integer)")
    if (lo is not None and value < lo) or (hi is not None and value > hi):
        allowed = " and ".join(
            p for p in (f">= {lo}" if lo is not None else "", f"<= {hi}" if hi is not None else "")
            if p)
        raise _fail(name, value, allowed)
    return value


def numbers(name: str, values, check=positive, length: int | None = None) -> tuple[float, ...]:
    """Check a sequence of numbers element-wise; a scalar is broadcast to ``length``."""
    if isinstance(values, (int, float)) and not isinstance(values, bool):
        if length is None:
            raise ValueError(f"{name} = {values!r} has the wrong type (expected a list)")
        values = (values,) * length
    if isinstance(values, (str, bytes)) or not isinstance(values, Iterable):
        raise ValueError(f"{name} = {values!r} has the wrong type (expected a list of numbers)")
    values = tuple(values)
    if length is not None and len(values) != length:
        raise ValueError(f"{name} has {len(values)} entries (allowed: exactly {length})")
    if not values:
        raise ValueError(f"{name} is empty (allowed: at least one entry)")
    return tuple(check(f"{name}[{i}]", v) for i, v in enumerate(values))


def choice(name: str, value, allowed: Iterable[str]) -> str:
    allowed = tuple(allowed)
    if value not in allowed:
        raise ValueError(f"{name} = {value!r} is not allowed (allowed: {', '.join(allowed)})")
    return value
