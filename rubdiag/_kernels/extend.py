"""A time-loop kernel whose element dispatch also knows kinds defined outside rubdiag.

The kernel runs each kind's law on its elements in
:func:`rubdiag._kernels.elements.element_laws` (and their books in ``element_books``),
compiled statically and cached on disk. A kind that is not (yet) part of rubdiag — a
prototype, or the kinds the tests define to prove the seam — has its law in a module of its
own (``KIND``, ``N_LOCAL``, ``law``, ``books``; see :mod:`rubdiag._kernels.elements`).
:func:`kernel_with` compiles, once per process and without the disk cache, an
``element_laws`` and ``element_books`` that also run those kinds, and the functions that
call them (the element solve, the state at rest, the controller) bound to them: the same
source, other globals. Built-in runs never use it.
"""

from __future__ import annotations

import functools
import types
from typing import NamedTuple

import numba

from rubdiag._kernels import element_solve, newmark
from rubdiag._kernels import elements as seam

__all__ = ["Kernel", "kernel_with"]


class Kernel(NamedTuple):
    """The controller (:func:`~rubdiag._kernels.newmark.newmark_contact`) and the state at
    rest (:func:`~rubdiag._kernels.elements.at_rest`) of one element dispatch."""

    newmark_contact: object
    at_rest: object


BUILTIN = Kernel(newmark.newmark_contact, seam.at_rest)


def _with_laws(kind, builtin):
    """``element_laws`` that runs ``builtin`` and then ``kind``'s law on its elements."""
    each = seam.laws_of(kind, cache=False)

    def element_laws(elements, local_work, local_state, parameters, element_state, track,
                     trial, progress, jacobian):
        builtin(elements, local_work, local_state, parameters, element_state, track, trial,
                progress, jacobian)
        each(elements, local_work, local_state, parameters, element_state, track, trial,
             progress, jacobian)

    return numba.njit(error_model="numpy")(element_laws)


def _with_books(kind, builtin):
    """``element_books`` that runs ``builtin`` and then ``kind``'s books on its elements."""
    each = seam.books_of(kind, cache=False)

    def element_books(elements, parameters, element_state, track, trial, progress):
        builtin(elements, parameters, element_state, track, trial, progress)
        each(elements, parameters, element_state, track, trial, progress)

    return numba.njit(error_model="numpy")(element_books)


def _rebound(func, swaps: dict):
    """``func`` compiled again (no disk cache) with the globals in ``swaps`` (old compiled
    function -> new) replaced."""
    py = getattr(func, "py_func", func)     # NUMBA_DISABLE_JIT: the function itself
    scope = dict(py.__globals__)
    for name in py.__code__.co_names:
        if any(scope.get(name) is old for old in swaps):
            scope[name] = next(new for old, new in swaps.items() if scope[name] is old)
    clone = types.FunctionType(py.__code__, scope, py.__name__, py.__defaults__,
                               py.__closure__)
    options = {k: v for k, v in getattr(func, "targetoptions", {}).items()
               if k not in ("cache", "nopython")}
    return numba.njit(**options)(clone)


@functools.cache
def kernel_with(kinds: tuple = ()) -> Kernel:
    """The kernel whose dispatch also knows ``kinds`` (kernel modules with ``KIND``,
    ``N_LOCAL``, ``law``); the built-in one for none."""
    if not kinds:
        return BUILTIN
    taken = set(seam.KINDS)
    for module in kinds:
        if module.KIND in taken:
            raise ValueError(f"{module.__name__}.KIND = {module.KIND} is out of range "
                             f"(allowed: a code no other kind uses, not in {sorted(taken)})")
        taken.add(module.KIND)
    laws, books = seam.element_laws, seam.element_books
    for module in kinds:
        laws = _with_laws(module, laws)
        books = _with_books(module, books)
    swaps = {seam.element_laws: laws, seam.element_books: books}
    solve = _rebound(element_solve.solve_elements, swaps)
    at_rest = _rebound(seam.at_rest, swaps)
    controller = _rebound(newmark.newmark_contact, {element_solve.solve_elements: solve})
    return Kernel(controller, at_rest)
