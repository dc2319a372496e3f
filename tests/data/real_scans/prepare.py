"""Re-create the vendored real scans from PCL's test and data repositories (run by hand, not
by the tests).

Each organised PCD (640 x 480, NaN where the sensor saw nothing) is stored as its depth image:
``depth`` (uint16, in units of ``depth_scale`` metres), the pinhole intrinsics ``fx fy cx cy``
recovered from the points by least squares, and ``rgb`` (uint8) where the cloud has colour. The
Kinect frames' depths are whole millimetres, so they come back to within 1e-6 m; the stereo
scan's are rounded to 0.1 mm.

The TUM RGB-D frame comes as a depth PNG (uint16, 5000 units a metre, registered to the colour
image) and a colour PNG, from Open3D's test data before it left the repository
(``isl-org/Open3D``, commit 6e0924e98^, ``examples/test_data/RGBD/other_formats``); its depths
are copied unchanged (``depth_scale`` 0.2 mm) with the intrinsics the TUM benchmark publishes
for its Freiburg 3 sensor.

Two Freiburg 1 frames of the benchmark's ``fr1/desk`` scene come the same way (depth PNG
registered to the colour PNG, 5000 units a metre) from the example data of
``LucasSheng/dense-rgbd-visual-odometry`` (``examples/case_{1,2}/{dep,img}_prev.png``), with the
intrinsics the benchmark recommends for its registered depth images, ROS's defaults (525 px,
centre 319.5, 239.5), which that repository's ``examples/kinect_params.txt`` also gives.

Two Freiburg 2 frames of the benchmark's ``fr2/desk`` scene come the same way from the example
data of ``gaoxiang12/slambook2`` (MIT; ``ch7/{1,2}.png`` and ``ch7/{1,2}_depth.png``), with the
same recommended intrinsics for registered depth images.

A frame of a lab seen from a robot comes from RTAB-Map's test data (``introlab/rtabmap``, BSD,
commit 982ba35e3d3393b1faa4b3906b234a2e9a9ed656 on its ``gtest`` branch, ``data/rgbd``): a depth
PNG in millimetres registered to a JPEG colour image, with the intrinsics of ``calib/154.yaml``.

Two RealSense frames of a cardboard box on a floor come from the test data of
``felixchenfy/ros_detect_planes_from_depth_img`` (MIT, commit
4d0037cdc67ab919545d4b8c2f14394a1e5eb405, ``data/test_img_{depth,color}.png`` and
``data/{depth,color}/000003.png``): depth in
millimetres (the repository's ``depth_unit``) aligned to the colour image, whose intrinsics
``data/cam_params_realsense.json`` gives.

A RealSense frame of a living room (objects on a wooden floor, a man on a sofa) comes the same way
from ``felixchenfy/ros_3d_pointing_detection`` (MIT, commit
6ba52e0893abca91563d201b2d9cde0e108c8139, ``data/images_n76/{depth,color}/00000.png``): depth
in millimetres aligned to the colour image, with the intrinsics of
``data/images_n76/cam_params_realsense.json``, the same as the box frames'.

A RealSense frame of a tissue box and a mallet on a carpet comes the same way from
``sakizuki/6DPoseAnnotator`` (MIT, commit 6a91bd2ea09847b4ada5e28fc7b42e02a17e6c95,
``data/{depth,rgb}.png``): depth in millimetres (its code reads it with Open3D's depth scale
1000) with pixel-to-pixel correspondence to the colour image, intrinsics in
``data/realsense_intrinsic.json``.

A frame of a mustard bottle on a table comes the same way from
``shiyoung77/6DoF_Pose_Estimation_with_Particle_Filtering`` (BSD-2-Clause, commit
69c653efe00bed8439c4648094345f4233de9576, ``sample_data/{depth,color}.png``): depth in units of
0.25 mm (its ``example.py`` divides by 4000) with the intrinsics that file gives.

Frames of YCB objects on tables come the same way from PoseCNN's demo images (``yuxng/PoseCNN``,
MIT, commit 9f3dd7b7bce21dcafc05e8f18ccc90da3caabd04,
``data/demo_images/00000{1,3,5}-{color,depth}.png``): an Asus Xtion's depth
registered to its colour image, in units of 0.1 mm (its ``tools/demo.py`` gives
``factor_depth`` 10000), with the intrinsic matrix that file gives.

Frames of a mug, a cracker box, a tin and a pepper can on a table come from 6-DoF GraspNet's
demo data (``NVlabs/6dof-graspnet``, MIT, commit d65ed693dcd66bac2bd98968675b452c588fcac6,
``demo/data/{blue_mug,cheezit,cylinder,pepper}.npy``): each a pickled dict holding a float32
depth image in metres (whole multiples of 0.1 mm, stored here in 0.1 mm units), the colour
image and the intrinsic matrix. They are read with an unpickler that builds numpy arrays and
nothing else.

Two frames of a picking robot's red tote come from the demo data of the Amazon Robotics
Challenge 2017 vision code (``andyzeng/arc-robot-vision``, Apache-2.0, commit
33c02ba97097d7a3109736da47f7ded0fc8f19ff,
``parallel-jaw-grasping/convnet/demo/input-{0,1}.{color,depth}.png``): an Intel RealSense
SR300's depth aligned to its colour image, in units of 0.1 mm (the README and
``getHeightmap.m`` read it so), with the colour camera's intrinsic matrix that
``camera-{0,1}.intrinsics.txt`` gives.

A frame of a mug on a desk comes from the test recording of ``etiennedub/pyk4a`` (MIT, commit
8c153164b484037bd7afc02db0c2be89e7bb8b38, ``tests/assets/recording.mkv``): one capture of an
Azure Kinect (time of flight, NFOV unbinned, 640 x 576) with its 720p MJPEG colour image and the
device's calibration in the Matroska file's attachment. The depth camera's lens distortion
(Brown-Conrady, rational) is undone by sampling the raw depth, nearest pixel, at each pixel of a
pinhole image with the depth camera's own focal lengths and principal point (the top 116 rows,
wall above the scene, dropped to make it 640 x 480); each point is coloured by projecting it into
the colour camera (its calibration's extrinsics and distortion), and left black where a nearer
point takes that colour pixel (what the colour camera cannot see). Depths stay whole millimetres.

Two frames of tables with a mug, an apple, cups and bottles come from the sample data of
ClearGrasp (``Shreeyak/cleargrasp``, Apache-2.0, commit
0688647e49380139e440bacbe8562132bb2afbd7,
``data/sample_dataset/real-val/d435/000000{130,080}-opaque-{depth-img.exr,rgb-img.jpg}`` and
``camera_intrinsics.yaml``): an Intel RealSense D435's depth aligned to its 1280 x 720 colour
image, in metres as half floats in an OpenEXR file (ZIP compressed; NaN where there is no
depth), of the scenes' opaque replicas. Every other pixel of every other row is kept (a pinhole
image with half the focal lengths, exactly), and 60 rows with no depth are added above and below
to make it 640 x 480. The depths are stored exactly, in units of 2^-14 m (every half float from
0.25 m to 4 m is a whole number of them).

    python tests/data/real_scans/prepare.py PCL_CHECKOUT/test OPEN3D_CHECKOUT/examples/test_data \
        PCL_DATA_CHECKOUT DENSE_RGBD_VO_CHECKOUT/examples SLAMBOOK2_CHECKOUT RTABMAP_CHECKOUT \
        PLANES_CHECKOUT POINTING_CHECKOUT ANNOTATOR_CHECKOUT PARTICLE_FILTER_CHECKOUT \
        POSECNN_CHECKOUT GRASPNET_6DOF_CHECKOUT ARC_ROBOT_VISION_CHECKOUT PYK4A_CHECKOUT \
        CLEARGRASP_CHECKOUT
"""

