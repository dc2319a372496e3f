"""What stands under a support's edge is part of the support, and a plane that crosses a
support is no second support (stop 38; docs/perception.md, "Things under a support's edge").

On real scans tuned on (tests/data/real_scans/README.md), in the sensor's frame: the desk's
leg of ``desk_fr2_tum_0`` and the panel under ``desk_tum``'s top, seen on the floor through the
gap under the desk's front edge, give no primitive; the orange box on the floor beside
``desk_tum``'s desk, which stands clear of the desk's outline, still does. With the plane
search's seed 2 the paper cup of ``desk_fr1_tum_0`` is found, as on the other seeds."""

import json
from pathlib import Path

import numpy as np

from shapes import FrameResult, ShapeKind
from shapes.support_edge import occluders_above
from shapes.view import ImageView
from tests.shapes.real_scans import perceived

SCANS = Path(__file__).parents[1] / "data" / "real_scans"
TRUTH = json.loads((SCANS / "truth.json").read_text())


def _seen(result: FrameResult) -> list[np.ndarray]:
    """Each primitive's cluster centroid in the sensor's frame."""
    back = np.linalg.inv(result.world_from_sensor)
    return [back[:3, :3] @ c + back[:3, 3] for c in result.centroids]


def _centre_of_pixels(name: str, rows: slice, cols: slice, farther_than_m: float) -> np.ndarray:
    """The centroid, in the sensor's frame, of a scan's depths in a pixel box farther than
    ``farther_than_m``: a thing measured on the image, independently of ``shapes``."""
    data = np.load(SCANS / f"{name}.npz")
    depth = data["depth"].astype(np.float64) * float(data["depth_scale"])
    r, c = np.mgrid[rows, cols]
    z = depth[rows, cols]
    keep = z > farther_than_m
    x = (c[keep] - float(data["cx"])) * z[keep] / float(data["fx"])
    y = (r[keep] - float(data["cy"])) * z[keep] / float(data["fy"])
    return np.array([x.mean(), y.mean(), z[keep].mean()])


def test_occluders_above_are_the_first_nearer_pixels_past_a_regions_top() -> None:
    """A 10 x 6 image, the open edge at the bottom: a region in rows 6-8 of columns 1-3; over
    column 1 a desk's edge 1 m away in row 4, over column 2 only the far floor, over column 3
    the edge too far up (row 0, 6 rows past the region's top) for a probe of 4 pixels."""
    image = np.full((10, 6), 3.0)
    image[4, 1] = 1.0
    image[0, 3] = 1.0
    pixels = np.array([r * 6 + c for r in (6, 7, 8) for c in (1, 2, 3)])
    view = ImageView((0, 9), (0, 5), 6, "bottom")
    lines, found = occluders_above(
        view, pixels, np.full(len(pixels), 2.0), image, probe_px=4, nearer_m=0.03
    )
    assert lines == 3
    assert found.tolist() == [4 * 6 + 1]


def test_the_desks_leg_under_the_front_of_desk_fr2_tum_0_gives_no_primitive() -> None:
    """Main gave two primitives on the floor, 58-78 cm under the desk: its leg (352 voxels),
    under the desk's outline, and a 17-voxel piece 16 cm left of where the seen desk ends
    (the image's edge cuts the desk there). The leg is gone; nothing lies under the desk's
    rectangle on the floor."""
    result = perceived("desk_fr2_tum_0")
    assert result.support is not None
    desk = result.support
    assert desk.centre is not None and desk.extent is not None
    lo = np.asarray(desk.centre[:2]) - np.asarray(desk.extent) / 2
    hi = np.asarray(desk.centre[:2]) + np.asarray(desk.extent) / 2
    under = [
        c
        for c in result.centroids
        if desk.signed_distance(np.asarray(c)[None, :])[0] < -0.3
        and np.all((np.asarray(c[:2]) > lo) & (np.asarray(c[:2]) < hi))
    ]
    assert under == []


def test_the_panel_under_desk_tums_top_gives_no_primitive() -> None:
    """The beige panel under the desk, 3.0-3.2 m away, about 1 m wide, seen between the desk's
    front edge and the chairs (rows 256-284, columns 120-284), its top hidden by the desk's
    edge: no primitive's centroid is seen there, beyond the desk's front (2.1 m)."""
    data = np.load(SCANS / "desk_tum.npz")
    fx, fy, cx, cy = (float(data[k]) for k in ("fx", "fy", "cx", "cy"))
    there = [
        c
        for c in _seen(perceived("desk_tum"))
        if c[2] > 2.9
        and 120 <= fx * c[0] / c[2] + cx <= 284
        and 256 <= fy * c[1] / c[2] + cy <= 284
    ]
    assert there == []


def test_the_orange_box_beside_desk_tums_desk_is_still_a_primitive() -> None:
    """The price's guard: the orange box on the floor at the desk's left end, its top also
    hidden by the desk's edge, stands 26 cm or more clear of the desk's outline: an object,
    kept (no ground truth: a stray primitive of the bench)."""
    box = _centre_of_pixels("desk_tum", slice(258, 268), slice(52, 69), 2.5)
    seen = _seen(perceived("desk_tum"))
    assert min(float(np.linalg.norm(c - box)) for c in seen) < 0.08


def test_the_paper_cup_of_desk_fr1_tum_0_is_found_on_the_plane_searchs_seed_2() -> None:
    """Main lost it on seed 2: a plane 4 degrees off the desk's, running from 2.7 cm under the
    desk to 14 cm over it, was a second support, and the cup stood on it under the monitor's
    screen. (Frame 1's cup is still lost on seed 2, by another rule: docs/perception.md.)"""
    name = "desk_fr1_tum_0"
    result = perceived(name, 2)
    cup = TRUTH[name]["cup"]
    seen = _seen(result)
    near = [k for k, c in enumerate(seen) if np.linalg.norm(c - cup["centre"]) < 0.08]
    assert len(near) == 1, [result.primitives[k] for k in near]
    primitive = result.primitives[near[0]]
    assert primitive.kind in (ShapeKind.CYLINDER, ShapeKind.CONE), primitive
    back = np.linalg.inv(result.world_from_sensor)
    axis_centre = back[:3, :3] @ np.asarray(primitive.centre) + back[:3, 3]
    assert np.linalg.norm(axis_centre - cup["centre"]) < 0.03
