"""Perception on real organised scans (PCL's test data, tests/data/real_scans/README.md).

The expected values were measured by hand, independently of ``shapes``
(tests/data/real_scans/measure.py); all comparisons are in the sensor's optical frame.
"""

import functools
from pathlib import Path

import numpy as np
import pytest

from shapes import FrameResult, Perception, PerceptionParams, ShapeKind, open_source

SCANS = Path(__file__).parents[1] / "data" / "real_scans"

# Ground truth (README there): support normal towards the camera, its distance from the camera.
SUPPORTS = {
    "mug_stereo": ((0.0169, -0.8345, -0.5507), 0.5316),
    "bottles_kinect": ((0.0077, -0.8275, -0.5614), 0.4589),
    "laptop_box_kinect_0": ((0.077, -0.6879, -0.7217), 0.7164),
}
MUG_CENTRE = np.array([0.0542, 0.0691, 0.7676])
MUG_RADIUS = 0.0392


def _run(name: str, pose: np.ndarray | None = None) -> FrameResult:
    if pose is None:
        return _without_pose(name)
    frame = next(open_source(SCANS / f"{name}.npz", world_from_sensor=pose))
    return Perception(seed=0).process(frame)


@functools.cache
def _without_pose(name: str) -> FrameResult:
    """One scan through a fresh chain with no pose (cached: several tests read each result)."""
    frame = next(open_source(SCANS / f"{name}.npz"))
    return Perception(PerceptionParams(gravity_from_scene=True), seed=0).process(frame)


def _in_sensor(result: FrameResult, point: tuple[float, float, float]) -> np.ndarray:
    pose = np.linalg.inv(result.world_from_sensor)
    return np.asarray(pose[:3, :3] @ np.asarray(point) + pose[:3, 3])


@pytest.fixture
def mug() -> FrameResult:
    return _run("mug_stereo")


@pytest.mark.parametrize("name", sorted(SUPPORTS))
def test_without_a_pose_up_is_the_normal_of_the_support(name: str) -> None:
    result = _run(name)
    assert result.gravity.startswith("gravity from the scene"), result.gravity
    assert result.support is not None, result.reason
    normal, distance = SUPPORTS[name]
    up = result.world_from_sensor[:3, :3].T @ np.asarray(result.support.normal)
    angle = np.degrees(np.arccos(np.clip(up @ np.asarray(normal), -1.0, 1.0)))
    assert angle < 5.0
    camera = result.world_from_sensor[:3, 3]
    height = float(camera @ np.asarray(result.support.normal) + result.support.offset)
    assert abs(height - distance) < 0.02


def test_one_mug_on_a_table_is_a_cylinder_standing_on_a_plane(mug: FrameResult) -> None:
    assert [p.kind for p in mug.primitives] == [ShapeKind.CYLINDER]
    assert [p.kind for p in mug.supports] == [ShapeKind.PLANE]
    cylinder, table = mug.primitives[0], mug.supports[0]
    assert cylinder.radius is not None
    assert abs(cylinder.radius - MUG_RADIUS) < 0.25 * MUG_RADIUS
    assert np.linalg.norm(_in_sensor(mug, cylinder.centre) - MUG_CENTRE) < 0.03
    assert table.axis is not None and table.axis[2] > 0.999  # the table's normal is up
    assert cylinder.axis is not None and abs(cylinder.axis[2]) > 0.99  # the mug stands


@pytest.mark.parametrize("name", ["laptop_box_kinect_1", "laptop_box_kinect_2", "bottles_kinect"])
def test_no_primitive_leaves_its_own_points(name: str) -> None:
    result = _run(name)
    assert result.primitives
    for primitive, centroid in zip(result.primitives, result.centroids, strict=True):
        reach = (primitive.radius or 0.0) + 0.3  # no object here is 60 cm across
        assert np.linalg.norm(np.asarray(primitive.centre) - centroid) < reach, primitive
        assert (primitive.radius or 0.0) < 0.3 and (primitive.height or 0.0) < 0.6, primitive


def test_a_pose_changed_by_a_millionth_gives_the_same_primitives(mug: FrameResult) -> None:
    pose = mug.world_from_sensor.copy()
    nudged = pose.copy()
    nudged[:3, 3] += 1e-6
    results = [_run("mug_stereo", pose=p) for p in (pose, nudged)]
    kinds = [[p.kind for p in r.primitives + r.supports] for r in results]
    assert kinds[0] == kinds[1] == [ShapeKind.CYLINDER, ShapeKind.PLANE]
    np.testing.assert_allclose(
        results[0].primitives[0].centre, results[1].primitives[0].centre, atol=1e-4
    )


def _turned_about_up(pose: np.ndarray, angle: float) -> np.ndarray:
    c, s = np.cos(angle), np.sin(angle)
    turned = pose.copy()
    turned[:3, :3] = np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]]) @ pose[:3, :3]
    return turned


