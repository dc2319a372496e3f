"""``bench/perception_where.py`` times functions by replacing the names their callers look up;
each of those names must still be there, or the script fails before it times anything (as it did
once ``shapes.segment`` became a package). No perception is run here."""

import importlib
import sys
from collections.abc import Iterator
from types import ModuleType

import pytest

from tests.shapes.real_scans import BENCH, bench_module


@pytest.fixture
def where(monkeypatch: pytest.MonkeyPatch) -> Iterator[ModuleType]:
    """bench/perception_where.py, loaded with bench/ importable (it imports a sibling)."""
    monkeypatch.syspath_prepend(str(BENCH))
    module = bench_module("perception_where")
    yield module
    sys.modules.pop("perception_callgrind", None)


def test_every_timed_name_is_where_its_caller_looks_it_up(where: ModuleType) -> None:
    missing = [
        f"{module}.{name}"
        for _, module, name in where.TIMED
        if not hasattr(importlib.import_module(module), name)
    ]
    assert missing == []
