"""Narrow interfaces in the simulator (issue 25): no function of rubdiag._kernels or
rubdiag.simulate takes more than :data:`LIMIT` parameters unless it is allowed below, with
the measured reason narrowing it would cost. Same-typed arrays passed by position are what a
long signature invites swapping: a swapped pair still compiles and computes wrong results."""

from __future__ import annotations

import ast
from pathlib import Path

PACKAGE = Path(__file__).resolve().parents[1] / "rubdiag"
LIMIT = 15
#: function (module path: name) -> the measured reason it keeps more than LIMIT parameters
#: (at most two)
ALLOWED: dict[str, str] = {}


def parameters(node: ast.FunctionDef) -> int:
    a = node.args
    return (len(a.posonlyargs) + len(a.args) + len(a.kwonlyargs) + (a.vararg is not None)
            + (a.kwarg is not None))


def wide_functions() -> dict[str, int]:
    wide = {}
    for layer in ("kernels", "simulate"):
        for path in sorted((PACKAGE / layer).rglob("*.py")):
            for node in ast.walk(ast.parse(path.read_text(), str(path))):
                if isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef):
                    n = parameters(node)
                    if n > LIMIT:
                        wide[f"{path.relative_to(PACKAGE.parent)}: {node.name}"] = n
    return wide


def test_no_function_takes_more_than_fifteen_parameters_unless_allowed():
    wide = wide_functions()
    assert set(wide) <= set(ALLOWED), {k: v for k, v in wide.items() if k not in ALLOWED}
    assert len(ALLOWED) <= 2
    assert not set(ALLOWED) - set(wide), "an allowed function got narrower: drop it"


def test_the_count_sees_every_kind_of_parameter():
    """The counter itself: positional, keyword-only, *args and **kwargs all count."""
    node = ast.parse("def f(a, /, b, *c, d, e=1, **f): pass").body[0]
    assert parameters(node) == 6
