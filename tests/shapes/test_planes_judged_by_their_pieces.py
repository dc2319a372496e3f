"""A plane is what its connected pieces are (shapes.plane_pieces): a tilted plane whose main
piece stands on the floor is a box's face, not a wall; a horizontal plane scattered in pieces is
no support. Small hand-made planes, and the real scans tuned on for it (box_floor_kinect,
chair_boxes_kinect, desk_fr1_tum_1; tests/data/real_scans/README.md), in the sensor's frame."""

import functools
import json
from pathlib import Path

import numpy as np
import pytest

from shapes import FrameResult, Perception, PerceptionParams, open_source
from shapes.plane_pieces import Ground, faces_standing_on, is_scattered
from shapes.support_region import support_region
from shapes.types import FloatArray

SCANS = Path(__file__).parents[1] / "data" / "real_scans"
TRUTH = json.loads((SCANS / "truth.json").read_text())
TICKS = np.arange(-1.0, 1.0, 0.05)
FLOOR_XY = np.array([[x, y] for x in TICKS for y in TICKS])
FLOOR = Ground(np.array([0.0, 0.0, 1.0]), 0.0, support_region(FLOOR_XY, 0.05), len(FLOOR_XY))
"""A floor 2 m wide at z = 0, its voxels every 5 cm."""


def _wall(y: tuple[float, float], z: tuple[float, float]) -> FloatArray:
    """Voxels every centimetre of the plane x = 0 over the spans ``y`` and ``z`` (metres)."""
    ys, zs = np.arange(*y, 0.01), np.arange(*z, 0.01)
    return np.array([[0.0, a, b] for a in ys for b in zs])


def _freed(*parts: FloatArray) -> list[int]:
    """How many voxels of each part of the plane x = 0 are faces of objects on the floor."""
    voxels = np.vstack(parts)
    freed = faces_standing_on(
        voxels,
        np.full(len(voxels), 0.01),
        np.array([1.0, 0.0, 0.0]),
        [FLOOR],
        cell_m=0.05,
        max_height_m=0.6,
        edge_margin_m=0.02,
        min_voxels=12,
    )
    ends = np.cumsum([len(p) for p in parts])
    return [int(f.sum()) for f in np.split(freed, ends[:-1])]


def test_a_face_standing_inside_the_floor_is_freed_whole() -> None:
    face = _wall((0.0, 0.3), (0.0, 0.4))
    assert _freed(face) == [len(face)]


@pytest.mark.parametrize(
    ("y", "z", "why"),
    [
        ((0.0, 0.3), (0.0, 0.7), "rises past 60 cm"),
        ((0.96, 1.1), (0.0, 0.4), "stands on the floor's outline"),
        ((0.0, 0.3), (-0.2, 0.4), "goes on under the floor"),
    ],
)
def test_a_piece_that_does_not_stand_inside_the_floor_is_a_wall(
    y: tuple[float, float], z: tuple[float, float], why: str
) -> None:
    assert _freed(_wall(y, z)) == [0], why


def test_a_face_lined_up_with_a_larger_wall_is_the_wall_s() -> None:
    """The plane's main piece is a wall (1.2 m tall), so the smaller face that lines up with
    it, 40 cm away, stays the wall's: a strip of clutter along a wall's base is not freed."""
    face, wall = _wall((0.0, 0.3), (0.0, 0.4)), _wall((0.7, 1.0), (0.0, 1.2))
    assert _freed(face, wall) == [0, 0]


def test_the_other_pieces_of_a_face_go_with_it() -> None:
    """A box's face (the main piece) and a smaller face of another box beside it, 20 cm
    away in the same plane, are both freed; a wall piece in the same plane is not."""
    face, small, wall = (
        _wall((0.0, 0.3), (0.0, 0.4)),
        _wall((-0.5, -0.3), (0.0, 0.2)),
        _wall((-0.9, -0.8), (0.0, 1.0)),
    )
    assert _freed(face, small, wall) == [len(face), len(small), 0]


def test_a_plane_whose_main_piece_holds_under_half_its_voxels_is_scattered() -> None:
    ring = np.array([[np.cos(a), np.sin(a)] for a in np.linspace(0, 2 * np.pi, 8, endpoint=False)])
    patch = np.array([[x, y] for x in np.arange(0, 0.1, 0.01) for y in np.arange(0, 0.1, 0.01)])
    assert is_scattered(support_region(np.vstack((patch, 3 * ring)), 0.05), 0.5) is False
    assert is_scattered(support_region(np.vstack((patch[:5], 3 * ring)), 0.05), 0.5) is True


@functools.cache
def _result(name: str) -> FrameResult:
    frame = next(open_source(SCANS / f"{name}.npz"))
    return Perception(PerceptionParams(gravity_from_scene=True), seed=0).process(frame)


def _near(scan: str, label: str) -> list[float]:
    """The distances (cm) of the primitives whose cluster lies within 8 cm of a measured
    object's centre, with no pose (the bench's rule for a part of it)."""
    result = _result(scan)
    back = np.linalg.inv(result.world_from_sensor)
    centre = np.asarray(TRUTH[scan][label]["centre"])
    seen = [np.linalg.norm(back[:3, :3] @ c + back[:3, 3] - centre) for c in result.centroids]
    return [round(100 * float(d), 1) for d in seen if d < 0.08]


@pytest.mark.parametrize(
    ("scan", "label", "within_cm"),
    [("box_floor_kinect", "front box", 3.0), ("chair_boxes_kinect", "box", 4.0)],
)
def test_a_box_on_the_floor_is_one_primitive(scan: str, label: str, within_cm: float) -> None:
    """The box's front face lined up with voxels across the room: judged whole, that plane
    rose to 1.1-1.9 m and was taken for a wall, and the box was missed."""
    near = _near(scan, label)
    assert len(near) == 1 and near[0] < within_cm, near


def test_the_keyboard_is_one_primitive() -> None:
    """A horizontal plane just under the desk's, scattered over the image, was a support of
    its own: the keyboard's voxels over its main piece went to it, and the keyboard came out
    in two parts."""
    assert len(_near("desk_fr1_tum_1", "keyboard")) == 1
