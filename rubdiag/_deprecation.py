"""Old public names kept for one release, each warning where its replacement lives.

A package lists its renamed or moved names as ``{old: "package.new_name"}`` and makes its
module ``__getattr__`` from :func:`moved_names`. The first access warns
:class:`DeprecationWarning` naming the replacement and the release that removes the old name;
the value is the replacement itself, so old code keeps working unchanged until then.
``CHANGELOG.md`` lists every entry.
"""

from __future__ import annotations

import importlib
import warnings

#: the release that removes the names deprecated in this one
REMOVED_IN = "0.3"


def moved_names(package: str, moved: dict[str, str], fallback=None):
    """A module ``__getattr__`` for ``package`` that resolves the deprecated names ``moved``.

    Parameters
    ----------
    package : str
        The package's dotted name (for the error of an unknown name).
    moved : dict of str to str or (str, str)
        Old name -> the dotted path of its replacement (``"rubdiag.signal.signal_features"``),
        or ``(path, advice)`` when the old name did several jobs: ``path`` is what the old
        name still does until its removal, ``advice`` which names replace it.
    fallback : callable, optional
        The package's own ``__getattr__`` for every other name (lazy imports).

    Returns
    -------
    callable
        ``__getattr__(name)``.
    """

    def __getattr__(name: str):
        if name in moved:
            target, advice = (moved[name] if isinstance(moved[name], tuple)
                              else (moved[name], f"use {moved[name]}"))
            module, attribute = target.rsplit(".", 1)
            warnings.warn(f"{package}.{name} is deprecated and will be removed in rubdiag "
                          f"{REMOVED_IN}: {advice}", DeprecationWarning, stacklevel=2)
            return getattr(importlib.import_module(module), attribute)
        if fallback is not None:
            return fallback(name)
        raise AttributeError(f"module {package!r} has no attribute {name!r}")

    return __getattr__
