"""How far the scene reaches: the depth cut, the image's window, a point's depth.

:class:`Reach` holds the depth cut and its band, the image's valid window and depth image, and
the pose that gives a world point's depth; :func:`reaching` says when enough of a cluster
reaches a limit to be cut by it.
"""

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
    """The survey's depth image (:attr:`shapes.segment.survey.Survey.depth_image`)."""

    def image(self) -> tuple[ImageView, FloatArray] | None:
        """The image's valid window and its depth image, when both and the pose are known (a
        camera's organised frame), else None."""
        if self.view is None or self.depth_image is None or self.world_from_sensor is None:
            return None
        return self.view, self.depth_image

    def depth_of(self, points: FloatArray) -> FloatArray:
        """Each of ``points`` (world frame) at its depth in the sensor's frame (its z there).
        Raises AssertionError when the pose is unknown (``world_from_sensor`` is None)."""
        assert self.world_from_sensor is not None
        rotation, shift = self.world_from_sensor[:3, :3], self.world_from_sensor[:3, 3]
        depth: FloatArray = (points - shift) @ rotation[:, 2]
        return depth


def reaching(near: npt.NDArray[np.bool_], params: SegmentationParams) -> bool:
    """Whether the ``near`` ones (of a cluster's voxels or points, those near a limit of the
    scene) are enough to cut it: ``min_cut_voxels`` of them and ``min_cut_share`` of all."""
    count = int(near.sum())
    return count >= params.min_cut_voxels and count >= params.min_cut_share * len(near)
