"""A seam cut whose parts all stay low is one thing lying on the support (shapes.lying_cut, in
shapes.segment.splitting; docs/perception.md, "One lying object is not three standing ones
(stop 39, late)")."""

import json
from pathlib import Path

import numpy as np
import pytest

from shapes.lying_cut import lies_low, part_heights
from tests.shapes.real_scans import perceived

SCANS = Path(__file__).parents[1] / "data" / "real_scans"
TRUTH = json.loads((SCANS / "truth.json").read_text())


def test_parts_that_all_stay_low_lie_low() -> None:
    heights = np.array([0.01, 0.05, 0.012, 0.04, 0.02, 0.055])
    assert lies_low(heights, np.array([0, 0, 1, 1, 2, 2]), 0.075)


def test_a_part_standing_taller_does_not() -> None:
    """A can 11 cm tall beside a lying box: objects side by side."""
    assert not lies_low(np.array([0.01, 0.05, 0.01, 0.11]), np.array([0, 0, 1, 1]), 0.075)


def test_one_stray_voxel_above_does_not_lift_a_part() -> None:
    heights = np.r_[np.linspace(0.01, 0.05, 99), 0.3, np.linspace(0.01, 0.05, 100)]
    parts = np.repeat([0, 1], 100)
    assert part_heights(heights, parts)[0] < 0.06
    assert lies_low(heights, parts, 0.075)


def test_no_cut_is_not_refused() -> None:
    assert not lies_low(np.array([0.01, 0.02]), np.zeros(2, dtype=np.int64), 0.075)


@pytest.mark.parametrize(
    ("heights", "parts", "max_height_m", "message"),
    [
        (np.zeros(3), np.array([0, 1]), 0.075, "one label per height (3), got 2"),
        (np.zeros(2), np.array([0, 1]), 0.0, "max_height_m must be positive, got 0.0"),
        (np.zeros(2), np.array([0, 1]), float("nan"), "max_height_m must be positive, got nan"),
    ],
)
def test_bad_input_is_refused(
    heights: np.ndarray, parts: np.ndarray, max_height_m: float, message: str
) -> None:
    with pytest.raises(ValueError, match=message.replace("(", r"\(").replace(")", r"\)")):
        lies_low(heights, parts, max_height_m)


@pytest.mark.parametrize("seed", [0, 1])
def test_the_chessboard_tables_lying_drill_is_one_primitive(seed: int) -> None:
    """The drill lies on its side on the chessboard table; the splitter cut its cluster into
    three parts (tallest 4.2-5.7 cm over the table), each reaching down to it, and the cut was
    taken: three primitives lay within 15 cm of the drill's centre. Now one, within 3 cm."""
    result = perceived("ycb_chessboard_table_xtion", seed)
    centre = np.asarray(TRUTH["ycb_chessboard_table_xtion"]["drill"]["centre"])
    back = np.linalg.inv(result.world_from_sensor)
    seen = [back[:3, :3] @ c + back[:3, 3] for c in result.centroids]
    near = sorted(g for g in (float(np.linalg.norm(c - centre)) for c in seen) if g < 0.15)
    assert len(near) == 1, near
    assert near[0] < 0.03, near
