"""Every vendored real scan loads, and its ground truth agrees with the points ``open_source``
gives for it: the support plane lies on the points of its pixel boxes, and each object has points
above that plane in its box, where its centre is. Data integrity only: no perception is run."""

import json
from typing import Any

import numpy as np
import pytest

from shapes import open_source
from tests.shapes.real_scans import SCANS, measure_module

TRUTH: dict[str, dict[str, Any]] = json.loads((SCANS / "truth.json").read_text())
SHARED_TRUTH = {
    "laptop_box_kinect_1": "laptop_box_kinect_0",
    "laptop_box_kinect_2": "laptop_box_kinect_0",
}
"""Later frames of a static scene, which share the ground truth of its first frame."""
MAX_FILE_BYTES = 1_000_000
MIN_OBJECT_POINTS = 200
SCENE_SHAPE = (480, 640)


MEASURE = measure_module()


def _image(name: str) -> np.ndarray:
    """The scan's points as ``open_source`` loads them, on its pixel grid (NaN where none)."""
    frame = next(open_source(SCANS / f"{name}.npz"))
    assert frame.image_shape == SCENE_SHAPE and frame.pixels is not None
    image = np.full((SCENE_SHAPE[0] * SCENE_SHAPE[1], 3), np.nan)
    image[frame.pixels] = frame.points
    return image.reshape(*SCENE_SHAPE, 3)


def _in_boxes(image: np.ndarray, region: tuple[Any, ...]) -> np.ndarray:
    """The finite points of the union of the boxes: a pixel in two boxes counts once."""
    boxes = region if isinstance(region[0], tuple) else (region,)
    inside = np.zeros(image.shape[:2], dtype=bool)
    for r0, r1, c0, c1 in boxes:
        inside[r0:r1, c0:c1] = True
    pts = image[inside]
    return pts[np.isfinite(pts).all(axis=1)]


def _plane(pts: np.ndarray) -> tuple[np.ndarray, float]:
    """The least-squares plane through the points (SVD): unit normal towards the camera, offset."""
    centre = pts.mean(axis=0)
    normal = np.linalg.svd(pts - centre, full_matrices=False)[2][2]
    normal = normal if normal @ centre < 0 else -normal
    return normal, float(-normal @ centre)


def test_every_vendored_scan_has_ground_truth() -> None:
    scans = {p.stem for p in SCANS.glob("*.npz")}
    assert scans == set(TRUTH) | set(SHARED_TRUTH)
    assert set(TRUTH) == set(MEASURE.REGIONS)


@pytest.mark.parametrize("name", sorted(TRUTH))
def test_each_scan_is_a_small_organised_depth_image(name: str) -> None:
    path = SCANS / f"{name}.npz"
    assert path.stat().st_size < MAX_FILE_BYTES
    data = np.load(path)
    assert data["depth"].dtype == np.uint16 and data["depth"].shape == SCENE_SHAPE
    if "rgb" in data.files:  # PCL's pairwise captures have no colour
        assert data["rgb"].dtype == np.uint8 and data["rgb"].shape == (*SCENE_SHAPE, 3)
    # open_source gives back the pinhole un-projection of each valid pixel.
    z = data["depth"].astype(np.float64) * float(data["depth_scale"])
    z[z == 0] = np.nan  # no return
    v, u = np.mgrid[0 : SCENE_SHAPE[0], 0 : SCENE_SHAPE[1]]
    expected = np.dstack(
        (
            (u - float(data["cx"])) / float(data["fx"]) * z,
            (v - float(data["cy"])) / float(data["fy"]) * z,
            z,
        )
    )
    np.testing.assert_allclose(_image(name), expected, atol=1e-6)


@pytest.mark.parametrize("name", sorted(TRUTH))
def test_the_support_plane_lies_on_the_points_of_its_boxes(name: str) -> None:
    support = TRUTH[name]["support"]
    normal, distance = np.asarray(support["normal"]), support["distance_m"]
    assert abs(np.linalg.norm(normal) - 1.0) < 1e-3 and distance > 0  # towards the camera
    bare = _in_boxes(_image(name), MEASURE.REGIONS[name][0])
    assert len(bare) == support["points"]
    residual = bare @ normal + distance
    rms = float(np.sqrt(np.mean(residual**2)))
    # truth.json rounds the normal to 1e-4, which moves points 2 m away by up to 0.3 mm.
    assert abs(rms - support["rms_m"]) < 5e-4, (rms, support["rms_m"])
    assert abs(float(np.median(residual))) < 5e-3 and rms < 0.015


