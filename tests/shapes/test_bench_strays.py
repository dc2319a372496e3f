"""``bench/perception_strays.py`` loads a held-out scan only when it is named with
``--held-out-too`` (for after the lead's one run of it). No perception is run here."""

import json
import sys
from types import ModuleType

import pytest

from tests.shapes.real_scans import SCANS, bench_module

TRUTH = json.loads((SCANS / "truth.json").read_text())
HELD_OUT = sorted(
    name for name, scan in TRUTH.items() if scan.get("held_out") and not scan.get("reserved")
)
RESERVED = sorted(name for name, scan in TRUTH.items() if scan.get("reserved"))


def _loaded_by_main(monkeypatch: pytest.MonkeyPatch, argv: list[str]) -> list[str]:
    """The scans ``perception_strays.py``'s main hands to ``strays_of`` with ``argv``."""
    strays: ModuleType = bench_module("perception_strays")
    loaded: list[str] = []

    def record(scan: str, measured: str, seeds: int, params: object) -> list[object]:
        loaded.append(scan)
        return []

    monkeypatch.setattr(strays, "strays_of", record)
    monkeypatch.setattr(sys, "argv", ["perception_strays.py", "--seeds", "1", *argv])
    strays.main()
    return loaded


def test_no_held_out_scan_is_loaded_unless_named(monkeypatch: pytest.MonkeyPatch) -> None:
    assert HELD_OUT, "the test needs a held-out scan in truth.json"
    loaded = _loaded_by_main(monkeypatch, [])
    assert loaded and not set(loaded) & set(HELD_OUT + RESERVED)
    named = _loaded_by_main(monkeypatch, ["--held-out-too", HELD_OUT[-1]])
    assert set(named) - set(loaded) == {HELD_OUT[-1]}


def test_a_reserved_scan_named_is_refused(monkeypatch: pytest.MonkeyPatch) -> None:
    assert RESERVED, "the test needs a reserved scan in truth.json"
    with pytest.raises(ValueError, match="is not a held-out scan the bench lists"):
        _loaded_by_main(monkeypatch, ["--held-out-too", RESERVED[0]])
