"""The plane search among a frame's voxels (step 3 of :mod:`shapes.segment`).

RANSAC in numpy, one plane after another on what the previous ones left, each refitted by least
squares (:func:`find_planes`), and a plane turned into the world frame, where it is horizontal
or not (:func:`in_world`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from shapes.arrays import column_span
from shapes.segment.params import SegmentationParams
from shapes.types import FloatArray

_HYPOTHESES_PER_PASS = 32
"""Plane hypotheses scored against every point at once (bounds the distance matrix)."""


_CONFIDENCE = 1 - 1e-3
"""RANSAC stops once a better plane is this unlikely to be left among the unscored samples
(the textbook bound: 1 - 1e-3 of drawing at least one all-inlier sample)."""


_SCORED_POINTS = 4000
"""Planes are sampled and scored on this many random points (a plane holding 3 % of the voxels
still has ~120 of them there); its inliers are then taken from all the points."""


def ransac_plane(
    points: FloatArray, threshold: float, iterations: int, rng: np.random.Generator
) -> tuple[FloatArray, npt.NDArray[np.intp]] | None:
    """RANSAC: of up to ``iterations`` planes through three random points, the one with the
    most points within ``threshold`` (the first on a tie), counted on ``_SCORED_POINTS`` random
    points when there are more, with distances in single precision. It stops early, as usual,
    once the samples scored make a better plane unlikely (``_CONFIDENCE``, from the best inlier
    ratio so far). Returns the unit normal and the indices of its points, or None if no sample
    spans a plane.

    In numpy with the caller's generator, so that a seed fixes the result: open3d's
    ``segment_plane`` runs its iterations on parallel threads and, even seeded, its result
    varies with their scheduling (seen as a flaky determinism test on a loaded machine).
    """
    if len(points) < 3:
        return None
    everything = points
    if len(points) > _SCORED_POINTS:
        points = points[np.sort(rng.choice(len(points), _SCORED_POINTS, replace=False))]
    samples = rng.integers(0, len(points), size=(iterations, 3))
    a, b, c = points[samples[:, 0]], points[samples[:, 1]], points[samples[:, 2]]
    normals = np.cross(b - a, c - a)
    lengths = np.linalg.norm(normals, axis=1)
    spanning = lengths > 1e-12
    if not spanning.any():
        return None
    normals = normals[spanning] / lengths[spanning, None]
    offsets = -np.einsum("ij,ij->i", normals, a[spanning])
    # Hypotheses are scored in single precision (docs/perception.md, "The plane search scored
    # in single precision (stop 40, speed)"): half the arithmetic and memory of the distance
    # matrices; a point's distance moves by a micrometre at most, so only a point that close to
    # the threshold can count differently. The inliers are then taken in double precision.
    scored = np.ascontiguousarray(points.T, dtype=np.float32)
    normals32, offsets32 = normals.astype(np.float32), offsets.astype(np.float32)
    best, best_count = 0, -1
    within = np.empty((_HYPOTHESES_PER_PASS, len(points)), dtype=np.float32)
    ones = np.ones(len(points), dtype=np.float32)
    for start in range(0, len(normals), _HYPOTHESES_PER_PASS):
        stop = start + _HYPOTHESES_PER_PASS
        # One row per hypothesis, summed along the row: a count down the columns of the
        # transposed matrix (np.count_nonzero with an axis) took seven times as long. The
        # count is a float32 matrix-vector product of the 0/1 matrix (exact below 2**24),
        # cheaper than numpy's sum of booleans.
        distances = normals32[start:stop] @ scored
        distances += offsets32[start:stop, None]
        np.abs(distances, out=distances)
        rows = within[: len(distances)]
        np.less_equal(distances, threshold, out=rows, casting="unsafe")
        counts = rows @ ones
        k = int(np.argmax(counts))
        if counts[k] > best_count:
            best, best_count = start + k, int(counts[k])
        p_good = (best_count / len(points)) ** 3  # that a sample's three points are all inliers
        if p_good >= 1 or (p_good > 0 and stop >= math.log(1 - _CONFIDENCE) / math.log1p(-p_good)):
            break
    inliers = np.flatnonzero(np.abs(everything @ normals[best] + offsets[best]) <= threshold)
    return normals[best], inliers


@dataclass(frozen=True, eq=False)
class Plane:
    normal: FloatArray
    offset: float
    inliers: npt.NDArray[np.bool_]
    horizontal: bool

    def describe(self) -> str:
        tilt = math.degrees(math.acos(min(1.0, abs(float(self.normal[2])))))
        height = -self.offset / self.normal[2] if abs(self.normal[2]) > 1e-6 else float("nan")
        kind = f"horizontal at z={height:.2f} m" if self.horizontal else f"tilted {tilt:.0f} deg"
        return f"{kind} ({int(self.inliers.sum())} voxels)"


def find_planes(
    voxels: FloatArray, params: SegmentationParams, seed: int, tolerance: FloatArray | None = None
) -> list[Plane]:
    """Up to ``max_planes`` planes, one after another on what the previous ones left, each
    refitted by least squares, in the frame of ``voxels`` (none is marked horizontal: that
    takes a pose, :func:`in_world`).

    ``tolerance``: per voxel, how far from a plane it may lie and still belong to it (the
    depth noise grows with the range); by default ``support_threshold_m``.
    """
    if tolerance is None:
        tolerance = np.full(len(voxels), params.support_threshold_m)
    remaining = np.arange(len(voxels))
    min_inliers = max(3, int(params.min_support_fraction * len(voxels)))
    rng = np.random.default_rng(seed)
    planes: list[Plane] = []
    for _ in range(params.max_planes):
        if len(remaining) < min_inliers:
            break
        left = voxels[remaining]  # gathered once a plane (remaining is in index order)
        found = ransac_plane(left, params.support_threshold_m, params.support_iterations, rng)
        if found is None or len(found[1]) < min_inliers:
            break
        n, inl = found
        pts = left[inl]
        if column_span(pts).max() < params.min_plane_extent_m:
            break  # a face of an object (a box side, a can's top), not a table, floor or wall
        # Refit by least squares on the inliers; the refit plane takes the voxels within
        # their tolerance of it.
        centre = pts.mean(axis=0)
        n = np.linalg.svd(pts - centre, full_matrices=False)[2][2]
        offset = float(-n @ centre)
        near = np.abs(left @ n + offset) <= tolerance[remaining]
        mask = np.zeros(len(voxels), dtype=bool)
        mask[remaining[near]] = True
        planes.append(Plane(np.asarray(n), offset, mask, False))
        remaining = remaining[~near]
    return planes


def in_world(plane: Plane, world_from_sensor: FloatArray, params: SegmentationParams) -> Plane:
    """A plane found in the sensor frame, in the world frame: horizontal when its normal lies
    within ``max_support_tilt_deg`` of world z, and then turned up."""
    rotation, shift = world_from_sensor[:3, :3], world_from_sensor[:3, 3]
    n = rotation @ plane.normal
    horizontal = abs(float(n[2])) >= math.cos(math.radians(params.max_support_tilt_deg))
    if horizontal and n[2] < 0:
        n = -n
        return Plane(n, -plane.offset - float(n @ shift), plane.inliers, True)
    return Plane(n, plane.offset - float(n @ shift), plane.inliers, horizontal)
