"""Options whose default, choices or help values are the library's, read from it.

An option that stands for a library parameter — a :class:`~rubdiag.simulation.Run` field, a
keyword of the function the command calls, a tuple of allowed values — names where that
value is defined (:func:`library_value`) instead of repeating it, so the command line
cannot drift from the library. The value is read when the command's options are parsed or
its help is shown, not when the parser is built: the modules that define them load numpy,
numba or scikit-learn, which ``rubdiag --help`` and the commands that do not need them must
not wait for (and a command pins OpenBLAS before numpy loads).
"""

from __future__ import annotations

import argparse
import dataclasses
import importlib
import inspect

__all__ = ["FromLibrary", "library_value"]


def library_value(spec: str):
    """The value ``spec`` names: ``"module:NAME"``, a module attribute;
    ``"module:Name.parameter"``, the default of a dataclass's field or of a function's
    keyword.

    Parameters
    ----------
    spec : str
        Where the value is defined, e.g. ``"rubdiag.simulation._run:Run.duration_s"``.

    Returns
    -------
    object
        The value.
    """
    module, _, path = spec.partition(":")
    owner, _, name = path.partition(".")
    value = getattr(importlib.import_module(module), owner)
    if not name:
        return value
    if dataclasses.is_dataclass(value):
        return value.__dataclass_fields__[name].default
    return inspect.signature(value).parameters[name].default


def _shown(value, separator: str = " ") -> str:
    """A value as the help shows it: a number in its short form; a list (a default of
    several values) space-separated, as it is typed; the keys of a dict or the items of a
    tuple (choices, names) with ``separator``."""
    if isinstance(value, list):
        return " ".join(_shown(v) for v in value)
    if isinstance(value, dict | tuple):
        return separator.join(_shown(v) for v in value)
    return f"{value:g}" if isinstance(value, float) else str(value)


class FromLibrary(argparse.Action):
    """A ``store`` option whose default (``default_of``), choices (``choices_of``: any
    iterable, e.g. a dict's keys) and help values (``shows``: placeholder -> spec) are read
    from the library on first use (module docstring). Its help is a template: ``{default}``,
    ``{choices}`` and each name of ``shows`` (a tuple or a dict's keys comma-separated).
    ``convert`` turns the library's default into the option's unit (e.g. m into mm). An
    option with choices needs a ``metavar``: argparse would otherwise read the choices to
    build the parser."""

    def __init__(self, option_strings, dest, default_of: str | None = None,
                 choices_of: str | None = None, shows: dict | None = None, convert=None,
                 help: str | None = None, **kwargs):
        self._specs = {"default": default_of, "choices": choices_of, **(shows or {})}
        self._convert = convert
        self._template = help
        self._given = {}                # what argparse set (set_defaults), by attribute
        super().__init__(option_strings, dest, **kwargs)

    def _value(self, name: str):
        if name in self._given:
            return self._given[name]
        spec = self._specs.get(name)
        if spec is None:
            return None
        value = library_value(spec)
        if name == "choices":
            value = tuple(value)
        elif name == "default" and self._convert is not None:
            value = self._convert(value)
        self._given[name] = value       # read once
        return value

    @property
    def default(self):
        return self._value("default")

    @default.setter
    def default(self, value) -> None:   # Action.__init__ sets None: the library answers
        if value is not None:
            self._given["default"] = value

    @property
    def choices(self):
        return self._value("choices")

    @choices.setter
    def choices(self, value) -> None:
        if value is not None:
            self._given["choices"] = tuple(value)

    @property
    def help(self) -> str | None:
        if self._template is None:
            return None
        values = {name: _shown(self._value(name), ", ") for name, spec in self._specs.items()
                  if spec is not None}
        return self._template.format(**values)

    @help.setter
    def help(self, value) -> None:      # Action.__init__ sets it: the template answers
        pass

    def __call__(self, parser, namespace, values, option_string=None) -> None:
        setattr(namespace, self.dest, values)
