"""Ground truth of the vendored scans, measured by hand, independently of ``shapes``.

Each region is a pixel box chosen by looking at the scan's colour image; the points are
un-projected with the file's own intrinsics, the support is a least-squares plane (SVD) through
the points of a box of bare table or floor (or of several boxes spread over it, where one box
is too small to fix its tilt), an object is the points of its box between 1.5 cm
and 40 cm above that plane (60 or 80 cm where said), and a round object's axis and radius come
from an algebraic least-squares circle (Kasa) through its points in the plane's coordinates.
Everything is in the sensor's optical frame (x right, y down, z forward), in metres.

    python tests/data/real_scans/measure.py > tests/data/real_scans/truth.json
"""

import json
from pathlib import Path

import numpy as np

HERE = Path(__file__).parent
# file: (bare support box or boxes, {object: (box or boxes, round?)}); a box is
# (row0, row1, col0, col1); several boxes are their union (a skewed object beside another).
REGIONS = {
    "mug_stereo": ((390, 470, 150, 300), {"mug": ((225, 385, 330, 440), True)}),
    "bottles_kinect": (
        (300, 380, 250, 600),
        {
            "detergent": ((130, 300, 80, 200), False),
            "milk carton": ((65, 235, 225, 330), False),
            "bleach bottle": ((65, 260, 400, 500), False),
        },
    ),
    "laptop_box_kinect_0": (
        (380, 470, 50, 600),
        {"laptop": ((140, 320, 130, 375), False), "box": ((175, 315, 372, 505), False)},
    ),
    # Held out when they were added (stop 34), tuned on since (README.md).
    "desk_tum": (
        # The desk through one box per quarter of it that holds bare desk (README.md, stop 37):
        # far left, near left, near right; its far right is all objects.
        ((206, 217, 85, 115), (217, 246, 177, 227), (227, 246, 315, 362)),
        {
            # The desk shows through the corners of the die's box 30-45 cm behind it (446 of
            # its 2,419 points, 2.43-2.49 m away): only the points nearer than 2.2 m
            # (NEARER_THAN_M).
            "die": ((193, 247, 124, 172), False),
            "mug": ((197, 228, 526, 552), True),
            "striped board": ((140, 205, 168, 222), False),
            "bag": ((97, 195, 465, 540), False),
            "green bottle": ((118, 188, 336, 350), False),
        },
    ),
    "office_kinect": (
        # Far right, near left, near right; the far left is holes in the depth.
        ((407, 423, 323, 362), (423, 458, 260, 322), (433, 458, 322, 398)),
        {"box": ((378, 455, 482, 590), False), "bag": ((400, 470, 415, 470), False)},
    ),
    # Held out: boxes chosen after the pipeline's code was frozen, never used to change it.
    "bottle_pack_floor_kinect": (
        (390, 470, 250, 550),
        {"bottle pack": ((130, 298, 328, 440), False)},
    ),
    "people_floor_kinect": (
        # Far left, near left, near right, between the people; the far right is all people.
        ((365, 401, 226, 293), (401, 468, 218, 293), (442, 468, 314, 365)),
        {
            "person 1": ((330, 478, 30, 140), False),
            "person 2": ((330, 478, 150, 240), False),
            "person 3": ((330, 440, 290, 362), False),
            "person 4": ((330, 455, 368, 450), False),
            "person 5": ((330, 478, 455, 585), False),
        },
    ),
    # Held out, added at stop 36: converted and measured here, never given to the pipeline
    # before the lead's one run after the merge (README.md).
    "desk_fr1_tum_0": (
        ((395, 445, 245, 335), (140, 160, 160, 260), (240, 255, 20, 60), (330, 345, 5, 25)),
        {
            "cup": ((288, 342, 301, 338), True),
            "milk carton": ((320, 412, 176, 236), False),
            "pen holder": ((310, 378, 236, 296), False),
            "book": ((250, 340, 25, 130), False),
            "keyboard": (((335, 462, 335, 545), (360, 462, 545, 592)), False),
        },
    ),
    "desk_fr1_tum_1": (
        ((395, 440, 250, 330), (135, 158, 150, 250), (250, 258, 5, 40), (300, 340, 3, 18)),
        {
            "cup": ((292, 346, 298, 336), True),
            "milk carton": ((322, 416, 168, 240), False),
            "pen holder": ((312, 378, 230, 292), False),
            "book": ((258, 346, 20, 128), False),
            "keyboard": (((338, 465, 330, 538), (367, 465, 538, 590)), False),
        },
    ),
    "box_floor_kinect": (
        # Far left, far right, near left, near right of the floor in front of the boxes.
        ((428, 449, 38, 190), (437, 449, 245, 290), (449, 469, 38, 245), (449, 469, 245, 451)),
        {"front box": ((280, 436, 298, 434), False), "right box": ((312, 428, 434, 574), False)},
    ),
    "chair_boxes_kinect": (
        # Far left (left of the chair), far right, near left, near right.
        ((410, 439, 35, 78), (421, 439, 321, 386), (439, 469, 255, 321), (440, 469, 321, 525)),
        {
            "chair": (
                (
                    (225, 298, 130, 250),  # back
                    (318, 370, 104, 232),  # seat
                    (372, 420, 148, 168),  # column
                    (420, 472, 80, 250),  # star base
                ),
                False,
            ),
            "box": ((282, 440, 530, 612), False),
        },
    ),
}
HELD_OUT: set[str] = set()
"""Scans no parameter or rule of ``shapes`` was chosen by looking at (README.md). Those held out
until stop 36 were run and diagnosed then, and are tuned on from stop 37; fresh ones join here."""
MAX_HEIGHT_M = {
    "desk_tum": 0.6,
    "office_kinect": 0.8,
    "people_floor_kinect": 0.6,
    "box_floor_kinect": 0.8,
    "chair_boxes_kinect": 1.0,
}
"""Scans whose objects stand taller than the default 40 cm (a bag, an archive box; people,
measured up to 60 cm, the height of objects segmentation looks at; cardboard boxes, a chair)."""
NEARER_THAN_M = {("chair_boxes_kinect", "chair"): 1.85, ("desk_tum", "die"): 2.2}
"""Objects whose boxes also hold what is seen behind them (between the chair's back and seat and
its legs): their points are those nearer to the camera than this. The chair's depths stop at
1.85 m and the wall and stairs behind it start at 1.90 m."""


