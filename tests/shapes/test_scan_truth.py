"""The real scans' ground truth is what measure.py computes from the scans, held-out ones marked."""

import json
from pathlib import Path

import numpy as np
import pytest

from shapes import open_source
from tests.shapes.real_scans import SCANS, measure_module

TRUTH = json.loads((SCANS / "truth.json").read_text())
TUNED_ON_SINCE_STOP_39 = {"ycb_desk_xtion", "ycb_chair_tablet_xtion", "ycb_chessboard_table_xtion"}
"""Reserved at stop 38, run once at stop 39 by the lead after the merge, then tuned on
(README.md)."""


@pytest.mark.parametrize("name", sorted(TRUTH))
def test_truth_json_is_what_measure_py_computes(name: str) -> None:
    # The JSON round trip turns the measured floats and tuples into what truth.json holds.
    assert json.loads(json.dumps(measure_module().measure(name))) == TRUTH[name]


TUNED_ON_SINCE_STOP_41 = {
    "blue_mug_table_realsense",
    "cracker_box_table_realsense",
    "tin_table_realsense",
}
"""Reserved at stop 39, held out at stop 40, run once by the lead after that stop's merge, then
tuned on (README.md)."""


HELD_OUT_AT_STOP_41 = {"tote_whisk_sr300_0", "tote_whisk_sr300_1", "pepper_can_table_realsense"}
"""Reserved at stop 40, held out at stop 41 for the lead's one run after the merge (README.md)."""


RESERVED_AT_STOP_41 = {"mug_desk_azure_kinect", "mug_apple_table_d435", "bottles_cloth_d435"}
"""Found and measured at stop 41, reserved for the next stop, never given to the pipeline
(README.md)."""


def test_the_held_out_scans_are_marked() -> None:
    held_out = {name for name, scan in TRUTH.items() if scan["held_out"]}
    measure = measure_module()
    assert held_out == measure.HELD_OUT == HELD_OUT_AT_STOP_41 | measure.RESERVED
    assert not held_out & (TUNED_ON_SINCE_STOP_39 | TUNED_ON_SINCE_STOP_41)


def test_the_reserved_scans_are_held_out_and_marked() -> None:
    """Reserved scans are kept for a later stop: held out, and marked so the bench skips them."""
    reserved = {name for name, scan in TRUTH.items() if scan.get("reserved")}
    measure = measure_module()
    assert reserved == measure.RESERVED == RESERVED_AT_STOP_41 == measure.RESERVED_AT_STOP_41
    assert not reserved & HELD_OUT_AT_STOP_41
    assert all(TRUTH[name]["held_out"] for name in reserved)
    assert all(scan.get("reserved", True) is True for scan in TRUTH.values())


def test_the_tum_frame_loads_with_its_depths_unchanged() -> None:
    """0.2 mm units (TUM's 5000 a metre) and the Freiburg 3 intrinsics, read back by shapes."""
    data = np.load(SCANS / "desk_tum.npz")
    frame = next(open_source(SCANS / "desk_tum.npz"))
    assert frame.pixels is not None
    depth = data["depth"].reshape(-1)[frame.pixels] / 5000.0
    np.testing.assert_allclose(frame.points[:, 2], depth, atol=1e-6)
    u = frame.pixels % 640
    np.testing.assert_allclose(frame.points[:, 0], (u - 320.1) / 535.4 * depth, atol=1e-6)


@pytest.mark.parametrize("path", sorted(SCANS.glob("*.npz")), ids=lambda p: p.stem)
def test_a_scan_with_colour_has_colours_and_one_without_has_none(path: Path) -> None:
    """PCL's pairwise captures carry no colour: their frames have none, where an all-black image
    once stood in and read as black things (a colour seam saw every part alike)."""
    data = np.load(path)
    frame = next(open_source(path))
    if "rgb" in data.files:
        assert data["rgb"].any(), "an all-black image is no colour: leave out 'rgb'"
        assert frame.colours is not None
    else:
        assert frame.colours is None
