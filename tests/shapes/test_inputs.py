"""Inputs: arrays, depth images, PLY/PCD/NumPy files and real ROS 1 / ROS 2 bags."""

import numpy as np
import open3d as o3d
import pytest

from shapes import Frame, InvalidCloudError, SourceError, frame_from_depth_image, open_source
from shapes.bags import read_bag, write_bag
from shapes.io import source_length
from shapes.synthetic import random_scene


@pytest.fixture(scope="module")
def shots():
    """Three rendered frames of one synthetic scene (with colours and a camera pose)."""
    rng = np.random.default_rng(21)
    scene = random_scene(rng, 3)
    return [scene.render(rng, stamp=100.0 + 0.5 * i) for i in range(3)]


@pytest.mark.parametrize("ros", [1, 2])
def test_a_bag_gives_back_the_clouds_written_to_it(tmp_path, shots, ros):
    path = tmp_path / ("cloud.bag" if ros == 1 else "cloud_bag")
    frames = [s.frame for s in shots]
    assert write_bag(path, frames, ros=ros, topic="/camera/depth/points") == 3
    pose = shots[0].frame.world_from_sensor
    read = list(read_bag(path, world_from_sensor=pose))
    assert len(read) == 3 and source_length(path) == 3
    for original, got in zip(frames, read, strict=True):
        np.testing.assert_allclose(got.points, original.points, atol=1e-6)  # float32 on the wire
        np.testing.assert_allclose(got.colours, original.colours, atol=0.5 / 255)
        np.testing.assert_allclose(got.world_from_sensor, pose)
        assert got.stamp == pytest.approx(original.stamp)
        assert got.frame_id == "synthetic_camera"
    # The same bag through the generic entry point.
    assert len(list(open_source(path))) == 3


def test_a_ros2_bag_can_be_named_by_its_storage_file(tmp_path, shots):
    write_bag(tmp_path / "b", [shots[0].frame], ros=2)
    db = next((tmp_path / "b").glob("*.db3"))
    assert [f.points.shape for f in open_source(db)] == [shots[0].frame.points.shape]


def test_a_bag_without_the_topic_names_the_topics_it_has(tmp_path, shots):
    path = tmp_path / "c.bag"
    write_bag(path, [shots[0].frame], ros=1, topic="/kinect/points")
    with pytest.raises(
        SourceError, match=r"/other.*\['/kinect/points \(sensor_msgs/msg/PointCloud2\)'\]"
    ):
        list(read_bag(path, topic="/other"))


def test_organised_clouds_lose_their_nan_points(tmp_path):
    points = np.array([[0.0, 0.0, 1.0], [np.nan, np.nan, np.nan], [0.1, 0.0, 1.0]])
    # Frame refuses NaN, so write the message through a frame-like object.
    frame = Frame(np.nan_to_num(points, nan=0.0))
    object.__setattr__(frame, "points", points)
    write_bag(tmp_path / "n.bag", [frame], ros=1)
    (read,) = read_bag(tmp_path / "n.bag")
    np.testing.assert_allclose(read.points, points[[0, 2]], atol=1e-7)


@pytest.mark.parametrize("suffix", [".ply", ".pcd"])
def test_ply_and_pcd_files_are_read_with_their_colours(tmp_path, shots, suffix):
    frame = shots[0].frame
    cloud = o3d.geometry.PointCloud(o3d.utility.Vector3dVector(frame.points))
    cloud.colors = o3d.utility.Vector3dVector(frame.colours)
    path = tmp_path / f"scene{suffix}"
    assert o3d.io.write_point_cloud(str(path), cloud)
    (read,) = open_source(path)
    np.testing.assert_allclose(read.points, frame.points, atol=1e-5)
    np.testing.assert_allclose(read.colours, frame.colours, atol=1 / 255)


def test_numpy_files_are_read(tmp_path):
    pts = np.array([[0.0, 0.0, 1.0], [0.0, 0.1, 1.0]])
    rgb = np.array([[255, 0, 0], [0, 255, 0]], dtype=np.uint8)
    np.save(tmp_path / "xyzrgb.npy", np.hstack((pts, rgb / 255.0)))
    np.savez(tmp_path / "cloud.npz", points=pts, colours=rgb)
    (a,) = open_source(tmp_path / "xyzrgb.npy")
    (b,) = open_source(tmp_path / "cloud.npz")
    for f in (a, b):
        np.testing.assert_allclose(f.points, pts)
        np.testing.assert_allclose(f.colours, rgb / 255.0)


def test_a_depth_image_gives_the_same_cloud_as_the_camera(shots):
    shot = shots[0]
    from shapes.synthetic import Camera

    cam = Camera()
    frame = frame_from_depth_image(
        shot.depth,
        fx=cam.fx,
        fy=cam.fy,
        cx=cam.cx,
        cy=cam.cy,
        rgb=shot.rgb,
        world_from_camera=cam.world_from_camera,
    )
    np.testing.assert_allclose(frame.points, shot.frame.points, atol=1e-12)
    np.testing.assert_allclose(frame.colours, shot.frame.colours, atol=1e-12)
    np.testing.assert_allclose(frame.world_points(), shot.frame.world_points(), atol=1e-12)