import importlib
import io
import json
import pickle
import sys
import zlib
from pathlib import Path

import numpy as np

SCANS = {
    "table_scene_mug_stereo_textured.pcd": ("mug_stereo.npz", 1e-4),
    "milk_cartoon_all_small_clorox.pcd": ("bottles_kinect.npz", 1e-3),
    "grabber_sequences/pcd/frame_20121214T142255.814212.pcd": ("laptop_box_kinect_0.npz", 1e-3),
    "grabber_sequences/pcd/frame_20121214T142256.068683.pcd": ("laptop_box_kinect_1.npz", 1e-3),
    "grabber_sequences/pcd/frame_20121214T142256.332395.pcd": ("laptop_box_kinect_2.npz", 1e-3),
    "office1.pcd": ("office_kinect.npz", 1e-3),
    "five_people.pcd": ("people_floor_kinect.npz", 1e-3),
}
PCL_DATA = {
    "tutorials/region_growing_rgb_tutorial.pcd": ("bottle_pack_floor_kinect.npz", 1e-3),
    "tutorials/pairwise/capture0001.pcd": ("box_floor_kinect.npz", 1e-3),
    "tutorials/pairwise/capture0005.pcd": ("chair_boxes_kinect.npz", 1e-3),
}
"""From PCL's data repository (``PointCloudLibrary/data``, BSD), the third argument."""
TUM = ("RGBD/other_formats/TUM_depth.png", "RGBD/other_formats/TUM_color.png", "desk_tum.npz")
TUM_FREIBURG3 = {"fx": 535.4, "fy": 539.2, "cx": 320.1, "cy": 247.6}
"""The Freiburg 3 sensor's colour intrinsics (the benchmark's depth images of Freiburg 3 are
registered to the colour camera)."""
TUM_FR1 = {
    "case_1/dep_prev.png": ("case_1/img_prev.png", "desk_fr1_tum_0.npz"),
    "case_2/dep_prev.png": ("case_2/img_prev.png", "desk_fr1_tum_1.npz"),
}
"""Freiburg 1 frames of ``fr1/desk``; the examples' ``dep_curr.png`` is one file in both cases
(case 1's and case 2's ``img_curr.png`` differ), so only the ``prev`` pairs are taken."""
TUM_FR2 = {
    "ch7/1_depth.png": ("ch7/1.png", "desk_fr2_tum_0.npz"),
    "ch7/2_depth.png": ("ch7/2.png", "desk_fr2_tum_1.npz"),
}
"""Freiburg 2 frames of ``fr2/desk`` (the fifth argument), two views of one desk from a sweep."""
RTABMAP = ("data/rgbd/depth/154.png", "data/rgbd/rgb/154.jpg", "lab_floor_rtabmap.npz")
RTABMAP_CALIB = {"fx": 525.0, "fy": 525.0, "cx": 319.5, "cy": 239.5}
"""``data/rgbd/calib/154.yaml``'s camera matrix (the sixth argument)."""
REALSENSE = {
    "data/test_img_depth.png": ("data/test_img_color.png", "box_floor_realsense_0.npz"),
    "data/depth/000003.png": ("data/color/000003.png", "box_floor_realsense_1.npz"),
}
REALSENSE_CALIB = {
    "fx": 617.25,
    "fy": 617.5486450195312,
    "cx": 317.3921203613281,
    "cy": 245.98019409179688,
}
"""``data/cam_params_realsense.json``'s intrinsic matrix (column-major, as Open3D writes it); the
seventh argument."""
POINTING = {
    "data/images_n76/depth/00000.png": (
        "data/images_n76/color/00000.png",
        "living_room_floor_realsense.npz",
    ),
}
"""``felixchenfy/ros_3d_pointing_detection``'s first frame (the eighth argument); its camera
file gives ``REALSENSE_CALIB``'s numbers."""
ANNOTATOR = ("data/depth.png", "data/rgb.png", "mallet_box_carpet_realsense.npz")
ANNOTATOR_CALIB = {
    "fx": 622.4392700195312,
    "fy": 622.4393310546875,
    "cx": 315.746337890625,
    "cy": 250.80445861816406,
}
"""``data/realsense_intrinsic.json``'s intrinsic matrix (column-major); the ninth argument."""
PARTICLE_FILTER = ("sample_data/depth.png", "sample_data/color.png", "mustard_table_l515.npz")
PARTICLE_FILTER_CALIB = {"fx": 459.906, "fy": 460.156, "cx": 347.191, "cy": 256.039}
"""``example.py``'s camera (the tenth argument); its depth scale is 4000 units a metre."""
POSECNN = {
    "data/demo_images/000001-depth.png": (
        "data/demo_images/000001-color.png",
        "ycb_chessboard_table_xtion.npz",
    ),
    "data/demo_images/000003-depth.png": (
        "data/demo_images/000003-color.png",
        "ycb_chair_tablet_xtion.npz",
    ),
    "data/demo_images/000005-depth.png": (
        "data/demo_images/000005-color.png",
        "ycb_desk_xtion.npz",
    ),
}
POSECNN_CALIB = {"fx": 1066.778, "fy": 1067.487, "cx": 312.9869, "cy": 241.3109}
"""``tools/demo.py``'s intrinsic matrix (the eleventh argument); 10000 depth units a metre."""
GRASPNET_6DOF = {
    "demo/data/blue_mug.npy": "blue_mug_table_realsense.npz",
    "demo/data/cheezit.npy": "cracker_box_table_realsense.npz",
    "demo/data/cylinder.npy": "tin_table_realsense.npz",
    "demo/data/pepper.npy": "pepper_can_table_realsense.npz",  # reserved at stop 40
}
"""6-DoF GraspNet's demo frames (the twelfth argument); each carries its own intrinsic matrix."""
ARC_TOTE = {
    "parallel-jaw-grasping/convnet/demo/input-0.depth.png": (
        "parallel-jaw-grasping/convnet/demo/input-0.color.png",
        "tote_whisk_sr300_0.npz",
        {"fx": 619.871277, "fy": 619.871338, "cx": 314.241211, "cy": 238.906021},
    ),
    "parallel-jaw-grasping/convnet/demo/input-1.depth.png": (
        "parallel-jaw-grasping/convnet/demo/input-1.color.png",
        "tote_whisk_sr300_1.npz",
        {"fx": 616.849915, "fy": 616.849915, "cx": 310.509369, "cy": 247.691116},
    ),
}
"""The ARC 2017 demo's two cameras over one tote (the thirteenth argument), each with the
intrinsic matrix of its ``camera-{0,1}.intrinsics.txt``; 10000 depth units a metre."""
AZURE_KINECT = ("tests/assets/recording.mkv", "mug_desk_azure_kinect.npz")
"""The pyk4a test recording (the fourteenth argument): one Azure Kinect capture, reserved at stop
41."""
AZURE_TOP_ROWS_DROPPED = 116
"""Rows of the undistorted 640 x 576 depth image left out at its top (the wall above the scene),
so that it is 640 x 480 like every other scan; its bottom row is the raw image's last."""
CLEARGRASP = {
    "data/sample_dataset/real-val/d435/000000130-opaque-depth-img.exr": (
        "data/sample_dataset/real-val/d435/000000130-opaque-rgb-img.jpg",
        "mug_apple_table_d435.npz",
    ),
    "data/sample_dataset/real-val/d435/000000080-opaque-depth-img.exr": (
        "data/sample_dataset/real-val/d435/000000080-opaque-rgb-img.jpg",
        "bottles_cloth_d435.npz",
    ),
}
CLEARGRASP_CALIB = {"fx": 921.0, "fy": 921.0, "cx": 642.0, "cy": 359.0}
"""``camera_intrinsics.yaml`` of the D435 frames at 1280 x 720 (the fifteenth argument)."""
CLEARGRASP_ROWS_ADDED = 60
"""Rows with no depth added above and below the halved 640 x 360 image."""
ROS_DEFAULT = {"fx": 525.0, "fy": 525.0, "cx": 319.5, "cy": 239.5}
"""The intrinsics the TUM benchmark recommends for its registered Freiburg 1 and 2 depth images."""
WIDTH, HEIGHT = 640, 480


