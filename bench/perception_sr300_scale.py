"""The two SR300 tote frames' depth scales, compared on marks both cameras see.

The floor of the tote in ``tote_whisk_sr300_{0,1}`` (one scene, two cameras, one at each end)
has four pairs of marks, rivet heads and holes about 3 cm apart, two pairs at each end of the
tote. Their pixels were read by eye on the colour images (``MARKS``; the depth is aligned to the
colour image). Each mark is placed in 3D in two ways: where its pixel's ray meets the measured
floor (``measure.py``'s plane), and as the median point of the 9 x 9 pixels round it that have a
depth. The script prints, per frame, the distances between the pairs' midpoints across each end
and along each side, and the ratio of frame 0's to frame 1's.

Nothing in the tote has a size known to us, so this checks the two cameras against each other,
not either one against the truth: a depth scale off by a factor scales every distance by it.
Both frames are held out at stop 41 and were loaded only after the lead's one run of them.

Run from the repository root::

    PYTHONPATH=. .venv/bin/python bench/perception_sr300_scale.py
"""

from pathlib import Path

import numpy as np
import numpy.typing as npt

from tests.shapes.real_scans import SCANS, load_script

oracle = load_script(Path(__file__).with_name("perception_oracle.py"), "perception_oracle_scale")

MARKS: dict[str, dict[str, tuple[tuple[int, int], tuple[int, int]]]] = {
    "tote_whisk_sr300_0": {
        "glass end, side A": ((324, 191), (345, 190)),
        "glass end, side B": ((324, 418), (346, 420)),
        "other end, side A": ((146, 207), (161, 206)),
        "other end, side B": ((145, 395), (160, 396)),
    },
    "tote_whisk_sr300_1": {
        "glass end, side A": ((199, 432), (214, 434)),
        "glass end, side B": ((192, 213), (207, 209)),
        "other end, side A": ((390, 467), (415, 472)),
        "other end, side B": ((381, 180), (405, 176)),
    },
}
"""Per frame, each pair's two marks as (row, column) on the colour image. Side A is frame 0's
left; frame 1 looks from the tote's other end, so there it is on the right. The pairs match
across the frames by what they are: at the other end, two rivet heads on side A, a rivet head
and a hole on side B (the hole nearer the tote's middle in both frames)."""

SPANS = (
    ("across the glass end", "glass end, side A", "glass end, side B"),
    ("across the other end", "other end, side A", "other end, side B"),
    ("along side A", "glass end, side A", "other end, side A"),
    ("along side B", "glass end, side B", "other end, side B"),
    ("diagonal", "glass end, side A", "other end, side B"),
)


def mark_points(scan: str, *, on_floor: bool) -> dict[str, npt.NDArray[np.float64]]:
    """Each pair's midpoint in the sensor frame (metres): on the measured floor when
    ``on_floor``, else from the depth round each mark. Raises ValueError when a mark has no
    depth within 4 pixels."""
    with np.load(SCANS / f"{scan}.npz") as data:
        fx, fy, cx, cy = (float(data[k]) for k in ("fx", "fy", "cx", "cy"))
    normal, offset = oracle.measured_support(scan, scan)
    image = oracle.measure.points_of(scan)

    def placed(row: int, col: int) -> npt.NDArray[np.float64]:
        if on_floor:
            ray = np.array([(col - cx) / fx, (row - cy) / fy, 1.0])
            return np.asarray(ray * (-offset / float(normal @ ray)))
        window = image[row - 4 : row + 5, col - 4 : col + 5].reshape(-1, 3)
        window = window[np.isfinite(window).all(axis=1) & (window[:, 2] > 0)]
        if not len(window):
            raise ValueError(f"mark at row {row}, column {col} of {scan}: no depth within 4 px")
        return np.asarray(np.median(window, axis=0))

    return {
        pair: (placed(*first) + placed(*second)) / 2
        for pair, (first, second) in MARKS[scan].items()
    }


def spans_cm(scan: str, *, on_floor: bool) -> dict[str, float]:
    """The distances ``SPANS`` names between pairs' midpoints, in centimetres."""
    points = mark_points(scan, on_floor=on_floor)
    return {name: 100 * float(np.linalg.norm(points[a] - points[b])) for name, a, b in SPANS}


def main() -> None:
    first, second = MARKS
    for on_floor in (True, False):
        how = "rays on the measured floor" if on_floor else "depth round each mark"
        ours, theirs = spans_cm(first, on_floor=on_floor), spans_cm(second, on_floor=on_floor)
        print(f"{how}:")
        for name in ours:
            print(
                f"  {name:<22} {first} {ours[name]:5.1f} cm, {second} {theirs[name]:5.1f} cm,"
                f" ratio {ours[name] / theirs[name]:.3f}"
            )


if __name__ == "__main__":
    main()
