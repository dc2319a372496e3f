"""The real things stop 40 measured among the bench's strays (tests/data/real_scans/README.md,
"The tuned-on scans' unmeasured objects, measured (stop 40)"): each is now a measured object, and
where the chain gives it a primitive, that primitive counts as the object found, not as a stray."""

import json
from typing import Any

import numpy as np
import pytest

from tests.shapes.real_scans import SCANS, bench_module, measure_module, perceived

TRUTH: dict[str, dict[str, Any]] = json.loads((SCANS / "truth.json").read_text())
BENCH = bench_module("perception")
MEASURE = measure_module()


@pytest.mark.parametrize(
    ("scan", "measured", "label"),
    [
        ("desk_fr1_tum_0", "desk_fr1_tum_0", "second monitor"),
        ("desk_fr1_tum_1", "desk_fr1_tum_1", "second monitor"),
    ],
)
def test_a_former_stray_is_the_measured_object_found_within_3_cm(
    scan: str, measured: str, label: str
) -> None:
    result = perceived(scan, 0)
    cells, _ = BENCH._objects_row(result, TRUTH[measured])
    cell = next(c for c in cells if c.startswith(f"{label} "))
    parts, error_cm = cell.removeprefix(f"{label} ").split(", ")[:2]
    assert parts == "1" and float(error_cm.removesuffix(" cm")) < 3.0, cell


@pytest.mark.parametrize("scan", ["desk_fr1_tum_0", "desk_fr1_tum_1"])
def test_the_second_monitor_is_the_first_monitors_backdrop_and_shares_no_point(scan: str) -> None:
    """The second monitor's points are those of its box within 10 cm of its face's plane; the
    first monitor's, more than 10 cm in front of it: both cuts use one plane, so no point of the
    first monitor's box above the desk belongs to both, and none within its box is lost between."""
    image = MEASURE.points_of(scan)
    support = TRUTH[scan]["support"]
    normal, offset = np.asarray(support["normal"]), support["distance_m"]
    second = MEASURE.object_mask(scan, "second monitor", image, normal, offset)
    first = MEASURE.object_mask(scan, "monitor", image, normal, offset)
    assert not np.any(second & first)
    assert np.count_nonzero(second) == TRUTH[scan]["second monitor"]["points"]
    wall, wall_offset, rms = MEASURE.plane(
        MEASURE.points_in(image, MEASURE.BACKDROPS[scan]["monitor behind"])
    )
    distance = image[second] @ wall + wall_offset
    assert rms < 0.01 and float(np.percentile(np.abs(distance), 95)) < 0.03