def convert(source: Path, target: Path, depth_scale: float) -> None:
    import open3d as o3d  # only here: collecting this file for doctests needs no open3d

    cloud = o3d.io.read_point_cloud(source, remove_nan_points=False, remove_infinite_points=False)
    points = np.asarray(cloud.points)
    assert len(points) == WIDTH * HEIGHT, source
    valid = np.isfinite(points).all(axis=1) & (points[:, 2] > 0)
    pixel = np.flatnonzero(valid)
    u, v = (pixel % WIDTH).astype(float), (pixel // WIDTH).astype(float)
    x, y, z = points[valid].T
    ax, bx = np.polyfit(u, x / z, 1)
    ay, by = np.polyfit(v, y / z, 1)
    depth = np.zeros(WIDTH * HEIGHT, dtype=np.uint16)
    depth[pixel] = np.round(z / depth_scale).astype(np.uint16)
    # A cloud with no colour (PCL's pairwise captures) gets no "rgb": black would read as colour.
    colour = {}
    if cloud.has_colors():
        rgb = np.round(np.asarray(cloud.colors) * 255).astype(np.uint8)
        colour["rgb"] = rgb.reshape(HEIGHT, WIDTH, 3)
    np.savez_compressed(
        target,
        depth=depth.reshape(HEIGHT, WIDTH),
        **colour,
        depth_scale=depth_scale,
        fx=1 / ax,
        fy=1 / ay,
        cx=-bx / ax,
        cy=-by / ay,
    )


def convert_tum(
    depth_png: Path,
    colour_png: Path,
    target: Path,
    intrinsics: dict[str, float] = TUM_FREIBURG3,
    depth_scale: float = 1 / 5000,
) -> None:
    from PIL import Image

    depth = np.asarray(Image.open(depth_png))
    assert depth.dtype == np.uint16 and depth.shape == (HEIGHT, WIDTH), depth_png
    rgb = np.asarray(Image.open(colour_png).convert("RGB"))
    np.savez_compressed(target, depth=depth, rgb=rgb, depth_scale=depth_scale, **intrinsics)


class _ArraysOnly(pickle.Unpickler):
    """Unpickles numpy arrays, their dtypes and plain containers, and refuses any other class (a
    pickle can otherwise run arbitrary code)."""

    ALLOWED = frozenset({"_reconstruct", "ndarray", "dtype", "scalar"})

    def find_class(self, module: str, name: str) -> object:
        if module.split(".")[0] != "numpy" or name not in self.ALLOWED:
            raise pickle.UnpicklingError(f"refused to unpickle {module}.{name}")
        try:
            return getattr(importlib.import_module(module), name)
        except ImportError:  # numpy 2 moved numpy.core to numpy._core
            return getattr(importlib.import_module(module.replace(".core", "._core")), name)


def convert_graspnet_npy(source: Path, target: Path, depth_scale: float = 1e-4) -> None:
    raw = source.read_bytes()
    header = int.from_bytes(raw[8:10], "little")  # a version 1 .npy file of one object
    assert raw[:8] == b"\x93NUMPY\x01\x00", source
    frame = _ArraysOnly(io.BytesIO(raw[10 + header :]), encoding="latin1").load().item()
    metres = frame["depth"].astype(np.float64)
    metres[~np.isfinite(metres)] = 0.0
    depth = np.round(metres / depth_scale)
    assert np.abs(depth * depth_scale - metres).max() < 1e-6 and depth.max() < 2**16, source
    k = frame["intrinsics_matrix"]
    np.savez_compressed(
        target,
        depth=depth.astype(np.uint16),
        rgb=np.ascontiguousarray(frame["image"][..., :3], dtype=np.uint8),
        depth_scale=depth_scale,
        fx=float(k[0, 0]),
        fy=float(k[1, 1]),
        cx=float(k[0, 2]),
        cy=float(k[1, 2]),
    )


def _matroska_frames(raw: bytes) -> dict[int, bytes]:
    """The payload of each track's first block in a Matroska file (track number: bytes), and its
    attachment's data under track 0: a minimal EBML walk, enough for an Azure Kinect recording."""
    masters = {0x18538067, 0x1F43B675, 0xA0, 0x1941A469, 0x61A7}  # segment, cluster, group, ...

    def number(at: int, keep_marker: bool) -> tuple[int, int]:
        length = 1
        while not raw[at] & (0x80 >> (length - 1)):
            length += 1
        value = raw[at] if keep_marker else raw[at] & ((0x80 >> (length - 1)) - 1)
        for byte in raw[at + 1 : at + length]:
            value = value << 8 | byte
        return value, length

    frames: dict[int, bytes] = {}
    stack = [(0, len(raw))]
    while stack:
        at, end = stack.pop()
        while at < end:
            element, n = number(at, keep_marker=True)
            size, m = number(at + n, keep_marker=False)
            at += n + m
            if element in masters:
                stack.append((at, at + size))
            elif element in (0xA3, 0xA1):  # SimpleBlock, Block: track, timecode (2), flags (1)
                track, k = number(at, keep_marker=False)
                frames.setdefault(track, raw[at + k + 3 : at + size])
            elif element == 0x465C:  # FileData of the attachment (calibration.json)
                frames.setdefault(0, raw[at : at + size])
            at += size
    return frames


def _k4a_camera(camera: dict, binned: tuple[int, int], crop: tuple[int, int]) -> dict[str, float]:
    """A camera of the Azure Kinect's raw calibration in pixels for one mode, as the SDK's
    ``transformation_get_mode_specific_camera_calibration`` computes it."""
    p = camera["Intrinsics"]["ModelParameters"]  # cx cy fx fy k1..k6 codx cody p2 p1 (unitised)
    return {
        "cx": p[0] * binned[0] - crop[0] - 0.5,
        "cy": p[1] * binned[1] - crop[1] - 0.5,
        "fx": p[2] * binned[0],
        "fy": p[3] * binned[1],
        **{f"k{i}": p[3 + i] for i in range(1, 7)},
        "p2": p[12],
        "p1": p[13],
    }


def _k4a_distort(cam: dict[str, float], x: np.ndarray, y: np.ndarray) -> tuple[np.ndarray, ...]:
    """Normalised pinhole coordinates to distorted ones (rational Brown-Conrady)."""
    r2 = x * x + y * y
    radial = (1 + r2 * (cam["k1"] + r2 * (cam["k2"] + r2 * cam["k3"]))) / (
        1 + r2 * (cam["k4"] + r2 * (cam["k5"] + r2 * cam["k6"]))
    )
    xd = x * radial + 2 * cam["p1"] * x * y + cam["p2"] * (r2 + 2 * x * x)
    yd = y * radial + cam["p1"] * (r2 + 2 * y * y) + 2 * cam["p2"] * x * y
    return xd, yd


def _exr_half_zip(path: Path) -> np.ndarray:
    """The first channel of an OpenEXR scan-line image of half floats with ZIP compression (the
    only kind ClearGrasp's depth files are), as float32."""
    raw = path.read_bytes()
    at, header = 8, {}
    while raw[at]:
        name_end = raw.index(b"\0", at)
        type_end = raw.index(b"\0", name_end + 1)
        size = int.from_bytes(raw[type_end + 1 : type_end + 5], "little")
        header[raw[at:name_end].decode()] = raw[type_end + 5 : type_end + 5 + size]
        at = type_end + 5 + size
    at += 1
    assert header["compression"] == b"\x03", path  # ZIP, 16 scan lines a block
    x0, y0, x1, y1 = np.frombuffer(header["dataWindow"], "<i4").tolist()
    width, height = x1 - x0 + 1, y1 - y0 + 1
    chlist, types = header["channels"], []
    while chlist[0]:  # name, pixel type (int32), linear, reserved (3), x and y sampling (int32)
        name_end = chlist.index(b"\0")
        types.append(int.from_bytes(chlist[name_end + 1 : name_end + 5], "little"))
        chlist = chlist[name_end + 17 :]
    assert set(types) == {1}, path  # half floats only
    channels = len(types)
    blocks = (height + 15) // 16
    image = np.zeros((height, width), dtype=np.float32)
    for offset in np.frombuffer(raw[at : at + 8 * blocks], "<u8").tolist():
        y, size = np.frombuffer(raw[offset : offset + 8], "<i4").tolist()
        packed = np.frombuffer(zlib.decompress(raw[offset + 8 : offset + 8 + size]), np.uint8)
        deltas = packed.astype(np.int64) - 128
        deltas[0] = packed[0]
        bytes_ = (np.cumsum(deltas) % 256).astype(np.uint8)  # undo the predictor
        half = (len(bytes_) + 1) // 2
        data = np.empty_like(bytes_)
        data[0::2], data[1::2] = bytes_[:half], bytes_[half:]  # undo the interleaving
        rows = min(16, height - (y - y0))
        lines = data.view("<f2").reshape(rows, channels, width)
        image[y - y0 : y - y0 + rows] = lines[:, 0]
    return image


def convert_cleargrasp(depth_exr: Path, colour_jpg: Path, target: Path) -> None:
    from PIL import Image

    metres = _exr_half_zip(depth_exr)[::2, ::2].astype(np.float64)
    metres[~np.isfinite(metres)] = 0.0
    depth = np.round(metres * 2**14)
    assert np.all(depth * 2.0**-14 == metres) and depth.max() < 2**16, depth_exr
    rgb = np.asarray(Image.open(colour_jpg).convert("RGB"))[::2, ::2]
    pad = ((CLEARGRASP_ROWS_ADDED, CLEARGRASP_ROWS_ADDED), (0, 0))
    np.savez_compressed(
        target,
        depth=np.pad(depth.astype(np.uint16), pad),
        rgb=np.pad(rgb, (*pad, (0, 0))),
        depth_scale=2.0**-14,
        fx=CLEARGRASP_CALIB["fx"] / 2,
        fy=CLEARGRASP_CALIB["fy"] / 2,
        cx=CLEARGRASP_CALIB["cx"] / 2,
        cy=CLEARGRASP_CALIB["cy"] / 2 + CLEARGRASP_ROWS_ADDED,
    )


def convert_azure_kinect_mkv(source: Path, target: Path) -> None:
    from PIL import Image

    frames = _matroska_frames(source.read_bytes())
    cameras = {c["Purpose"]: c for c in json.loads(frames[0])["CalibrationInformation"]["Cameras"]}
    depth_cam = _k4a_camera(cameras["CALIBRATION_CameraPurposeDepth"], (1024, 1024), (192, 180))
    colour = cameras["CALIBRATION_CameraPurposePhotoVideo"]
    colour_cam = _k4a_camera(colour, (1280, 960), (0, 120))  # 720p
    raw = np.frombuffer(frames[2], ">u2").reshape(576, 640)  # track 2: depth, b16g, mm
    rgb = np.asarray(Image.open(io.BytesIO(frames[1])).convert("RGB"))  # track 1: MJPEG
    v, u = np.mgrid[0:HEIGHT, 0:WIDTH].astype(np.float64)
    x = (u - depth_cam["cx"]) / depth_cam["fx"]
    y = (v + AZURE_TOP_ROWS_DROPPED - depth_cam["cy"]) / depth_cam["fy"]
    xd, yd = _k4a_distort(depth_cam, x, y)
    ur = np.rint(xd * depth_cam["fx"] + depth_cam["cx"]).astype(int)
    vr = np.rint(yd * depth_cam["fy"] + depth_cam["cy"]).astype(int)
    inside = (ur >= 0) & (ur < 640) & (vr >= 0) & (vr < 576)
    depth = np.zeros((HEIGHT, WIDTH), dtype=np.uint16)
    depth[inside] = raw[vr[inside], ur[inside]]
    z = depth.astype(np.float64) * 1e-3
    points = np.dstack((x * z, y * z, z)).reshape(-1, 3)
    rotation = np.array(colour["Rt"]["Rotation"]).reshape(3, 3)  # depth to colour camera
    seen = points @ rotation.T + np.array(colour["Rt"]["Translation"])
    with np.errstate(invalid="ignore", divide="ignore"):
        xc, yc = _k4a_distort(colour_cam, seen[:, 0] / seen[:, 2], seen[:, 1] / seen[:, 2])
        uc = np.rint(xc * colour_cam["fx"] + colour_cam["cx"])
        vc = np.rint(yc * colour_cam["fy"] + colour_cam["cy"])
    ok = (z.reshape(-1) > 0) & (uc >= 0) & (uc < 1280) & (vc >= 0) & (vc < 720)
    uc, vc = np.where(ok, uc, 0).astype(int), np.where(ok, vc, 0).astype(int)
    cell = vc // 4 * 320 + uc // 4  # a z-buffer over 4 x 4 colour pixels: the nearest point wins
    nearest = np.full(180 * 320, np.inf)
    np.minimum.at(nearest, cell[ok], seen[ok, 2])
    ok &= seen[:, 2] <= nearest[cell] + 0.03
    colours = np.zeros((HEIGHT * WIDTH, 3), dtype=np.uint8)
    colours[ok] = rgb[vc[ok], uc[ok]]
    np.savez_compressed(
        target,
        depth=depth,
        rgb=colours.reshape(HEIGHT, WIDTH, 3),
        depth_scale=1e-3,
        fx=depth_cam["fx"],
        fy=depth_cam["fy"],
        cx=depth_cam["cx"],
        cy=depth_cam["cy"] - AZURE_TOP_ROWS_DROPPED,
    )


if __name__ == "__main__":
    root = Path(sys.argv[1])
    for name, (out, scale) in SCANS.items():
        convert(root / name, Path(__file__).with_name(out), scale)
    if len(sys.argv) > 2:
        depth_png, colour_png, out = TUM
        test_data = Path(sys.argv[2])
        convert_tum(test_data / depth_png, test_data / colour_png, Path(__file__).with_name(out))
    if len(sys.argv) > 3:
        for name, (out, scale) in PCL_DATA.items():
            convert(Path(sys.argv[3]) / name, Path(__file__).with_name(out), scale)
    if len(sys.argv) > 4:
        examples = Path(sys.argv[4])
        for depth_png, (colour_png, out) in TUM_FR1.items():
            target = Path(__file__).with_name(out)
            convert_tum(examples / depth_png, examples / colour_png, target, ROS_DEFAULT)
    if len(sys.argv) > 5:
        slambook = Path(sys.argv[5])
        for depth_png, (colour_png, out) in TUM_FR2.items():
            target = Path(__file__).with_name(out)
            convert_tum(slambook / depth_png, slambook / colour_png, target, ROS_DEFAULT)
    if len(sys.argv) > 6:
        depth_png, colour_png, out = RTABMAP
        rtabmap = Path(sys.argv[6])
        target = Path(__file__).with_name(out)
        convert_tum(rtabmap / depth_png, rtabmap / colour_png, target, RTABMAP_CALIB, 1e-3)
    if len(sys.argv) > 7:
        planes = Path(sys.argv[7])
        for depth_png, (colour_png, out) in REALSENSE.items():
            target = Path(__file__).with_name(out)
            convert_tum(planes / depth_png, planes / colour_png, target, REALSENSE_CALIB, 1e-3)
    if len(sys.argv) > 8:
        pointing = Path(sys.argv[8])
        for depth_png, (colour_png, out) in POINTING.items():
            target = Path(__file__).with_name(out)
            convert_tum(pointing / depth_png, pointing / colour_png, target, REALSENSE_CALIB, 1e-3)
    if len(sys.argv) > 9:
        depth_png, colour_png, out = ANNOTATOR
        annotator = Path(sys.argv[9])
        target = Path(__file__).with_name(out)
        convert_tum(annotator / depth_png, annotator / colour_png, target, ANNOTATOR_CALIB, 1e-3)
    if len(sys.argv) > 10:
        depth_png, colour_png, out = PARTICLE_FILTER
        checkout = Path(sys.argv[10])
        target = Path(__file__).with_name(out)
        convert_tum(
            checkout / depth_png, checkout / colour_png, target, PARTICLE_FILTER_CALIB, 1 / 4000
        )
    if len(sys.argv) > 11:
        posecnn = Path(sys.argv[11])
        for depth_png, (colour_png, out) in POSECNN.items():
            target = Path(__file__).with_name(out)
            convert_tum(posecnn / depth_png, posecnn / colour_png, target, POSECNN_CALIB, 1e-4)
    if len(sys.argv) > 12:
        graspnet = Path(sys.argv[12])
        for source, out in GRASPNET_6DOF.items():
            convert_graspnet_npy(graspnet / source, Path(__file__).with_name(out))
    if len(sys.argv) > 13:
        arc = Path(sys.argv[13])
        for depth_png, (colour_png, out, camera) in ARC_TOTE.items():
            target = Path(__file__).with_name(out)
            convert_tum(arc / depth_png, arc / colour_png, target, camera, 1e-4)
    if len(sys.argv) > 14:
        recording, out = AZURE_KINECT
        convert_azure_kinect_mkv(Path(sys.argv[14]) / recording, Path(__file__).with_name(out))
    if len(sys.argv) > 15:
        checkout = Path(sys.argv[15])
        for depth_exr, (colour_jpg, out) in CLEARGRASP.items():
            target = Path(__file__).with_name(out)
            convert_cleargrasp(checkout / depth_exr, checkout / colour_jpg, target)