@pytest.mark.parametrize(
    ("name", "label"),
    [
        (name, label)
        for name, truth in sorted(TRUTH.items())
        for label in truth
        if label not in ("support", "held_out", "reserved")
    ],
)
def test_each_object_stands_on_the_support_where_its_box_is(name: str, label: str) -> None:
    truth, support = TRUTH[name][label], TRUTH[name]["support"]
    normal, distance = np.asarray(support["normal"]), support["distance_m"]
    region = MEASURE.REGIONS[name][1][label][0]
    image = _image(name)
    pts = _in_boxes(image, region)
    height = pts @ normal + distance
    max_height = MEASURE.MAX_HEIGHT_M.get(name, 0.40)
    # measure.object_mask re-implemented here, on open_source's points, to check it.
    keep = (height > 0.015) & (height < max_height)
    keep &= pts[:, 2] < MEASURE.NEARER_THAN_M.get((name, label), np.inf)
    if (name, label) in MEASURE.IN_FRONT_OF:
        backdrop, in_front_m = MEASURE.IN_FRONT_OF[name, label]
        wall, wall_distance = _plane(_in_boxes(image, MEASURE.BACKDROPS[name][backdrop]))
        keep &= pts @ wall + wall_distance > in_front_m
    if (name, label) in MEASURE.ON_BACKDROP:
        backdrop, within_m = MEASURE.ON_BACKDROP[name, label]
        wall, wall_distance = _plane(_in_boxes(image, MEASURE.BACKDROPS[name][backdrop]))
        keep &= np.abs(pts @ wall + wall_distance) <= within_m
    above = pts[keep]
    assert len(above) >= MIN_OBJECT_POINTS
    # The rounded normal moves points by up to 0.3 mm: those that near a height cut may fall
    # either side of it (many, on a flat object a few cm tall).
    at_cuts = (np.abs(height - 0.015) < 5e-4) | (np.abs(height - max_height) < 5e-4)
    assert abs(len(above) - truth["points"]) <= 0.01 * truth["points"] + np.count_nonzero(at_cuts)
    assert float(np.percentile(height[keep], 99)) == pytest.approx(truth["height_m"], abs=2e-3)
    centre = np.asarray(truth["centre"])
    centre_height = float(centre @ normal + distance)
    assert 0.0 < centre_height < truth["height_m"]
    # The centre is seen inside the object's box (an axis centre, behind the visible surface,
    # within a few pixels of it); an object seen in several boxes around something in front of
    # it (a box behind a mallet's handle) may have it in the gap, inside the boxes' bounds.
    data = np.load(SCANS / f"{name}.npz")
    col = float(data["fx"]) * centre[0] / centre[2] + float(data["cx"])
    row = float(data["fy"]) * centre[1] / centre[2] + float(data["cy"])
    boxes = region if isinstance(region[0], tuple) else (region,)
    rows_cols = np.asarray(boxes)
    bounds = (
        rows_cols[:, 0].min(),
        rows_cols[:, 1].max(),
        rows_cols[:, 2].min(),
        rows_cols[:, 3].max(),
    )
    boxes = (*boxes, tuple(int(v) for v in bounds))
    margin = 10 if "radius_m" in truth else 0
    assert any(
        r0 - margin <= row < r1 + margin and c0 - margin <= col < c1 + margin
        for r0, r1, c0, c1 in boxes
    ), (row, col, boxes)
    if "radius_m" in truth:  # an axis centre: half the top height, its points a radius off
        assert abs(centre_height - truth["height_m"] / 2) < 2e-3
        across = above - centre
        across -= np.outer(across @ normal, normal)
        off_axis = np.linalg.norm(across, axis=1)
        assert abs(float(np.median(off_axis)) - truth["radius_m"]) < 0.25 * truth["radius_m"]
    else:  # the centroid of the visible points above the support
        np.testing.assert_allclose(above.mean(axis=0), centre, atol=0.01)


