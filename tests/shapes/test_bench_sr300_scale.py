"""``bench/perception_sr300_scale.py``: the two SR300 tote frames measure the same floor marks
10-18 % apart (docs/perception.md, "The held-out scans of stop 41, run once, diagnosed")."""

from types import ModuleType

import pytest

from tests.shapes.real_scans import bench_module


@pytest.fixture(scope="module")
def scale() -> ModuleType:
    """bench/perception_sr300_scale.py as a module."""
    return bench_module("perception_sr300_scale")


def test_both_ways_of_placing_the_marks_agree(scale: ModuleType) -> None:
    for scan in scale.MARKS:
        on_floor = scale.spans_cm(scan, on_floor=True)
        from_depth = scale.spans_cm(scan, on_floor=False)
        assert on_floor.keys() == from_depth.keys()
        for name, cm in on_floor.items():
            assert cm == pytest.approx(from_depth[name], abs=0.6), name


def test_the_first_camera_measures_every_span_longer(scale: ModuleType) -> None:
    first, second = (scale.spans_cm(scan, on_floor=True) for scan in scale.MARKS)
    ratios = [first[name] / second[name] for name in first]
    assert all(1.10 <= r <= 1.18 for r in ratios), ratios
