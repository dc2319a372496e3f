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

    python tests/data/real_scans/prepare.py PCL_CHECKOUT/test OPEN3D_CHECKOUT/examples/test_data \
        PCL_DATA_CHECKOUT DENSE_RGBD_VO_CHECKOUT/examples SLAMBOOK2_CHECKOUT RTABMAP_CHECKOUT \
        PLANES_CHECKOUT POINTING_CHECKOUT ANNOTATOR_CHECKOUT PARTICLE_FILTER_CHECKOUT \
        POSECNN_CHECKOUT GRASPNET_6DOF_CHECKOUT ARC_ROBOT_VISION_CHECKOUT
"""

import importlib
import io
import pickle
import sys
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