POSECNN_FRAMES = ("ycb_desk_xtion", "ycb_chair_tablet_xtion", "ycb_chessboard_table_xtion")
"""PoseCNN's demo frames (an Asus Xtion), reserved at stop 38 (README.md)."""
POSECNN_CAMERA = {"fx": 1066.778, "fy": 1067.487, "cx": 312.9869, "cy": 241.3109}
"""``tools/demo.py``'s intrinsic matrix, which reads the depth PNGs at 10000 units a metre."""


@pytest.mark.parametrize("name", POSECNN_FRAMES)
def test_the_xtion_frames_keep_their_depths_and_camera(name: str) -> None:
    """Depths stored unchanged (whole millimetres in 0.1 mm units) with demo.py's camera, and
    loaded by ``open_source`` at that scale."""
    data = np.load(SCANS / f"{name}.npz")
    assert float(data["depth_scale"]) == 1e-4
    assert {key: float(data[key]) for key in POSECNN_CAMERA} == POSECNN_CAMERA
    depth = data["depth"]
    assert not (depth % 10).any() and 0.6 < np.median(depth[depth > 0]) / 10_000 < 1.5
    frame = next(open_source(SCANS / f"{name}.npz"))
    assert frame.pixels is not None
    np.testing.assert_allclose(
        frame.points[:, 2], depth.reshape(-1)[frame.pixels] / 10_000, atol=1e-6
    )


SHARED_POINTS = {
    ("laptop_box_kinect_0", "laptop", "box"): 337,
    ("desk_fr1_tum_0", "cup", "keyboard"): 1,
    ("desk_fr1_tum_1", "milk carton", "pen holder"): 441,
    ("desk_fr2_tum_1", "mug", "telephone"): 19,
    ("mallet_box_carpet_realsense", "box", "mallet"): 1248,  # the box's right one, the head's
}
"""Points that two objects' boxes both hold, in boxes measured before stop 38 (an object's box
around a skewed neighbour's corner). No other pair may share a point."""


@pytest.mark.parametrize("name", sorted(n for n in TRUTH if n not in MEASURE.RESERVED))
def test_no_point_counts_for_two_objects_but_the_listed_ones(name: str) -> None:
    """Each point above the support belongs to one object's box at most: an object measured beside
    another (the tray's devices, the tape dispenser and the power adapter) takes none of its
    points. The reserved scans stay unopened here, kept for a later stop."""
    truth, image = TRUTH[name], _image(name)
    normal = np.asarray(truth["support"]["normal"])
    owned = {
        label: MEASURE.object_mask(name, label, image, normal, truth["support"]["distance_m"])
        for label in MEASURE.REGIONS[name][1]
    }
    labels = list(owned)
    shared = {
        (name, a, b): int(np.count_nonzero(owned[a] & owned[b]))
        for i, a in enumerate(labels)
        for b in labels[i + 1 :]
        if np.any(owned[a] & owned[b])
    }
    expected = {key: n for key, n in SHARED_POINTS.items() if key[0] == name}
    assert shared.keys() == expected.keys(), shared
    for key, n in expected.items():  # the rounded normal moves a few points across the cuts
        assert abs(shared[key] - n) <= 0.05 * n + 2, (key, shared[key])


PARTITION_CLEARANCE_M = 0.02
"""One depth step of the Kinect 2.65-2.85 m away, where desk_tum's partition stands behind the
far objects (README.md, stop 42)."""


def test_no_desk_tum_object_holds_points_of_the_partition() -> None:
    """Every desk_tum object's points lie more than a depth step in front of the partition's
    plane, fitted here through its bare boxes: the wood seen past the bottles, the jar, the cup
    and the bag is not theirs."""
    image = _image("desk_tum")
    wall, wall_distance = _plane(_in_boxes(image, MEASURE.BACKDROPS["desk_tum"]["partition"]))
    support = TRUTH["desk_tum"]["support"]
    normal = np.asarray(support["normal"])
    near = {}
    for label in MEASURE.REGIONS["desk_tum"][1]:
        own = MEASURE.object_mask("desk_tum", label, image, normal, support["distance_m"])
        near[label] = int(
            np.count_nonzero(image[own] @ wall + wall_distance <= PARTITION_CLEARANCE_M)
        )
    assert not any(near.values()), near
    assert MEASURE.IN_FRONT_OF[("desk_tum", "brown bottle")] == ("partition", PARTITION_CLEARANCE_M)
