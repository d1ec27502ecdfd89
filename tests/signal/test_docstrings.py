"""The docstring examples of the signal layer run and give what they print."""

from __future__ import annotations

import doctest
import importlib

import pytest


@pytest.mark.parametrize(
    "module",
    ["rubdiag.signal._spectrum", "rubdiag.signal._table", "rubdiag.signal._transformer"],
)
def test_examples(module):
    result = doctest.testmod(importlib.import_module(module))
    assert result.attempted > 0
    assert result.failed == 0

