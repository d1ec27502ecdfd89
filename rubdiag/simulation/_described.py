"""A run's description as plain data, by one rule: what result files store and run ids hash.

Every field of a description (a :class:`~rubdiag.simulation.Run` and the frozen dataclasses
it holds, recursively) is written under its name, as JSON-ready data (tuples as lists), with
one exception: a field declared ``field(default=None, metadata=WHEN_SET)`` is written only
when it is set (not None).
Every field added to a description after its first release is declared so, and so a
description that does not use it is written as before it existed: its run id and result
files stay as they were. A value that describes itself is written as its own description: a
:class:`~rubdiag.model.Rig` as in its TOML file, a :class:`~rubdiag.reduce.Reduction` as its
``description()``.
"""

from __future__ import annotations

import dataclasses

from rubdiag.model import Rig, rig_to_dict

__all__ = ["WHEN_SET", "described"]

#: the metadata of a field (default None) that a description writes only when it is set
WHEN_SET = {"described": "when set"}


def described(value):
    """``value`` (a description, or any of its fields' values) as plain data, by the rule
    of the module docstring."""
    if isinstance(value, Rig):
        return rig_to_dict(value)
    if callable(getattr(value, "description", None)):
        return value.description()
    if dataclasses.is_dataclass(value) and not isinstance(value, type):
        return {f.name: described(getattr(value, f.name)) for f in dataclasses.fields(value)
                if not (f.metadata == WHEN_SET and getattr(value, f.name) is None)}
    if isinstance(value, list | tuple):
        return [described(v) for v in value]
    return value
