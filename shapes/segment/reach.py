"""reach TODO."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from shapes.segment.params import SegmentationParams
from shapes.types import FloatArray
from shapes.view import ImageView


@dataclass(frozen=True)
class Reach:
    """How far the scene reaches in depth: the frame's pose (None when the points' ranges are
    unknown), the depth cut and how near it a point counts as reaching it."""

    world_from_sensor: FloatArray | None
    depth_cut_m: float
    band_m: float
    view: ImageView | None = None
    """The image's valid window (None for a cloud that is not a camera's image)."""
    depth_image: FloatArray | None = None
    """The survey's depth image (:attr:`Survey.depth_image`)."""


def reaching(near: npt.NDArray[np.bool_], params: SegmentationParams) -> bool:
    count = int(near.sum())
    return count >= params.min_cut_voxels and count >= params.min_cut_share * len(near)
