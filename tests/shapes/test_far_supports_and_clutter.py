"""Far supports, clutter and quantised depth on the real scans tuned on for them (desk_tum,
office_kinect; tests/data/real_scans/README.md). Expected values measured by hand
(tests/data/real_scans/measure.py), compared in the sensor's optical frame."""

import functools
import json
from pathlib import Path

import numpy as np
import pytest

from shapes import FrameResult, Perception, PerceptionParams, ShapeKind, open_source
from shapes.artefacts import depth_noise_1m
from shapes.segment import SegmentationParams, depth_cut_m

SCANS = Path(__file__).parents[1] / "data" / "real_scans"
TRUTH = json.loads((SCANS / "truth.json").read_text())


@functools.cache
def _without_pose(name: str) -> FrameResult:
    frame = next(open_source(SCANS / f"{name}.npz"))
    return Perception(PerceptionParams(gravity_from_scene=True), seed=0).process(frame)


def _support_error(result: FrameResult, name: str) -> tuple[float, float, float]:
    """The found support's angle (deg), its height error at the camera (m), and its largest
    height error where the measured objects stand (m; each object's centre dropped onto the
    measured plane), against the measured support."""
    assert result.support is not None, result.reason
    truth = TRUTH[name]["support"]
    normal, distance = np.asarray(truth["normal"]), truth["distance_m"]
    up = result.world_from_sensor[:3, :3].T @ np.asarray(result.support.normal)
    angle = float(np.degrees(np.arccos(np.clip(up @ normal, -1.0, 1.0))))
    height = float(result.world_from_sensor[:3, 3] @ np.asarray(result.support.normal))
    height += result.support.offset
    centres = [
        np.asarray(v["centre"])
        for v in TRUTH[name].values()
        if isinstance(v, dict) and "centre" in v
    ]
    at_objects = max(
        abs(float(up @ (c - (c @ normal + distance) * normal) + height)) for c in centres
    )
    return angle, height - distance, at_objects


# Each far support's measured plane fixes its height where the objects stand better than at the
# camera, 2-4 m from the support seen: bench/support_truth.py finds the planes through all but one
# of desk_tum's boxes of bare desk up to 8.5 cm apart at the camera, 4.3 cm at its objects
# (tests/data/real_scans/README.md, stop 37). The coarse bound at the camera tells the support
# from the surfaces nearest it (the office's desk 73 cm higher, the TUM desk's floor 1 m lower).


def test_a_floor_beyond_three_metres_is_the_support_of_the_office() -> None:
    angle, at_camera, at_objects = _support_error(_without_pose("office_kinect"), "office_kinect")
    assert angle < 5.0 and abs(at_camera) < 0.05 and at_objects < 0.02, (
        angle,
        at_camera,
        at_objects,
    )


def test_the_desk_two_metres_away_is_found_within_two_centimetres_at_its_objects() -> None:
    angle, at_camera, at_objects = _support_error(_without_pose("desk_tum"), "desk_tum")
    assert angle < 5.0 and abs(at_camera) < 0.05 and at_objects < 0.02, (
        angle,
        at_camera,
        at_objects,
    )


@pytest.mark.xfail(
    strict=True,
    reason="the supports measured over the whole visible support (stop 37) lie 2.3 cm (office) "
    "and 3.1 cm (desk_tum) from the found ones at the camera; the issue's 2 cm there is not met",
)
@pytest.mark.parametrize("name", ["office_kinect", "desk_tum"])
def test_the_far_support_is_found_within_two_centimetres_at_the_camera(name: str) -> None:
    angle, at_camera, _ = _support_error(_without_pose(name), name)
    assert angle < 5.0 and abs(at_camera) < 0.02, (angle, at_camera)


def test_the_mug_on_the_far_desk_is_a_cylinder() -> None:
    result = _without_pose("desk_tum")
    back = np.linalg.inv(result.world_from_sensor)
    mug = np.asarray(TRUTH["desk_tum"]["mug"]["centre"])
    near = [
        p
        for p, c in zip(result.primitives, result.centroids, strict=True)
        if np.linalg.norm(back[:3, :3] @ c + back[:3, 3] - mug) < 0.08
    ]
    assert [p.kind for p in near] == [ShapeKind.CYLINDER]


def test_the_chairs_in_front_of_the_desk_give_no_primitive_over_it() -> None:
    """The desk's plane also holds the chairs' seats and things across the room at its
    height; its objects are those over the desk itself (its main piece's outline)."""
    result = _without_pose("desk_tum")
    desk = result.support
    assert desk is not None and desk.extent is not None and desk.centre is not None
    assert desk.extent[1] < 1.2, desk.extent  # not 1.45 m: the chairs in front are no desk
    front = desk.centre[1] - desk.extent[1] / 2 - 0.05  # y grows away from the camera
    over = [
        np.round(c, 2).tolist()
        for c in result.centroids
        if 0.0 < desk.signed_distance(np.asarray(c)) < 0.6 and c[1] < front
    ]
    assert over == []


def test_the_noise_of_quantised_depths_is_not_zero() -> None:
    """The desk's depths come in steps (about 1 cm at 2 m): most second differences along a
    row are exactly zero, and their median with them."""
    data = np.load(SCANS / "desk_tum.npz")
    depth = data["depth"] * float(data["depth_scale"])
    assert 0.0005 < depth_noise_1m(np.where(depth > 0, depth, np.nan)) < 0.003


def test_the_depth_cut_follows_the_noise_of_the_sensor() -> None:
    params = SegmentationParams()
    cuts = [depth_cut_m(sigma_1m, params) for sigma_1m in (0.001, 0.002, 0.003)]
    assert cuts[0] > cuts[1] > 3.0 > cuts[2]  # the old fixed cut lies between
    assert depth_cut_m(0.001, SegmentationParams(max_depth_m=2.0)) == 2.0
