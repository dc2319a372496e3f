"""``bench/perception.py`` gives the pipeline no reserved real scan unless ``--reserved`` is
given: those scans are kept for the next stop (tests/data/real_scans/README.md). No perception
is run here: loading any scan fails the test's way."""

import json
from pathlib import Path
from types import ModuleType

import pytest

from tests.shapes.real_scans import bench_module

ROOT = Path(__file__).parents[2]
TRUTH = json.loads((ROOT / "tests" / "data" / "real_scans" / "truth.json").read_text())
HELD_OUT = sorted(
    name for name, scan in TRUTH.items() if scan["held_out"] and not scan.get("reserved")
)
RESERVED = sorted(name for name, scan in TRUTH.items() if scan.get("reserved"))


class Loaded(Exception):
    """Raised instead of loading a scan."""


def _bench(monkeypatch: pytest.MonkeyPatch, truth: Path) -> ModuleType:
    """bench/perception.py reading ``truth`` (a truth.json), with every scan it lists failing to
    load."""
    bench = bench_module("perception")

    def refuse(path: Path) -> None:
        raise Loaded(Path(path).stem)

    monkeypatch.setattr(bench, "open_source", refuse)
    monkeypatch.setattr(bench, "simulated_frames", lambda count=3: [])
    monkeypatch.setattr(bench, "REAL_SCANS", truth.parent)
    monkeypatch.setattr(bench, "REAL_TRUTH", {name: name for name in json.loads(truth.read_text())})
    return bench


def test_the_bench_skips_the_reserved_scans_unless_asked(
    monkeypatch: pytest.MonkeyPatch, tmp_path: Path
) -> None:
    truth = tmp_path / "truth.json"
    truth.write_text(json.dumps({"kept": {"held_out": True, "reserved": True}}))
    bench = _bench(monkeypatch, truth)
    bench.real_scans()
    bench.real_scans(tuned_only=True)
    bench.real_scans(tuned_only=True, reserved=True)  # reserved scans are held out too
    with pytest.raises(Loaded, match="kept"):
        bench.real_scans(reserved=True)


def test_a_held_out_scan_is_left_out_when_tuning(
    monkeypatch: pytest.MonkeyPatch, tmp_path: Path
) -> None:
    """A held-out scan is run by the bench, for the lead's one run, and ``--tuned-only`` never
    loads it."""
    truth = tmp_path / "truth.json"
    truth.write_text(json.dumps({"fresh": {"held_out": True}}))
    bench = _bench(monkeypatch, truth)
    bench.real_scans(tuned_only=True)
    with pytest.raises(Loaded, match="fresh"):
        bench.real_scans()


def test_every_held_out_scan_is_listed_in_the_bench() -> None:
    """The held-out scans (stop 39's reserved RealSense frames, from stop 40) are in
    ``REAL_TRUTH``, for the lead's one run."""
    assert set(HELD_OUT) <= set(bench_module("perception").REAL_TRUTH)


@pytest.mark.parametrize("name", RESERVED)
def test_the_reserved_scans_are_not_in_the_bench(name: str) -> None:
    """Scans reserved for the next stop are not even listed, so that no run of this stop, the
    lead's ``--reserved`` one included, can give them to the pipeline."""
    bench = bench_module("perception")
    assert name not in set(bench.REAL_TRUTH) | set(bench.REAL_TRUTH.values())
    assert name not in ROOT.joinpath("bench", "perception.py").read_text()
