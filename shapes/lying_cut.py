"""A cut whose parts all lie low: one thing lying on the support, cut along its own shape.

The splitter (:mod:`shapes.split`) cuts a cluster where its surface folds inwards. A drill lying
on its side folds so between its grip, its body and its chuck, and each of the parts reaches
down to the support, as objects standing side by side do. What tells them apart is height:
objects set down side by side stand up from the support, while the parts of one thing lying
on it all stay low. :func:`lies_low` reads each part's height as the 98th percentile of its
voxels' heights over the support, so that a stray voxel above does not lift it.
"""

from __future__ import annotations

import numpy as np
import numpy.typing as npt

from shapes.types import FloatArray

__all__ = ["lies_low", "part_heights"]


def part_heights(heights: FloatArray, parts: npt.NDArray[np.int64]) -> FloatArray:
    """Each part's height over the support (``parts``: labels 0, 1, ... of the voxels whose
    heights are ``heights``): the 98th percentile of its voxels' heights.

    Raises ValueError when ``parts`` does not give one label per height.

    >>> part_heights(np.array([0.01, 0.05, 0.02, 0.12]), np.array([0, 0, 1, 1])).round(4)
    array([0.0492, 0.118 ])
    """
    heights = np.asarray(heights, dtype=np.float64)
    if len(parts) != len(heights):
        raise ValueError(f"parts: expected one label per height ({len(heights)}), got {len(parts)}")
    count = int(parts.max(initial=-1)) + 1
    return np.array([np.percentile(heights[parts == k], 98) for k in range(count)])


def lies_low(heights: FloatArray, parts: npt.NDArray[np.int64], max_height_m: float) -> bool:
    """Whether a cut into two parts or more (``parts``: labels 0, 1, ... of the voxels whose
    heights over the support are ``heights``) has every part lower than ``max_height_m``
    (:func:`part_heights`): one thing lying on the support, not things standing side by side.

    Raises ValueError when ``max_height_m`` is not positive, or ``parts`` does not give one
    label per height.

    >>> drill = np.array([0.01, 0.05, 0.01, 0.04, 0.02, 0.055])
    >>> lies_low(drill, np.array([0, 0, 1, 1, 2, 2]), 0.075)
    True
    >>> lies_low(np.array([0.01, 0.05, 0.01, 0.11]), np.array([0, 0, 1, 1]), 0.075)
    False
    >>> lies_low(drill, np.zeros(6, dtype=np.int64), 0.075)  # no cut
    False
    """
    if not max_height_m > 0:
        raise ValueError(f"max_height_m must be positive, got {max_height_m}")
    tops = part_heights(heights, parts)
    return len(tops) >= 2 and bool((tops < max_height_m).all())
