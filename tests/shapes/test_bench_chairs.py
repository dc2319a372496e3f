"""``bench/perception_chairs.py`` measures what the chairs' centroids rest on (docs/perception.md,
"The chairs: a seat joined with what stands under it (stop 41, tried)")."""

import json
from types import ModuleType

import pytest

from shapes import open_source
from tests.shapes.real_scans import SCANS, bench_module

TRUTH = json.loads((SCANS / "truth.json").read_text())


@pytest.fixture(scope="module")
def chairs() -> ModuleType:
    """bench/perception_chairs.py as a module."""
    return bench_module("perception_chairs")


def test_a_chair_from_its_seat_up_lies_off_its_measured_centroid(chairs: ModuleType) -> None:
    """Without the parts under the seat (from 33 cm up), the lab's left chair lies 10.2 cm from
    its measured centroid: no cluster of its seat and back can be within 3 cm of it."""
    rows = chairs.truth_rows("lab_floor_rtabmap", "lab_floor_rtabmap", TRUTH)
    left = next(row for row in rows if row.startswith("lab_floor_rtabmap / left chair:"))
    assert "from 0 cm: 100 % 0.0 cm" in left
    assert "from 33 cm: 80 % 10.2 cm" in left


def test_the_chair_s_back_lies_outside_the_floor_s_box(chairs: ModuleType) -> None:
    """On ``chair_boxes_kinect`` (seed 0), 722 of the chair's free voxels in the height band lie
    outside the box of the floor's main piece, and what is left lies 6.4 cm off."""
    frame = next(open_source(SCANS / "chair_boxes_kinect.npz"))
    centre = {"chair": TRUTH["chair_boxes_kinect"]["chair"]["centre"]}
    (row,) = chairs.voxel_rows("chair_boxes_kinect", "chair_boxes_kinect", frame, 0, centre)
    assert "free in the band outside the floor's box 722" in row
    assert row.endswith("free 0.5 cm; free, in the box 6.4 cm")
