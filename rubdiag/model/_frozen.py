"""The one helper the rig's frozen dataclasses share."""

from __future__ import annotations

__all__ = ["set_field"]


def set_field(obj, name: str, value) -> None:
    """Normalise a field of a frozen dataclass during ``__post_init__``.

    Parameters
    ----------
    obj : object
        The dataclass instance being made.
    name : str
        The field.
    value : object
        Its normalised value.
    """
    object.__setattr__(obj, name, value)
