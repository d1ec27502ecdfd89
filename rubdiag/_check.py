"""Parameter checks shared by every layer: one message style, plain numbers.

A bad value raises one line naming the parameter, the value and what is allowed::

    Shaft.element_lengths_m[3] = -0.01 is out of range (allowed: > 0 m)
    case = '1' has the wrong type (expected an integer)

Out-of-range values raise :class:`ValueError`; wrong types raise :class:`ParameterTypeError`,
which is both a ``TypeError`` (the Python convention) and a ``ValueError`` (so that a caller
catching bad input, such as the command line, needs one ``except``). numpy scalars count as
numbers; ``bool`` does not. Values are printed as plain numbers, never as numpy reprs.
"""

from __future__ import annotations

import math
import numbers as _numbers
from collections.abc import Iterable

import numpy as np

__all__ = ["ParameterTypeError", "choice", "indices", "integer", "non_negative", "number",
           "numbers", "out_of_range", "plain", "positive", "wrong_type"]


class ParameterTypeError(TypeError, ValueError):
    """A parameter of the wrong type (a TypeError that bad-input handlers also catch)."""


def plain(value) -> str:
    """``value`` as a person writes it: ``0.0`` not ``np.float64(0.0)``, ``[1, 2]`` not
    ``array([1, 2])``; strings keep their quotes."""
    if isinstance(value, np.ndarray):
        value = value.tolist()
    elif isinstance(value, np.generic):
        value = value.item()
    if isinstance(value, tuple | list):
        return "[" + ", ".join(plain(v) for v in value) + "]"
    if isinstance(value, float):
        if not math.isfinite(value):
            return str(value)
        text = f"{value:.12g}"      # no float noise (0.30000000000000004)
        return text if any(c in text for c in ".en") else f"{text}.0"
    return repr(value)


def out_of_range(name: str, value, allowed: str) -> ValueError:
    return ValueError(f"{name} = {plain(value)} is out of range (allowed: {allowed})")


def wrong_type(name: str, value, expected: str) -> ParameterTypeError:
    return ParameterTypeError(f"{name} = {plain(value)} has the wrong type (expected {expected})")


def _is_number(value) -> bool:
    return isinstance(value, _numbers.Real) and not isinstance(value, bool | np.bool_)


def _bounds(lo, hi, lo_open, hi_open, unit) -> str:
    parts = []
    if lo is not None:
        parts.append(f"{'>' if lo_open else '>='} {lo:g}")
    if hi is not None:
        parts.append(f"{'<' if hi_open else '<='} {hi:g}")
    text = " and ".join(parts) or "a finite number"
    return f"{text} {unit}" if unit else text


def number(name: str, value, *, lo: float | None = None, hi: float | None = None,
           lo_open: bool = False, hi_open: bool = False, unit: str = "",
           allowed: str | None = None) -> float:
    """``value`` as a float, after checking it is a finite real number inside [lo, hi].

    ``unit`` is appended to the allowed range in the message; ``allowed`` replaces the
    range's text altogether.
    """
    if not _is_number(value):
        raise wrong_type(name, value, "a number")
    x = float(value)
    inside = (math.isfinite(x)
              and (lo is None or x > lo or (not lo_open and x == lo))
              and (hi is None or x < hi or (not hi_open and x == hi)))
    if not inside:
        raise out_of_range(name, value, allowed or _bounds(lo, hi, lo_open, hi_open, unit))
    return x


def positive(name: str, value, unit: str = "") -> float:
    return number(name, value, lo=0.0, lo_open=True, unit=unit)


def non_negative(name: str, value, unit: str = "") -> float:
    return number(name, value, lo=0.0, unit=unit)


def integer(name: str, value, *, lo: int | None = None, hi: int | None = None) -> int:
    """``value`` as an int; a float (even 3.0) is refused: indices and counts are exact."""
    if isinstance(value, bool | np.bool_) or not isinstance(value, int | np.integer):
        raise wrong_type(name, value, "an integer")
    value = int(value)
    if (lo is not None and value < lo) or (hi is not None and value > hi):
        raise out_of_range(name, value, _bounds(lo, hi, False, False, ""))
    return value


def indices(name: str, values, n: int | None = None) -> np.ndarray:
    """``values`` as a flat int64 array of indices (into ``range(n)`` when ``n`` is given);
    floats (even 3.0) and booleans are refused rather than truncated."""
    arr = np.asarray(values)
    if arr.size and not np.issubdtype(arr.dtype, np.integer):
        raise wrong_type(name, arr, "integer indices")
    arr = np.ascontiguousarray(arr, dtype=np.int64).reshape(-1)
    if n is not None and arr.size and (arr.min() < 0 or arr.max() >= n):
        raise out_of_range(name, arr, f"indices in [0, {n})")
    return arr


def numbers(name: str, values, check=positive, length: int | None = None) -> tuple[float, ...]:
    """Check a sequence of numbers element-wise; a scalar is broadcast to ``length``."""
    if _is_number(values):
        if length is None:
            raise wrong_type(name, values, "a list of numbers")
        values = (values,) * length
    if isinstance(values, str | bytes) or not isinstance(values, Iterable):
        raise wrong_type(name, values, "a list of numbers")
    values = tuple(values)
    if length is not None and len(values) != length:
        raise ValueError(f"{name} has {len(values)} entries (allowed: exactly {length})")
    if not values:
        raise ValueError(f"{name} is empty (allowed: at least one entry)")
    return tuple(check(f"{name}[{i}]", v) for i, v in enumerate(values))


def choice(name: str, value, allowed: Iterable[str]) -> str:
    allowed = tuple(allowed)
    if value not in allowed:
        raise ValueError(f"{name} = {plain(value)} is not allowed "
                         f"(allowed: {', '.join(allowed)})")
    return value