def points_of(name: str) -> np.ndarray:
    data = np.load(HERE / f"{name}.npz")
    z = data["depth"].astype(np.float64) * float(data["depth_scale"])
    v, u = np.mgrid[0 : z.shape[0], 0 : z.shape[1]]
    x = (u - float(data["cx"])) / float(data["fx"]) * z
    y = (v - float(data["cy"])) / float(data["fy"]) * z
    return np.dstack((x, y, np.where(z > 0, z, np.nan)))


def box(image: np.ndarray, rows_cols: tuple[int, int, int, int]) -> np.ndarray:
    r0, r1, c0, c1 = rows_cols
    pts = image[r0:r1, c0:c1].reshape(-1, 3)
    return pts[np.isfinite(pts).all(axis=1)]


def points_in(image: np.ndarray, region: tuple) -> np.ndarray:
    """The finite points of a box, or of the union of a tuple of boxes."""
    boxes = region if isinstance(region[0], tuple) else (region,)
    return np.concatenate([box(image, b) for b in boxes])


def measure(name: str) -> dict[str, object]:
    image = points_of(name)
    support_box, objects = REGIONS[name]
    floor = points_in(image, support_box)
    centre = floor.mean(axis=0)
    normal = np.linalg.svd(floor - centre, full_matrices=False)[2][2]
    if normal @ -centre < 0:  # towards the camera
        normal = -normal
    offset = float(-normal @ centre)
    rms = float(np.sqrt(np.mean((floor @ normal + offset) ** 2)))
    out: dict[str, object] = {
        "held_out": name in HELD_OUT,
        "support": {
            "normal": normal.round(4).tolist(),
            "distance_m": round(offset, 4),
            "rms_m": round(rms, 4),
            "points": len(floor),
        },
    }
    e1 = np.cross(normal, [1.0, 0.0, 0.0])
    e1 /= np.linalg.norm(e1)
    e2 = np.cross(normal, e1)
    for label, (rows_cols, round_) in objects.items():
        pts = points_in(image, rows_cols)
        h = pts @ normal + offset
        keep = (h > 0.015) & (h < MAX_HEIGHT_M.get(name, 0.40))
        keep &= pts[:, 2] < NEARER_THAN_M.get((name, label), np.inf)
        pts, h = pts[keep], h[keep]
        top = float(np.percentile(h, 99))
        item: dict[str, object] = {"points": len(pts), "height_m": round(top, 4)}
        if round_:
            a, b = pts @ e1, pts @ e2
            design = np.column_stack((a, b, np.ones_like(a)))
            sol = np.linalg.lstsq(design, a**2 + b**2, rcond=None)[0]
            ca, cb = sol[0] / 2, sol[1] / 2
            radius = float(np.sqrt(sol[2] + ca**2 + cb**2))
            foot = ca * e1 + cb * e2 - offset * normal  # the axis meets the support here
            item["radius_m"] = round(radius, 4)
            item["centre"] = (foot + normal * top / 2).round(4).tolist()
        else:
            item["centre"] = pts.mean(axis=0).round(4).tolist()
            item["note"] = "centroid of the visible points"
        out[label] = item
    return out


if __name__ == "__main__":
    print(json.dumps({name: measure(name) for name in REGIONS}, indent=1))
