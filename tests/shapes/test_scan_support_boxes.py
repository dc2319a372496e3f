"""The supports measured over the whole visible support (tests/data/real_scans/README.md,
stop 37) keep to their rule's letter where it can be checked without eyes: several boxes, each
on valid depth and 5 pixels clear of every pixel with no depth."""

import numpy as np
import pytest
from scipy.ndimage import binary_dilation

from tests.shapes.real_scans import SCANS, measure_module

SPREAD_OVER_THE_SUPPORT = (
    "desk_tum",
    "office_kinect",
    "people_floor_kinect",
    "box_floor_kinect",
    "chair_boxes_kinect",
    "ycb_desk_xtion",
    "ycb_chair_tablet_xtion",
    "ycb_chessboard_table_xtion",
    "blue_mug_table_realsense",
    "cracker_box_table_realsense",
    "tin_table_realsense",
    "tote_whisk_sr300_0",
    "tote_whisk_sr300_1",
    "pepper_can_table_realsense",
)
"""The scans whose support the stop-37 rule concerns (one box's halves disagree by more than
1 degree or 1 cm, by bench/support_truth.py), and every scan measured since (stop 38 on)."""
CLEAR_PX = 5
MIN_BOX_PX = (8, 20)


MEASURE = measure_module()


@pytest.mark.parametrize("name", SPREAD_OVER_THE_SUPPORT)
def test_the_support_is_several_boxes_clear_of_missing_depth(name: str) -> None:
    boxes = MEASURE.REGIONS[name][0]
    assert isinstance(boxes[0], tuple) and 2 <= len(boxes) <= 4, boxes  # one a quarter at most
    missing = np.load(SCANS / f"{name}.npz")["depth"] == 0
    near_missing = binary_dilation(missing, structure=np.ones((2 * CLEAR_PX + 1,) * 2, bool))
    for r0, r1, c0, c1 in boxes:
        assert r1 - r0 >= MIN_BOX_PX[0] and c1 - c0 >= MIN_BOX_PX[1], (r0, r1, c0, c1)
        assert not near_missing[r0:r1, c0:c1].any(), (r0, r1, c0, c1)