def test_millimetre_depth_images_are_scaled():
    depth = np.array([[0, 1000], [2000, 0]], dtype=np.uint16)
    frame = frame_from_depth_image(depth, fx=1.0, fy=1.0, cx=0.0, cy=0.0, depth_scale=0.001)
    np.testing.assert_allclose(frame.points, [[1.0, 0.0, 1.0], [0.0, 2.0, 2.0]])


GOOD = np.zeros((4, 3))


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        (
            {"points": np.zeros((0, 3))},
            r"points: expected an \(N, 3\) array with N >= 1, got shape \(0, 3\)",
        ),
        ({"points": []}, r"points: expected an \(N, 3\) array with N >= 1, got shape \(0,\)"),
        ({"points": np.zeros((4, 2))}, r"points: .*got shape \(4, 2\)"),
        ({"points": np.zeros((2, 3, 1))}, r"points: .*got shape \(2, 3, 1\)"),
        (
            {"points": [[0, 0, np.nan], [1, 1, 1]]},
            r"points: expected finite coordinates, got 1 rows .*row 0",
        ),
        ({"points": [[0, 0, 1], [np.inf, 1, 1]]}, r"points: expected finite .*row 1"),
        ({"points": [["a", "b", "c"]]}, r"points: expected an \(N, 3\) array of numbers"),
        (
            {"points": GOOD, "colours": np.zeros((3, 3))},
            r"colours: expected an \(4, 3\) array .*got shape \(3, 3\)",
        ),
        (
            {"points": GOOD, "colours": np.full((4, 3), 1.5)},
            r"colours: float colours must .*\[0, 1\], got 1.5..1.5",
        ),
        (
            {"points": GOOD, "colours": np.full((4, 3), 300)},
            r"colours: integer colours must lie in 0..255, got 300..300",
        ),
        (
            {"points": GOOD, "world_from_sensor": np.eye(3)},
            r"world_from_sensor: expected a finite 4x4 matrix, got shape \(3, 3\)",
        ),
        (
            {"points": GOOD, "world_from_sensor": 2 * np.eye(4)},
            r"world_from_sensor: expected a rigid transform",
        ),
    ],
)
def test_bad_arrays_are_refused_with_the_field_and_value(kwargs, message):
    with pytest.raises(InvalidCloudError, match=message):
        Frame(**kwargs)


@pytest.mark.parametrize(
    ("depth", "kwargs", "message"),
    [
        (np.zeros(4), {}, r"depth: expected an \(H, W\) image, got shape \(4,\)"),
        (np.zeros((2, 2)), {}, r"depth: expected at least one pixel with a positive depth"),
        (np.full((2, 2), np.nan), {}, r"depth: expected at least one pixel"),
        (np.ones((2, 2)), {"fx": 0.0}, r"fx: expected a positive number, got 0.0"),
        (
            np.ones((2, 2)),
            {"depth_scale": -1.0},
            r"depth_scale: expected a positive number, got -1.0",
        ),
        (
            np.ones((2, 2)),
            {"rgb": np.zeros((2, 3, 3))},
            r"rgb: expected an image of shape \(2, 2, 3\).*got \(2, 3, 3\)",
        ),
    ],
)
def test_bad_depth_images_are_refused(depth, kwargs, message):
    args = {"fx": 1.0, "fy": 1.0, "cx": 0.0, "cy": 0.0, **kwargs}
    with pytest.raises(InvalidCloudError, match=message):
        frame_from_depth_image(depth, **args)


@pytest.mark.parametrize(
    ("name", "content", "error", "message"),
    [
        ("missing.ply", None, SourceError, r"source: '.*missing.ply' does not exist"),
        ("cloud.txt", b"1 2 3", SourceError, r"source: expected a point-cloud file .*cloud.txt"),
        ("empty.ply", b"", SourceError, r"cloud file '.*empty.ply': no point could be read"),
        ("broken.bag", b"not a bag", SourceError, r"bag '.*broken.bag': cannot be read"),
        ("bad.npz", None, SourceError, r"expected an array named 'points'"),
        ("nan.npy", None, InvalidCloudError, r"nan.npy': points: expected finite coordinates"),
    ],
)
def test_bad_sources_are_refused(tmp_path, name, content, error, message):
    path = tmp_path / name
    if content is not None:
        path.write_bytes(content)
    elif name == "bad.npz":
        np.savez(path, xyz=np.zeros((2, 3)))
    elif name == "nan.npy":
        np.save(path, np.full((2, 3), np.nan))
    with pytest.raises(error, match=message):
        list(open_source(path))


def test_a_frame_given_a_pose_that_is_not_rigid_says_so_and_keeps_its_own():
    frame = Frame(np.zeros((2, 3)))
    with pytest.raises(InvalidCloudError, match="world_from_sensor: expected a rigid transform"):
        frame.with_pose(np.diag([1.0, 1.0, 1.0, 2.0]))
    np.testing.assert_array_equal(frame.world_from_sensor, np.eye(4))
