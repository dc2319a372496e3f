"""A cut whose parts close a ring: one thing seen from above, cut along its own inside.

The splitter (:mod:`shapes.split`) cuts a cluster along its concave seams. A bowl seen from above
is concave all round its inside, and comes out in pieces laid around its middle; so does the
foot of a desk's leg, whose seams run round its post. Objects that touch stand side by side:
their parts do not surround a common centre. :func:`closes_a_ring` tells the two apart from the
parts' centres across the support alone.
"""

from __future__ import annotations

import numpy as np
import numpy.typing as npt

from shapes.types import FloatArray

__all__ = ["closes_a_ring", "largest_gap_deg"]


def largest_gap_deg(voxels: FloatArray, parts: npt.NDArray[np.int64]) -> float:
    """The widest angle, seen from the centre of ``voxels`` across the support (x, y), between
    the centres of two parts (``parts``: labels 0, 1, ...) that follow each other around it;
    360 for a single part.

    >>> square = np.array([[1.0, 0, 0], [0, 1, 0], [-1, 0, 0], [0, -1, 0]])
    >>> largest_gap_deg(square, np.array([0, 1, 2, 3]))
    90.0
    >>> largest_gap_deg(square, np.array([0, 0, 1, 1]))  # two halves side by side
    180.0
    """
    xy = np.asarray(voxels)[:, :2]
    count = int(parts.max()) + 1
    if count < 2:
        return 360.0
    offsets = np.array([xy[parts == k].mean(axis=0) for k in range(count)]) - xy.mean(axis=0)
    angles = np.sort(np.degrees(np.arctan2(offsets[:, 1], offsets[:, 0])))
    gaps = np.diff(np.r_[angles, angles[0] + 360.0])
    return float(np.round(gaps.max(), 6))


def closes_a_ring(voxels: FloatArray, parts: npt.NDArray[np.int64], max_gap_deg: float) -> bool:
    """Whether the parts of a cut (``parts``: labels 0, 1, ... of ``voxels``) lie around their
    common centre with no gap between neighbouring parts wider than ``max_gap_deg``
    (:func:`largest_gap_deg`): three parts or more round one middle.

    Raises ValueError when ``max_gap_deg`` is not in (0, 180).

    >>> ring = np.array([[np.cos(a), np.sin(a), 0.0] for a in np.radians([0, 100, 200, 280])])
    >>> closes_a_ring(ring, np.array([0, 1, 2, 3]), 125.0)
    True
    >>> closes_a_ring(ring, np.array([0, 0, 1, 1]), 125.0)
    False
    """
    if not 0 < max_gap_deg < 180:
        raise ValueError(f"max_gap_deg must lie between 0 and 180 degrees, got {max_gap_deg}")
    return int(parts.max()) >= 2 and largest_gap_deg(voxels, parts) <= max_gap_deg