@pytest.mark.parametrize(
    ("name", "nudge"),
    [
        ("bottles_kinect", "moved"),
        ("bottles_kinect", "turned"),
        ("laptop_box_kinect_0", "moved"),
        ("laptop_box_kinect_2", "turned"),
        ("desk_tum", "turned"),  # one cluster more or less no longer moves the others' fits
    ],
)
def test_a_pose_changed_by_a_millionth_gives_the_same_primitives_on_a_cluttered_scan(
    name: str, nudge: str
) -> None:
    pose = _without_pose(name).world_from_sensor
    nudged = _turned_about_up(pose, 1e-6) if nudge == "turned" else pose.copy()
    if nudge == "moved":
        nudged[:3, 3] += 1e-6
    first, second = (_run(name, pose=p) for p in (pose, nudged))
    kinds = [[p.kind for p in r.primitives + r.supports] for r in (first, second)]
    assert kinds[0] == kinds[1]
    pairs = zip(first.primitives + first.supports, second.primitives + second.supports, strict=True)
    for a, b in pairs:
        np.testing.assert_allclose(a.centre, b.centre, atol=1e-4)


# Hand-measured centroids of the visible points of objects that are none of the four shapes.
OBJECTS = {
    "bottles_kinect": {
        "detergent": (-0.2211, -0.0178, 0.6478),
        "milk carton": (-0.0564, -0.1381, 0.7728),
        "bleach bottle": (0.1722, -0.0874, 0.6974),
    },
    "laptop_box_kinect_0": {"laptop": (-0.0998, -0.0206, 0.8214), "box": (0.19, 0.0106, 0.8968)},
}


@pytest.mark.parametrize("name", sorted(OBJECTS))
def test_each_object_is_one_primitive_on_one_support(name: str) -> None:
    result = _run(name)
    assert len(result.supports) == 1  # a box's top or a rug is no second table
    seen = [_in_sensor(result, tuple(c)) for c in result.centroids]
    for label, truth in OBJECTS[name].items():
        near = [k for k, c in enumerate(seen) if np.linalg.norm(c - truth) < 0.08]
        assert len(near) == 1, (label, [result.primitives[k] for k in near])
        assert np.linalg.norm(seen[near[0]] - truth) < 0.03, label


def test_the_open_laptop_on_the_floor_is_a_plane_and_its_lid_no_wall() -> None:
    result = _run("laptop_box_kinect_0")
    laptop = OBJECTS["laptop_box_kinect_0"]["laptop"]
    planes = [
        p
        for p in result.primitives
        if p.kind is ShapeKind.PLANE
        and np.linalg.norm(_in_sensor(result, p.centre) - laptop) < 0.03
    ]
    assert len(planes) == 1
    assert planes[0].axis is not None and abs(planes[0].axis[2]) < 0.9  # the lid leans back


def test_a_static_scene_keeps_the_ids_of_its_objects_over_consecutive_frames() -> None:
    perception = Perception(PerceptionParams(gravity_from_scene=True), seed=0)
    ids = []
    for k in range(3):
        frame = next(open_source(SCANS / f"laptop_box_kinect_{k}.npz"))
        result = perception.process(frame)
        near = {}
        for label, truth in OBJECTS["laptop_box_kinect_0"].items():
            centres = [_in_sensor(result, tuple(c)) for c in result.centroids]
            k_near = int(np.argmin([np.linalg.norm(c - truth) for c in centres]))
            near[label] = result.primitives[k_near].tracking_id
        near["floor"] = result.supports[0].tracking_id
        ids.append(near)
    assert ids[0] == ids[1] == ids[2]
    assert len(set(ids[0].values())) == 3


# The TUM desk's mug, 2.27 m away, where the Kinect's depths come in ~2 cm steps (truth.json).
TUM_MUG_CENTRE = np.array([0.9364, -0.1389, 2.2831])
TUM_MUG_RADIUS = 0.0344


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_a_far_mug_on_coarse_depth_steps_is_a_standing_cylinder_of_its_radius(seed: int) -> None:
    frame = next(open_source(SCANS / "desk_tum.npz"))
    result = Perception(PerceptionParams(gravity_from_scene=True), seed=seed).process(frame)
    seen = [_in_sensor(result, tuple(c)) for c in result.centroids]
    k = int(np.argmin([np.linalg.norm(c - TUM_MUG_CENTRE) for c in seen]))
    assert np.linalg.norm(seen[k] - TUM_MUG_CENTRE) < 0.08
    mug = result.primitives[k]
    assert mug.kind is ShapeKind.CYLINDER and mug.radius is not None
    assert abs(mug.radius - TUM_MUG_RADIUS) < 0.25 * TUM_MUG_RADIUS
    assert mug.axis is not None and mug.axis[2] > 0.95  # it stands
