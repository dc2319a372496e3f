"""Segmentation: from a raw frame to the object clusters standing on their supports.

Steps (PITT's, with its quirks fixed; see ``shared/reference/pitt-perception.md`` §4):

1. depth cut in the sensor frame, where the sensor's depth noise reaches
   ``max_range_noise_m`` (:func:`depth_cut_m`; a Kinect keeps a floor 4.4 m away, not its walls
   at 5 m). On an organised frame the depth noise is measured from the image and
   flying pixels and veils are dropped
   (:mod:`shapes.artefacts`), judged on the full-resolution image; only every k-th pixel of
   every k-th row is kept, k chosen from the points within range to leave about
   ``target_points`` points (:func:`pixel_stride`; a 640 x 480
   frame keeps one pixel in four, still about 4 to 13 per 1 cm voxel of a surface facing the
   camera at 1.5 to 0.8 m, and a cluster its hundreds of points), and the points go to the
   world frame (z up, the gravity direction);
2. voxel grid (``voxel_m``), laid in the *sensor* frame, so that the pose moves the voxels
   but never changes which points share one (the output does not depend on the pose's last
   digits): each occupied voxel becomes the mean of its points, computed in numpy so that every
   full-resolution point keeps the index of its voxel. Voxels with fewer than two occupied
   neighbours (stray returns, outliers) are set aside;
3. planes: RANSAC (numpy, seeded) finds up to ``max_planes`` planes one after another, each
   holding at least ``min_support_fraction`` of the voxels and spanning at least
   ``min_plane_extent_m`` (a smaller one is the face of an object, and the search stops).
   Threshold 1 cm, not PITT's 2 cm, which ate the bottom of every object. A plane whose
   voxels all lie above a horizontal one, less than ``max_height_m`` over it, in pieces none of
   which spans ``min_plane_extent_m``, is the fronts of objects standing in a row or the tops
   of objects of one height (seen on clean scans), not a wall or a shelf: its voxels stay free
   (``_faces_on``). Likewise a plane standing on a larger horizontal one, inside it and lower
   than ``min_support_rise_m`` (horizontal) or ``max_height_m`` (tilted) over it, is part of
   an object (a box's top, a laptop's open lid) and its voxels stay free, except a horizontal
   one less than ``floor_step_m`` over it (a rug, a seam of the floor), which joins the support
   (``_standing_on``). A plane is also judged by its connected pieces (:mod:`shapes.plane_pieces`):
   a tilted plane whose main piece stands on a larger horizontal one is an object's face, and
   its standing pieces stay free however far the plane's other voxels reach; a would-be
   support whose main piece holds under ``min_main_piece_share`` of its voxels is no support,
   and removes only its main piece's voxels (``_supports_by_pieces``);
4. **the support rule**: a support is a *horizontal* plane (normal within
   ``max_support_tilt_deg`` of world z, i.e. of gravity) *with objects on it*. Every voxel that
   belongs to no plane and lies between ``above_margin`` and ``max_height_m`` above a horizontal
   plane, inside the xy bounding box of the plane's *main piece* (its largest connected part,
   :mod:`shapes.support_region`) shrunk by ``edge_margin_m``, goes to the *nearest such plane
   below it*: objects on a table belong to the table, not to the floor under it. A cluster
   (step 6) whose centre lies outside the main piece's convex hull grown by
   ``extent_margin_m`` does not stand on the support (the back of a chair rising over a
   desk's front edge) and is dropped.
   A cluster cut by the scene's limits (``min_cut_share`` of its voxels within ``cut_band_m``
   of ``max_height_m`` over its support, or of its points near the depth cut) is a part of
   something larger (a wall, a chair's back) and is dropped too (:func:`_cut_by_limits`),
   unless it stands on the support and, grown upwards through the free voxels over the band,
   ends under ``max_tall_height_m`` in view (a rack case: :func:`_grown_upwards`), as
   is one cut by an edge of the image's valid window other than the one the camera looks down
   through (:mod:`shapes.view`), one whose bottom is seen hanging over the support (a chair's
   seat; :func:`_floats`), and one standing under any such part (a chair's base;
   :func:`_not_under`), and one on a lower support that reaches under a higher support's
   outline and whose top that support's edge hides (a desk's leg seen on the floor under its
   front edge; :mod:`shapes.support_edge`). A would-be support that crosses a larger
   horizontal plane, lying partly under it and partly over it, is no support and its voxels
   stay free (:func:`_crosses`).
   Every horizontal plane that gets clusters is reported (:attr:`Segmentation.supports`); the
   one with the most object voxels is *the* support. The largest plane (often the floor or a
   wall) wins nothing by its size;
5. the above-table margin adapts to the noise: ``above_margin = max(above_margin_m, 3 sigma)``
   with sigma the robust spread of the support's voxels about the plane; full-resolution points
   are cut at ``max(above_margin_m, 2 sigma(z))`` with ``sigma(z) = sigma_1m z²`` (measured on
   the image, or from the support's residuals on an unorganised cloud; a cloud that is not in
   a camera frame, with points at z <= 0.1 m, gets one sigma for every range);
6. statistical outlier removal and DBSCAN (open3d) on those voxels; each cluster is cut along
   its concave seams, which separates objects that touch (:mod:`shapes.split`) when every part
   reaches down to the support (a handle or a shoulder hangs above it); clusters with
   fewer than ``min_cluster_voxels`` voxels are dropped;
7. each cluster gets its full-resolution points (and colours) back through the voxel index.

When there is no cluster, :attr:`Segmentation.reason` says why in one line: no support found
(with the planes seen), or no clusters above it, or clusters too small.
"""

from __future__ import annotations

import logging
import math
from dataclasses import dataclass, replace

import numpy as np
import numpy.typing as npt
import open3d as o3d
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components
from scipy.spatial import cKDTree

from shapes.arrays import column_max, column_min, column_span, unique_inverse
from shapes.artefacts import depth_noise_1m, flying_pixels, sparse_points, sparse_voxels
from shapes.frame import Frame
from shapes.grow_upwards import grow_upwards
from shapes.nested_parts import joined_where_nested
from shapes.plane_pieces import Ground, faces_standing_on, is_scattered
from shapes.split import split_each
from shapes.support_edge import hidden_by_edge, occluders_above, reaches_under
from shapes.support_region import SupportRegion, support_region
from shapes.types import FloatArray, SupportPlane, vec3
from shapes.view import ImageView, image_view

__all__ = [
    "Cluster",
    "Segmentation",
    "SegmentationParams",
    "Survey",
    "depth_cut_m",
    "segment",
    "survey",
]

log = logging.getLogger(__name__)


@dataclass(frozen=True)
class SegmentationParams:
    """Parameters of :func:`segment`; lengths in metres."""

    voxel_m: float = 0.01
    max_depth_m: float | None = None
    """A fixed depth cut; None: the cut follows the sensor's noise (``max_range_noise_m``)."""
    max_range_noise_m: float = 0.02
    default_depth_m: float = 3.0
    """The cut when the noise is not known (an unorganised cloud, or a noiseless image)."""
    target_points: int = 60_000
    filter_artefacts: bool = True
    support_threshold_m: float = 0.01
    support_iterations: int = 500
    max_support_tilt_deg: float = 10.0
    min_support_fraction: float = 0.03
    max_planes: int = 5
    min_plane_extent_m: float = 0.25
    above_margin_m: float = 0.008
    max_height_m: float = 0.6
    max_tall_height_m: float = 1.2
    """How high a cluster that stands on its support and is cut at ``max_height_m`` may grow
    (:func:`_grown_upwards`): what ends under it is a tall object, what reaches it a part of
    something larger."""
    edge_margin_m: float = 0.02
    outlier_neighbours: int = 10
    outlier_std_ratio: float = 3.0
    cluster_eps_m: float = 0.03
    cluster_min_points: int = 3
    min_cluster_voxels: int = 12
    split_touching: bool = True
    min_split_extent_m: float = 0.07
    min_support_rise_m: float = 0.25
    max_base_height_m: float = 0.04
    floor_step_m: float = 0.03
    support_cell_m: float = 0.05
    """The grid on which a plane's voxels are joined into pieces (a support's main piece, a
    tilted plane's pieces: :mod:`shapes.plane_pieces`)."""
    min_main_piece_share: float = 0.5
    """The share of a horizontal plane's voxels its main piece must hold for the plane to be a
    surface of its own; a plane scattered in smaller pieces is reduced to its main piece
    (:func:`shapes.plane_pieces.is_scattered`)."""
    extent_margin_m: float = 0.05
    """How far past the hull of its support's main piece an object's centre may lie."""
    cut_band_m: float = 0.03
    """How near the scene's limits (``max_height_m`` over the support, the depth cut) a voxel
    or point counts as reaching them (the depth cut's band grows to 3 sigma of the noise)."""
    min_cut_share: float = 0.01
    """The share of a cluster's voxels (or points) reaching a limit that makes it cut by it,
    and so a part of something larger than the scene, not an object."""
    min_cut_voxels: int = 3
    """As ``min_cut_share``, a count: one stray voxel at the limit cuts nothing."""
    border_band_px: int = 8
    """How near an edge of the image's valid window (other than the edge the camera looks
    down through) a point counts as cut by it (:mod:`shapes.view`): four sampled pixels at a
    640 x 480 frame's stride of 2; the window's edge itself wanders by a few pixels where
    flying pixels were dropped."""
    floating_probe_px: int = 8
    """How far past a cluster's lower outline in the image something nearer is looked for,
    which hides its bottom (:func:`_floats`)."""
    min_hidden_share: float = 0.5
    """The share of a cluster's lower outline that something nearer must hide for a bottom
    seen above ``max_base_height_m`` to be hidden rather than hanging (:func:`_floats`)."""
    support_edge_depth_m: float = 0.08
    """How far under a support's plane its edge reaches (the top's thickness, its front face,
    an apron): what hides the top of a cluster on a lower support from that high up is the
    support's edge, and the cluster stands under it (:mod:`shapes.support_edge`)."""
    min_edge_hidden_share: float = 0.5
    """The share of a cluster's upper outline that a higher support's edge must hide for the
    cluster to stand under that edge (:mod:`shapes.support_edge`); the same half as
    ``min_hidden_share`` asks of a lower outline."""


@dataclass(frozen=True, eq=False)
class Cluster:
    """The full-resolution points of one object, in the world frame, and its support."""

    points: FloatArray
    colours: FloatArray | None
    voxels: FloatArray
    support: SupportPlane | None = None
    noise_m: float = 0.0
    """The depth noise (one sigma) expected at the cluster's range, in metres."""
    pixels: npt.NDArray[np.intp] | None = None
    """The flat row-major image pixel of each point, on an organised frame."""

    @property
    def centroid(self) -> FloatArray:
        """The mean of the points (PITT's visual centroid, without its n+1 bug)."""
        return np.asarray(self.points.mean(axis=0), dtype=np.float64)


@dataclass(frozen=True, eq=False)
class Segmentation:
    """What :func:`segment` found: the support plane (None if none), the clusters on every
    support, the supports that carry clusters, the depth noise at 1 m, and, when there is no
    cluster, the reason in one line."""

    support: SupportPlane | None
    clusters: tuple[Cluster, ...]
    supports: tuple[SupportPlane, ...] = ()
    noise_1m: float = 0.0
    reason: str | None = None


def voxel_grid(points: FloatArray, voxel_m: float) -> tuple[FloatArray, npt.NDArray[np.intp]]:
    """Voxel means and, for each input point, the index of its voxel.

    >>> means, index = voxel_grid(np.array([[0.001, 0, 0], [0.003, 0, 0], [0.5, 0, 0]]), 0.01)
    >>> means.round(3).tolist(), index.tolist()
    ([[0.002, 0.0, 0.0], [0.5, 0.0, 0.0]], [0, 0, 1])
    """
    keys = np.floor(points / voxel_m).astype(np.int64)
    keys -= column_min(keys)
    span = column_max(keys) + 1
    flat = (keys[:, 0] * span[1] + keys[:, 1]) * span[2] + keys[:, 2]
    _, index, counts = unique_inverse(flat)
    means = np.empty((len(counts), 3))
    for axis in range(3):
        means[:, axis] = np.bincount(index, weights=points[:, axis]) / counts
    return means, index.astype(np.intp)


def _cloud(points: FloatArray) -> o3d.geometry.PointCloud:
    return o3d.geometry.PointCloud(o3d.utility.Vector3dVector(points))


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
    points when there are more. It stops early, as usual, once the
    samples scored make a better plane unlikely (``_CONFIDENCE``, from the best inlier ratio so
    far). Returns the unit normal and the indices of its points, or None if no sample spans a
    plane.

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
    best, best_count = 0, -1
    within = np.empty((_HYPOTHESES_PER_PASS, len(points)), dtype=np.float32)
    ones = np.ones(len(points), dtype=np.float32)
    for start in range(0, len(normals), _HYPOTHESES_PER_PASS):
        stop = start + _HYPOTHESES_PER_PASS
        # One row per hypothesis, summed along the row: a count down the columns of the
        # transposed matrix (np.count_nonzero with an axis) took seven times as long. The
        # count is a float32 matrix-vector product of the 0/1 matrix (exact below 2**24),
        # cheaper than numpy's sum of booleans.
        distances = normals[start:stop] @ points.T
        distances += offsets[start:stop, None]
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
class _Plane:
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
) -> list[_Plane]:
    """Up to ``max_planes`` planes, one after another on what the previous ones left, each
    refitted by least squares, in the frame of ``voxels`` (none is marked horizontal: that
    takes a pose, :func:`_in_world`).

    ``tolerance``: per voxel, how far from a plane it may lie and still belong to it (the
    depth noise grows with the range); by default ``support_threshold_m``.
    """
    if tolerance is None:
        tolerance = np.full(len(voxels), params.support_threshold_m)
    remaining = np.arange(len(voxels))
    min_inliers = max(3, int(params.min_support_fraction * len(voxels)))
    rng = np.random.default_rng(seed)
    planes: list[_Plane] = []
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
        planes.append(_Plane(np.asarray(n), offset, mask, False))
        remaining = remaining[~near]
    return planes


def _in_world(plane: _Plane, world_from_sensor: FloatArray, params: SegmentationParams) -> _Plane:
    """A plane found in the sensor frame, in the world frame: horizontal when its normal lies
    within ``max_support_tilt_deg`` of world z, and then turned up."""
    rotation, shift = world_from_sensor[:3, :3], world_from_sensor[:3, 3]
    n = rotation @ plane.normal
    horizontal = abs(float(n[2])) >= math.cos(math.radians(params.max_support_tilt_deg))
    if horizontal and n[2] < 0:
        n = -n
        return _Plane(n, -plane.offset - float(n @ shift), plane.inliers, True)
    return _Plane(n, plane.offset - float(n @ shift), plane.inliers, horizontal)


@dataclass(frozen=True, eq=False)
class Survey:
    """What segmentation finds before it needs a pose, all in the sensor frame: the points
    kept (artefacts dropped, strided), their range, their voxel grid and the planes among the
    voxels. Computed once per frame and shared by :func:`shapes.gravity.gravity_from_survey`
    (which way is up) and :func:`segment`."""

    keep: npt.NDArray[np.bool_]
    """Which of the frame's points are kept."""
    points: FloatArray
    depth: FloatArray
    """Each kept point's range (its z), or 1 for every point of a cloud not in a camera's
    frame (points at z <= 0.1 m), whose ranges are unknown."""
    voxels: FloatArray
    voxel_of: npt.NDArray[np.intp]
    tolerance: FloatArray
    """Per voxel, how far from a plane it may lie and still belong to it."""
    planes: tuple[_Plane, ...]
    sigma_1m: float
    in_camera_frame: bool
    reason: str | None = None
    """Why nothing can be found (no point within range), else None."""
    depth_image: FloatArray | None = None
    """Every depth of an organised frame as its image, NaN where there is none (and, when
    artefacts are filtered, beyond the depth cut)."""


def _nothing_to_survey(keep: npt.NDArray[np.bool_], frame: Frame, reason: str) -> Survey:
    empty = np.zeros((0, 3))
    return Survey(
        keep,
        empty,
        np.zeros(0),
        empty,
        np.zeros(0, dtype=np.intp),
        np.zeros(0),
        (),
        0.0,
        frame.pixels is not None,
        reason,
    )


def survey(frame: Frame, params: SegmentationParams, seed: int) -> Survey:
    """Steps 1 to 3 of the module doc in the sensor frame: the kept points, their voxel grid
    and the planes. Deterministic for a given ``seed``; the frame's pose plays no part."""
    sigma_1m = 0.0
    image = None if frame.pixels is None else _depth_image(frame)
    if params.filter_artefacts and image is not None:
        sigma_1m = depth_noise_1m(image)
    cut = depth_cut_m(sigma_1m, params)
    keep = frame.points[:, 2] <= cut
    if not keep.any():
        return _nothing_to_survey(keep, frame, f"no point within {cut:.2f} m")
    # The stride comes from the points within range: the artefacts are then judged only on
    # the pixels it keeps (a quarter of them at stride 2).
    stride = pixel_stride(int(keep.sum()), params)
    if frame.pixels is None or frame.image_shape is None:
        stride = 1
    if params.filter_artefacts and image is not None:
        image[image > cut] = np.nan  # nothing beyond the cut is nearer than what it keeps
        keep &= _artefact_mask(frame, image, sigma_1m, stride)
        if not keep.any():
            reason = f"no point within {cut:.2f} m but flying pixels and veils"
            return _nothing_to_survey(keep, frame, reason)
    elif stride > 1:
        assert frame.image_shape is not None
        on_grid = np.zeros(frame.image_shape, dtype=np.bool_)
        on_grid[::stride, ::stride] = True
        keep &= on_grid.ravel()[frame.pixels]
    points = np.compress(keep, frame.points, axis=0)  # frame.points[keep], at a fifth of the cost
    depth = points[:, 2]
    in_camera_frame = frame.pixels is not None or bool((depth > 0.1).all())
    if not in_camera_frame:
        # Not in a camera's frame (e.g. a cloud already in the world frame): the range of each
        # point is unknown, so the noise is taken as the same everywhere.
        depth = np.ones(len(depth))
    # The grid is laid in the sensor frame, where the points were measured: laid in the world
    # frame, a point on a cell boundary changes cells with the least change of the pose, and
    # every fit downstream with it.
    voxels, voxel_of = voxel_grid(points, params.voxel_m)
    counts = np.bincount(voxel_of, minlength=len(voxels))
    voxel_depth = np.bincount(voxel_of, weights=depth, minlength=len(voxels)) / counts
    tolerance = np.maximum(params.support_threshold_m, 3 * sigma_1m * voxel_depth**2)
    planes = find_planes(voxels, params, seed, tolerance)
    return Survey(
        keep,
        points,
        depth,
        voxels,
        voxel_of,
        tolerance,
        tuple(planes),
        sigma_1m,
        in_camera_frame,
        depth_image=image,
    )


_FACES_LINK_M = 0.025
"""Voxels of a plane closer than this are one piece of it (see _faces_on)."""


def _faces_on(inliers: FloatArray, below: list[_Plane], params: SegmentationParams) -> bool:
    """Whether a plane's voxels are the faces of objects standing on one of the ``below``
    horizontal planes, rather than a table, wall or shelf of its own.

    Objects standing in a row show fronts that line up into a plane wider than
    ``min_plane_extent_m``, and objects of one height show tops in one horizontal plane. Such a
    plane lies above a horizontal plane (all its voxels but 2 %), less than ``max_height_m``
    over it, and falls apart into pieces (voxels ``_FACES_LINK_M`` apart) of which none spans
    ``min_plane_extent_m``: a table or a wall is one piece that wide.
    """
    heights = (inliers @ plane.normal + plane.offset for plane in below)
    if not any(
        np.percentile(h, 2.0) > -params.support_threshold_m and float(h.max()) < params.max_height_m
        for h in heights
    ):
        return False
    pairs = cKDTree(inliers).query_pairs(_FACES_LINK_M, output_type="ndarray")
    graph = coo_matrix((np.ones(len(pairs)), (pairs[:, 0], pairs[:, 1])), (len(inliers),) * 2)
    _, piece = connected_components(graph, directed=False)
    order = np.argsort(piece, kind="stable")
    starts = np.flatnonzero(np.r_[True, np.diff(piece[order]) != 0])
    span = np.maximum.reduceat(inliers[order], starts) - np.minimum.reduceat(inliers[order], starts)
    return bool(span.max() < params.min_plane_extent_m)


def _standing_on(
    points: FloatArray, plane: _Plane, level: list[_Plane], params: SegmentationParams
) -> float | None:
    """How high (median, metres) a plane stands over a larger horizontal plane that carries it
    as part of an object, or None when it is a support, a wall or a shelf of its own.

    ``points`` are the voxels the planes' inlier masks index. A plane is part of what stands on
    a larger horizontal plane when all its voxels but 2 % lie above it, over it (inside its
    bounding box shrunk by ``edge_margin_m``) and lower than ``min_support_rise_m`` (a
    horizontal plane) or ``max_height_m`` (a tilted one) over it: the top of a box, the open
    lid of a laptop, a book lying flat. A table stands higher than ``min_support_rise_m`` over
    the floor; a wall rises at the edge of the floor or table it meets, not inside it.
    """
    mine = points[plane.inliers]
    for other in level:
        if other is plane or int(other.inliers.sum()) <= int(plane.inliers.sum()):
            continue
        height = mine @ other.normal + other.offset
        limit = params.min_support_rise_m if plane.horizontal else params.max_height_m
        if np.percentile(height, 2.0) <= -params.support_threshold_m:
            continue
        if np.percentile(height, 98.0) >= limit:
            continue
        if plane.horizontal and np.median(height) < params.floor_step_m:
            return float(np.median(height))  # a step of the support, wherever it lies
        base = points[other.inliers][:, :2]
        lo = column_min(base) + params.edge_margin_m
        hi = column_max(base) - params.edge_margin_m
        x, y = mine[:, 0], mine[:, 1]
        inside = (x > lo[0]) & (x < hi[0]) & (y > lo[1]) & (y < hi[1])
        if inside.mean() < 0.98:
            continue
        return float(np.median(height))
    return None


def _supports_by_pieces(
    planes: list[_Plane],
    candidates: list[_Plane],
    level: list[_Plane],
    faces: set[int],
    voxels: FloatArray,
    params: SegmentationParams,
) -> tuple[list[_Plane], dict[int, SupportRegion], set[int]]:
    """The planes with every scattered one of the would-be supports (``candidates``) reduced
    to its main piece (:func:`shapes.plane_pieces.is_scattered`), the region of each of the
    others by its id, and the ids of the scattered ones, which are no support.

    A scattered plane's other voxels belong to other things and stay free. Its main piece is
    judged again as a plane of its own (:func:`_standing_on`): the top of an object (its id
    is added to ``faces``, and its voxels stay free too), else a strip of a surface already
    found or too small to tell, whose voxels are removed."""
    judged, regions, scattered = [], {}, set()
    for plane in planes:
        if any(plane is q for q in candidates):
            inliers = np.flatnonzero(plane.inliers)
            region = support_region(voxels[inliers, :2], params.support_cell_m)
            if is_scattered(region, params.min_main_piece_share):
                kept = np.zeros_like(plane.inliers)
                kept[inliers[region.piece]] = True
                main = replace(plane, inliers=kept)
                others = [main if q is plane else q for q in level]
                below = _standing_on(voxels, main, others, params)
                if below is not None and below >= params.floor_step_m:
                    faces.add(id(main))
                scattered.add(id(main))
                plane = main
            else:
                regions[id(plane)] = region
        judged.append(plane)
    return judged, regions, scattered


def _crosses(
    plane: _Plane,
    region: SupportRegion,
    level: list[_Plane],
    voxels: FloatArray,
    tolerance: FloatArray,
    params: SegmentationParams,
) -> bool:
    """Whether a would-be support (its main piece: ``region``) crosses a larger one of the
    ``level`` planes: more than ``min_cut_share`` of the main piece's voxels lie under that
    plane by more than their ``tolerance``, and as many over it. Two supports are two levels
    (a table over the floor, a shelf over a desk): the one lies wholly over the other. A
    plane a few degrees off a desk's, which RANSAC finds through the desk's near strip, the
    things standing on it and the space under its edge, runs from under the desk to over it:
    it is no surface of its own, and what it holds over the desk belongs to the desk's
    objects."""
    mine = np.flatnonzero(plane.inliers)[region.piece]
    for other in level:
        if other is plane or int(other.inliers.sum()) <= int(plane.inliers.sum()):
            continue
        height = voxels[mine] @ other.normal + other.offset
        under = float(np.mean(height < -tolerance[mine]))
        over = float(np.mean(height > tolerance[mine]))
        if min(under, over) > params.min_cut_share:
            return True
    return False


def _robust_sigma(values: FloatArray) -> float:
    if len(values) == 0:
        return 0.0
    return float(1.4826 * np.median(np.abs(values - np.median(values))))


def _focal_px(frame: Frame) -> float:
    """The focal length in pixels of an organised frame, from its points and pixel columns."""
    assert frame.image_shape is not None and frame.pixels is not None
    every = max(1, len(frame.pixels) // 2000)
    u = (frame.pixels[::every] % frame.image_shape[1]).astype(np.float64)
    slope = frame.points[::every, 0] / frame.points[::every, 2]
    if np.ptp(u) == 0:
        return 570.0
    a = np.polyfit(u, slope, 1)[0]
    return float(1.0 / a) if a > 0 else 570.0


def _depth_image(frame: Frame) -> FloatArray:
    """The depths of an organised frame's points as its image, NaN where there is no point."""
    assert frame.image_shape is not None and frame.pixels is not None
    image = np.full(frame.image_shape[0] * frame.image_shape[1], np.nan)
    image[frame.pixels] = frame.points[:, 2]
    return image.reshape(frame.image_shape)


def _artefact_mask(
    frame: Frame, image: FloatArray, sigma_1m: float, stride: int
) -> npt.NDArray[np.bool_]:
    """Which of an organised frame's points lie on every ``stride``-th pixel of every
    ``stride``-th row and are neither flying pixels nor veils of ``image`` (its depths, NaN
    where there is none)."""
    assert frame.pixels is not None
    on_grid = np.zeros(image.shape, dtype=np.bool_)
    drop = flying_pixels(image, sigma_1m, focal_px=_focal_px(frame), step=stride)
    on_grid[::stride, ::stride] = ~drop
    return np.asarray(on_grid.ravel()[frame.pixels], dtype=np.bool_)


def depth_cut_m(sigma_1m: float, params: SegmentationParams) -> float:
    """The range beyond which points are dropped: ``max_depth_m`` when set, else where the
    depth noise ``sigma_1m z²`` reaches ``max_range_noise_m`` (``default_depth_m`` when the
    noise is not known).

    >>> params = SegmentationParams()
    >>> round(depth_cut_m(0.001, params), 2), depth_cut_m(0.0, params)
    (4.47, 3.0)
    """
    if params.max_depth_m is not None:
        return params.max_depth_m
    if sigma_1m <= 0.0:
        return params.default_depth_m
    return math.sqrt(params.max_range_noise_m / sigma_1m)


def pixel_stride(points: int, params: SegmentationParams) -> int:
    """The pixel stride that brings an organised frame of ``points`` valid points near
    ``target_points`` (1: every pixel, as with ``target_points <= 0``).

    >>> [pixel_stride(n, SegmentationParams()) for n in (40_000, 145_000, 307_200, 1_000_000)]
    [1, 2, 2, 4]
    """
    if params.target_points <= 0:
        return 1
    return max(1, round(math.sqrt(points / params.target_points)))


def segment(
    frame: Frame,
    params: SegmentationParams | None = None,
    seed: int = 0,
    *,
    surveyed: Survey | None = None,
) -> Segmentation:
    """Find the supports and the object clusters on them in one frame (see the module doc).

    ``surveyed``: the frame's :func:`survey` with the same ``params`` and ``seed``, when the
    caller has it already (the pipeline takes up from it first).
    """
    params = params or SegmentationParams()
    scan = surveyed if surveyed is not None else survey(frame, params, seed)
    if scan.reason is not None:
        return Segmentation(None, (), reason=scan.reason)
    keep, depth, sigma_1m, voxel_of = scan.keep, scan.depth, scan.sigma_1m, scan.voxel_of
    pixels = None if frame.pixels is None else frame.pixels[keep]
    reach = _Reach(
        frame.world_from_sensor if scan.in_camera_frame else None,
        depth_cut_m(sigma_1m, params),
        max(params.cut_band_m, 3 * sigma_1m * depth_cut_m(sigma_1m, params) ** 2),
        None
        if frame.pixels is None or frame.image_shape is None or not scan.in_camera_frame
        else image_view(frame.image_shape, frame.pixels, frame.world_from_sensor[:3, :3]),
        scan.depth_image,
    )
    points = frame.world_points_of(scan.points)
    voxels = frame.world_points_of(scan.voxels)
    viewpoint = frame.world_from_sensor[:3, 3] if scan.in_camera_frame else None
    # The frame's colours and which point of the frame each kept point is: a cluster's
    # colours are gathered from the frame's (all the kept points' would cost a pass over it).
    colours = None if frame.colours is None else (frame.colours, np.flatnonzero(keep))
    planes = [_in_world(p, frame.world_from_sensor, params) for p in scan.planes]
    level = [p for p in planes if p.horizontal]
    faces = {
        id(p)
        for p in planes
        if _faces_on(voxels[p.inliers], [q for q in level if q is not p], params)
    }
    steps: set[int] = set()
    for p in planes:
        if id(p) in faces:
            continue
        below = _standing_on(voxels, p, level, params)
        if below is None:
            continue
        if p.horizontal and below < params.floor_step_m:
            steps.add(id(p))  # a rug or a seam of the floor: part of the support under it
        else:
            faces.add(id(p))  # the top or the side of an object standing on a support
    horizontal = [p for p in level if id(p) not in faces and id(p) not in steps]
    planes, region_of, scattered = _supports_by_pieces(
        planes, horizontal, level, faces, voxels, params
    )
    horizontal = [p for p in planes if p.horizontal and id(p) not in faces | steps | scattered]
    crossing = {
        id(p)
        for p in horizontal
        if _crosses(p, region_of[id(p)], horizontal, voxels, scan.tolerance, params)
    }
    faces |= crossing  # a slice through a support and what stands on it: its voxels stay free
    horizontal = [p for p in horizontal if id(p) not in crossing]
    if not horizontal:
        seen = "; ".join(p.describe() for p in planes) or "none"
        log.info("no horizontal support plane in %d voxels", len(voxels))
        return Segmentation(
            None,
            (),
            noise_1m=sigma_1m,
            reason=f"no support found: no horizontal plane among the planes seen ({seen})",
        )
    grounds = [
        Ground(p.normal, p.offset, region_of[id(p)], int(region_of[id(p)].piece.sum()))
        for p in horizontal
    ]
    in_plane = np.zeros(len(voxels), dtype=bool)
    for p in planes:
        if id(p) in faces:  # the fronts or tops of objects stay free
            continue
        in_plane[p.inliers] = True
        if not p.horizontal:  # and so do the pieces of a tilted plane that stand on a support
            inliers = np.flatnonzero(p.inliers)
            faces_of_objects = faces_standing_on(
                voxels[inliers],
                scan.tolerance[inliers],
                p.normal,
                grounds,
                cell_m=params.support_cell_m,
                max_height_m=params.max_height_m,
                edge_margin_m=params.edge_margin_m,
                min_voxels=params.min_cluster_voxels,
            )
            in_plane[inliers[faces_of_objects]] = False
    free = ~in_plane
    # Stray returns and outliers: free voxels with fewer than two occupied neighbours.
    free_idx = np.flatnonzero(free)
    stray = sparse_voxels(scan.voxels[free_idx], params.voxel_m, among=scan.voxels)
    free[free_idx[stray]] = False
    # Each free voxel goes to the nearest horizontal plane below it that covers it.
    best_height = np.full(len(voxels), np.inf)
    owner = np.full(len(voxels), -1)
    margins, supports, regions, boxes = [], [], [], []
    for k, p in enumerate(horizontal):
        table = voxels[p.inliers]
        region = region_of[id(p)]
        regions.append(region)
        table = table[region.piece]
        span = column_span(table[:, :2])
        centre = table.mean(axis=0)
        support = SupportPlane(
            vec3(p.normal),
            p.offset,
            vec3(centre - (centre @ p.normal + p.offset) * p.normal),
            (float(span[0]), float(span[1])),
        )
        supports.append(support)
        sigma_vox = _robust_sigma(support.signed_distance(table))
        margin = max(params.above_margin_m, 3 * sigma_vox)
        margins.append(margin)
        height = support.signed_distance(voxels)
        lo = column_min(table[:, :2]) + params.edge_margin_m
        hi = column_max(table[:, :2]) - params.edge_margin_m
        boxes.append((lo, hi))
        over = (
            free
            & (height > margin)
            & (height < params.max_height_m)
            & (voxels[:, 0] > lo[0])
            & (voxels[:, 0] < hi[0])
            & (voxels[:, 1] > lo[1])
            & (voxels[:, 1] < hi[1])
            & (height < best_height)
        )
        best_height[over] = height[over]
        owner[over] = k
    if sigma_1m == 0.0:
        # Unorganised: the noise from the full-resolution residuals of the biggest support.
        main = max(range(len(horizontal)), key=lambda k: int(horizontal[k].inliers.sum()))
        on = np.zeros(len(voxels), dtype=bool)
        on[horizontal[main].inliers] = True
        sel = on[voxel_of]
        if sel.sum() > 100:
            resid = supports[main].signed_distance(points[sel])
            sigma_1m = _robust_sigma(resid) / float(np.median(depth[sel] ** 2))
    clusters: list[Cluster] = []
    too_small = above = 0
    votes = np.zeros(len(horizontal), dtype=np.int64)
    kept: list[list[Cluster]] = []
    for k, support in enumerate(supports):
        candidates = np.flatnonzero(owner == k)
        above += len(candidates)
        if len(candidates) < params.min_cluster_voxels:
            kept.append([])
            continue
        found, small = _clusters(
            candidates,
            voxels,
            voxel_of,
            points,
            depth,
            colours,
            pixels,
            support,
            margins[k],
            sigma_1m,
            params,
            frame.pixels is not None and params.filter_artefacts,
            viewpoint,
        )
        too_small += small
        found = [c for c in found if _stands_within(c, regions[k], params)]
        found = _grown_upwards(
            found,
            free & (owner < 0),
            boxes[k],
            voxels,
            voxel_of,
            points,
            depth,
            colours,
            pixels,
            reach,
            margins[k],
            sigma_1m,
            params,
        )
        found = [c for c in found if _stands_within(c, regions[k], params)]
        parts = [
            c
            for c in found
            if _cut_by_limits(c, reach, params) or _floats(c, reach, margins[k], params)
        ]
        kept.append(_not_under(found, parts, support, params))
    kept = _not_under_support_edges(kept, supports, regions, frame, reach, params)
    for k, found in enumerate(kept):
        votes[k] = sum(len(c.voxels) for c in found)
        clusters += found
    with_objects = [supports[k] for k in np.argsort(-votes, kind="stable") if votes[k] > 0]
    primary = (
        with_objects[0]
        if with_objects
        else supports[max(range(len(horizontal)), key=lambda k: int(horizontal[k].inliers.sum()))]
    )
    reason = None
    if not clusters:
        if above < params.min_cluster_voxels:
            reason = (
                f"no clusters above the support: {above} voxels above "
                f"{len(horizontal)} horizontal plane(s)"
            )
        elif too_small:
            reason = (
                f"clusters rejected: {too_small} cluster(s) smaller than "
                f"{params.min_cluster_voxels} voxels"
            )
        else:
            reason = (
                f"no clusters above the support: {above} voxels above it, all stray points "
                "or outliers"
            )
    log.debug("segmented %d points into %d clusters", len(points), len(clusters))
    return Segmentation(primary, tuple(clusters), tuple(with_objects), sigma_1m, reason)


def _cut_at_band_top(cluster: Cluster, params: SegmentationParams) -> bool:
    """Whether a cluster within the height band reaches its top (``min_cut_share`` of its
    voxels, and ``min_cut_voxels``, within ``cut_band_m`` of ``max_height_m``)."""
    assert cluster.support is not None
    height = cluster.support.signed_distance(cluster.voxels)
    return _reaching(height >= params.max_height_m - params.cut_band_m, params)


def _above_band(
    voxels: FloatArray,
    free: npt.NDArray[np.bool_],
    support: SupportPlane,
    box: tuple[FloatArray, FloatArray],
    params: SegmentationParams,
) -> npt.NDArray[np.intp]:
    """The ``free`` voxels over the height band of ``support`` and under
    ``max_tall_height_m``, inside ``box`` (across the support): where a cluster cut at the
    band's top may go on."""
    lo, hi = box
    x, y = voxels[:, 0], voxels[:, 1]
    idx = np.flatnonzero(free & (x > lo[0]) & (x < hi[0]) & (y > lo[1]) & (y < hi[1]))
    height = support.signed_distance(voxels[idx])
    return idx[(height >= params.max_height_m) & (height < params.max_tall_height_m)]


def _seen_standing(cluster: Cluster, margin_m: float, params: SegmentationParams) -> bool:
    """Whether a cluster's lowest voxel lies on its support: less than ``max_base_height_m``
    over the lowest an object's voxel can lie (``margin_m``). Unlike :func:`_floats`, a bottom
    hidden behind something nearer does not count: it may be anything's upper part."""
    assert cluster.support is not None
    lowest = float(cluster.support.signed_distance(cluster.voxels).min())
    return lowest < margin_m + params.max_base_height_m


def _goes_on_above(cluster: Cluster, reach: _Reach, params: SegmentationParams) -> bool:
    """Whether a cluster grown over the band goes on past its top in the image: on at least
    ``min_hidden_share`` of its lines across the image, no pixel within ``floating_probe_px``
    past its pixel farthest from the open edge holds a depth beyond that pixel's by more than
    ``cut_band_m`` (or three times its noise). An object that ends shows what lies behind it
    there; a person's hips under the shirt a plane took, or a thing against something as near,
    do not. False when the image is unknown."""
    if (
        reach.view is None
        or reach.depth_image is None
        or reach.world_from_sensor is None
        or cluster.pixels is None
    ):
        return False
    view, image = reach.view, reach.depth_image
    rotation, shift = reach.world_from_sensor[:3, :3], reach.world_from_sensor[:3, 3]
    depth = (cluster.points - shift) @ rotation[:, 2]
    row, col = np.divmod(np.asarray(cluster.pixels), view.width)
    vertical = view.open_edge in ("top", "bottom")
    along, across = (row, col) if vertical else (col, row)
    limit = image.shape[0] if vertical else view.width
    sign = -1 if view.open_edge in ("bottom", "right") else 1  # away from the open edge
    order = np.lexsort((along * sign, across))
    ends = order[np.r_[across[order][1:] != across[order][:-1], True]]
    margin = max(params.cut_band_m, 3 * cluster.noise_m)
    behind = np.zeros(len(ends), dtype=np.bool_)
    for step in range(1, params.floating_probe_px + 1):
        beyond = along[ends] + sign * step
        inside = (beyond >= 0) & (beyond < limit)
        r, c = (beyond, across[ends]) if vertical else (across[ends], beyond)
        found = image[r[inside], c[inside]] > depth[ends][inside] + margin
        behind[np.flatnonzero(inside)[found]] = True
    on = ~behind
    return bool(len(ends)) and float(on.mean()) >= params.min_hidden_share


def _grown_upwards(
    found: list[Cluster],
    free: npt.NDArray[np.bool_],
    box: tuple[FloatArray, FloatArray],
    voxels: FloatArray,
    voxel_of: npt.NDArray[np.intp],
    points: FloatArray,
    depth: FloatArray,
    colours: tuple[FloatArray, npt.NDArray[np.intp]] | None,
    pixels: npt.NDArray[np.intp] | None,
    reach: _Reach,
    margin_m: float,
    sigma_1m: float,
    params: SegmentationParams,
) -> list[Cluster]:
    """``found`` (clusters on one support) with each cluster seen standing on it
    (:func:`_seen_standing`) and cut at the band's top (:func:`_cut_at_band_top`) grown
    upwards: joined with the ``free`` voxels over the band (:func:`_above_band`, inside ``box``
    and no farther across the support from the clusters that grow than the band's rise,
    ``max_tall_height_m - max_height_m``) that link to it within ``cluster_eps_m``
    (:func:`shapes.grow_upwards.grow_upwards`). Clusters that the voxels above join become one,
    in the first one's place. A group that reaches ``max_tall_height_m`` (``min_cut_share`` of
    its voxels within ``cut_band_m`` of it), or goes on past its top in the image
    (:func:`_goes_on_above`), does not end, and its clusters are left as they were, cut: a
    wall, a door, a person. Clusters that hang or stay within the band are left as
    they are: only what stands may reach higher, so the voxels above the band never join a
    stray part to anything."""
    seeds = [
        k
        for k, c in enumerate(found)
        if _cut_at_band_top(c, params) and _seen_standing(c, margin_m, params)
    ]
    if not seeds:
        return list(found)
    support = found[seeds[0]].support
    assert support is not None
    rise = params.max_tall_height_m - params.max_height_m
    every = np.vstack([found[k].voxels[:, :2] for k in seeds])
    lo = np.maximum(box[0], column_min(every) - rise)
    hi = np.minimum(box[1], column_max(every) + rise)
    tall = _above_band(voxels, free, support, (lo, hi), params)
    if len(tall) == 0:
        return list(found)
    groups = grow_upwards([found[k].voxels for k in seeds], voxels[tall], params.cluster_eps_m)
    top = support.signed_distance(voxels[tall]) >= params.max_tall_height_m - params.cut_band_m
    grown: dict[int, Cluster] = {}
    dropped: set[int] = set()
    for members, added in groups:
        ks = [seeds[m] for m in members]
        size = len(added) + sum(len(found[k].voxels) for k in ks)
        if len(added) == 0 or (
            int(top[added].sum()) >= params.min_cut_voxels
            and int(top[added].sum()) >= params.min_cut_share * size
        ):
            continue
        marked = np.zeros(len(voxels), dtype=np.bool_)
        marked[tall[added]] = True
        idx = np.flatnonzero(marked[voxel_of])
        parts = [found[k] for k in ks]
        first = parts[0]
        whole = Cluster(
            np.vstack([*(c.points for c in parts), points[idx]]),
            None
            if colours is None or first.colours is None
            else np.vstack(
                [*(c.colours for c in parts if c.colours is not None), colours[0][colours[1][idx]]]
            ),
            np.vstack([*(c.voxels for c in parts), voxels[tall[added]]]),
            first.support,
            max([c.noise_m for c in parts] + [sigma_1m * float(np.median(depth[idx])) ** 2]),
            None
            if pixels is None or first.pixels is None
            else np.concatenate([*(c.pixels for c in parts if c.pixels is not None), pixels[idx]]),
        )
        if _goes_on_above(whole, reach, params):
            continue
        grown[ks[0]] = whole
        dropped.update(ks[1:])
    return [grown.get(k, c) for k, c in enumerate(found) if k not in dropped]


def _stands_within(cluster: Cluster, region: SupportRegion, params: SegmentationParams) -> bool:
    """Whether a cluster stands within its support's outline (its voxels' centre across the
    support inside the main piece's hull grown by ``extent_margin_m``): the back of a chair
    rising over the edge of a desk, or a wall behind it, does not."""
    centre = cluster.voxels[:, :2].mean(axis=0)
    return bool(region.contains(centre[None, :], params.extent_margin_m)[0])


@dataclass(frozen=True)
class _Reach:
    """How far the scene reaches in depth: the frame's pose (None when the points' ranges are
    unknown), the depth cut and how near it a point counts as reaching it."""

    world_from_sensor: FloatArray | None
    depth_cut_m: float
    band_m: float
    view: ImageView | None = None
    """The image's valid window (None for a cloud that is not a camera's image)."""
    depth_image: FloatArray | None = None
    """The survey's depth image (:attr:`Survey.depth_image`)."""


def _reaching(near: npt.NDArray[np.bool_], params: SegmentationParams) -> bool:
    count = int(near.sum())
    return count >= params.min_cut_voxels and count >= params.min_cut_share * len(near)


def _cut_by_limits(cluster: Cluster, reach: _Reach, params: SegmentationParams) -> bool:
    """Whether a cluster is cut by the scene's limits, and so is a part of something larger
    (a wall, a door, a chair's back, a person's legs), not an object: at least
    ``min_cut_share`` of its voxels (and ``min_cut_voxels``) lie within ``cut_band_m`` of
    ``max_height_m`` over its support (``max_tall_height_m`` for a cluster grown over the band,
    :func:`_grown_upwards`), or as large a share of its points within
    ``reach.band_m`` of the depth cut, or within ``border_band_px`` of an edge of the image's
    valid window other than the one the camera looks down through, on a line where nothing
    behind it (:func:`_behind_m`) shows between it and that edge
    (:meth:`shapes.view.ImageView.cut_at_closed_edge`)."""
    assert cluster.support is not None
    height = cluster.support.signed_distance(cluster.voxels)
    # Only a cluster grown upwards (:func:`_grown_upwards`) rises over the band: its limit is
    # the higher one.
    limit = params.max_tall_height_m if height.max() >= params.max_height_m else params.max_height_m
    if _reaching(height >= limit - params.cut_band_m, params):
        return True
    if (
        reach.view is not None
        and cluster.pixels is not None
        and _reaching(reach.view.at_closed_edge(cluster.pixels, params.border_band_px), params)
        and (
            reach.depth_image is None
            or _reaching(
                reach.view.cut_at_closed_edge(
                    cluster.pixels,
                    params.border_band_px,
                    reach.depth_image,
                    _behind_m(cluster, reach.depth_image, params),
                ),
                params,
            )
        )
    ):
        return True
    if reach.world_from_sensor is None:
        return False
    rotation, shift = reach.world_from_sensor[:3, :3], reach.world_from_sensor[:3, 3]
    depth = (cluster.points - shift) @ rotation[:, 2]
    return _reaching(depth >= reach.depth_cut_m - reach.band_m, params)


def _behind_m(cluster: Cluster, depth_image: FloatArray, params: SegmentationParams) -> float:
    """How much farther than a cluster's outline a depth must lie to be something seen behind
    it: ``cut_band_m`` (or three times its noise), and no less than the cluster's own depth
    extent, so that a surface receding towards the image's edge (a chair's leg, the floor
    round a wheel) does not pass for a background behind the cluster."""
    assert cluster.pixels is not None
    extent_m = float(np.ptp(depth_image.ravel()[cluster.pixels]))
    return max(params.cut_band_m, 3 * cluster.noise_m, extent_m)


def _floats(cluster: Cluster, reach: _Reach, margin_m: float, params: SegmentationParams) -> bool:
    """Whether a cluster hangs over its support, and so is a part of something standing on it
    elsewhere (a chair's seat or armrest over its post, a shelf's edge, what stands on a
    shelf), not an object: its lowest voxel lies ``max_base_height_m`` or more above the
    lowest an object's voxel can lie (``margin_m``, the support's noise margin), and its
    lower outline in the image is its own (less than ``min_hidden_share`` of
    it has something nearer just past it, towards the image's open edge). An object whose
    base is hidden behind another stands on the support unseen, and is kept."""
    assert cluster.support is not None
    if (
        reach.view is None
        or reach.depth_image is None
        or reach.world_from_sensor is None
        or cluster.pixels is None
    ):
        return False
    lowest = float(cluster.support.signed_distance(cluster.voxels).min())
    if lowest < margin_m + params.max_base_height_m:
        return False
    rotation, shift = reach.world_from_sensor[:3, :3], reach.world_from_sensor[:3, 3]
    depth = (cluster.points - shift) @ rotation[:, 2]
    hidden = reach.view.hidden_below(
        cluster.pixels,
        depth,
        reach.depth_image,
        params.floating_probe_px,
        max(params.cut_band_m, 3 * cluster.noise_m),
    )
    return hidden < params.min_hidden_share


def _not_under(
    found: list[Cluster], parts: list[Cluster], support: SupportPlane, params: SegmentationParams
) -> list[Cluster]:
    """The clusters of ``found`` (all on ``support``) that are not one of ``parts`` and do not
    stand under one, in their order. A cluster stands under a part of something larger when its
    voxels' centre across the support lies within the part's extent, grown by
    ``cluster_eps_m``, and its top lies below the part's bottom: a chair's base under its
    seat, a table's legs under its top. Both are parts of one thing.

    Each cluster's centre and top and each part's extent and bottom are computed once (a
    cluttered frame has hundreds of pairs)."""
    if not parts:
        return list(found)
    lo = np.array([column_min(p.voxels[:, :2]) for p in parts]) - params.cluster_eps_m
    hi = np.array([column_max(p.voxels[:, :2]) for p in parts]) + params.cluster_eps_m
    bottom = np.array([float(support.signed_distance(p.voxels).min()) for p in parts])
    kept = []
    for cluster in found:
        if any(cluster is p for p in parts):
            continue
        centre = cluster.voxels[:, :2].mean(axis=0)
        over = (centre >= lo).all(axis=1) & (centre <= hi).all(axis=1)
        if over.any() and float(support.signed_distance(cluster.voxels).max()) < bottom[over].max():
            continue
        kept.append(cluster)
    return kept


def _not_under_support_edges(
    kept: list[list[Cluster]],
    supports: list[SupportPlane],
    regions: list[SupportRegion],
    frame: Frame,
    reach: _Reach,
    params: SegmentationParams,
) -> list[list[Cluster]]:
    """The clusters kept on each support (``kept[k]`` on ``supports[k]``, whose main piece
    covers ``regions[k]``) without those that stand under another support's edge: every voxel
    under that support's plane, its footprint reaching under it and its top hidden by that
    support's edge (:mod:`shapes.support_edge`): a desk's legs and panel seen on the
    floor through the gap under its front edge are parts of the desk."""
    if (
        len(supports) < 2
        or reach.view is None
        or reach.depth_image is None
        or reach.world_from_sensor is None
        or frame.pixels is None
    ):
        return kept
    rotation, shift = reach.world_from_sensor[:3, :3], reach.world_from_sensor[:3, 3]
    point_of: npt.NDArray[np.intp] | None = None  # the frame's point at each pixel, if needed
    out = []
    for k, found in enumerate(kept):
        stays = []
        for cluster in found:
            above = [
                j
                for j, higher in enumerate(supports)
                if j != k
                and float(higher.signed_distance(cluster.voxels).max()) < 0.0
                and reaches_under(cluster.voxels, regions[j], params.extent_margin_m)
            ]
            if not above or cluster.pixels is None:
                stays.append(cluster)
                continue
            nearer_m = max(params.cut_band_m, 3 * cluster.noise_m)
            lines, hiding = occluders_above(
                reach.view,
                cluster.pixels,
                (cluster.points - shift) @ rotation[:, 2],
                reach.depth_image,
                params.floating_probe_px,
                nearer_m,
            )
            if point_of is None:
                point_of = np.full(reach.depth_image.size, -1, dtype=np.intp)
                point_of[frame.pixels] = np.arange(len(frame.pixels))
            at = point_of[hiding]
            hiders = frame.world_points_of(frame.points[at[at >= 0]])
            if any(
                hidden_by_edge(
                    supports[j].signed_distance(hiders),
                    lines,
                    edge_depth_m=params.support_edge_depth_m,
                    nearer_m=nearer_m,
                    min_hidden_share=params.min_edge_hidden_share,
                )
                for j in above
            ):
                continue
            stays.append(cluster)
        out.append(stays)
    return out


def _stacked(voxels: FloatArray, parts: npt.NDArray[np.int64], min_apart_m: float) -> bool:
    """Whether two parts stand on top of each other (their centres closer than ``min_apart_m``
    across the table): objects on a table touch side by side, so such a cut runs through one
    object (an occlusion line, say) and is not taken."""
    centres = np.array([voxels[parts == k, :2].mean(axis=0) for k in range(int(parts.max()) + 1)])
    gaps = np.linalg.norm(centres[:, None, :] - centres[None, :, :], axis=2)
    return bool((gaps[np.triu_indices(len(centres), 1)] < min_apart_m).any())


def _each_stands(
    heights: FloatArray, parts: npt.NDArray[np.int64], params: SegmentationParams
) -> bool:
    """Whether every part of a cut reaches down to the support (its lowest voxel less than
    ``max_base_height_m`` over it): objects that touch stand side by side on the table, while
    a bottle's handle or shoulder cut off by a seam hangs above it."""
    lowest = [float(heights[parts == k].min()) for k in range(int(parts.max()) + 1)]
    return max(lowest) < params.max_base_height_m


def _taken_cut(
    voxels: FloatArray,
    heights: FloatArray,
    parts: npt.NDArray[np.int64],
    margin_m: float,
    params: SegmentationParams,
) -> npt.NDArray[np.int64]:
    """The parts of a seam cut that are taken, as labels 0, 1, ... (all 0: the cut is refused).

    Every part, when each stands (:func:`_each_stands`). Otherwise a part is cut off on its own
    when it hangs clear of the support as :func:`_floats` reads a hanging bottom (lowest voxel
    ``margin_m + max_base_height_m`` or more over it) over no part that stands (its centre
    across the support outside each standing part's extent grown by ``cluster_eps_m``): a
    monitor's screen whose lower edge touches the rim of a cup in front of it. The other parts
    stay one, as a refused cut leaves them: a bottle's shoulder, which hangs over its standing
    body, keeps the body whole, and an open cup's front wall is not cut from its inside (the
    splitter finds a seam where the inside meets the bottom). No part is cut off when the
    others would then fall apart (no chain of voxels ``cluster_eps_m`` apart joins them): what
    hangs holds them together, as a table's top its legs.
    """
    count = int(parts.max()) + 1
    lowest = np.array([float(heights[parts == k].min()) for k in range(count)])
    footprints = [
        (
            column_min(voxels[parts == k, :2]) - params.cluster_eps_m,
            column_max(voxels[parts == k, :2]) + params.cluster_eps_m,
        )
        for k in np.flatnonzero(lowest < params.max_base_height_m)
    ]
    apart = []
    for k in np.flatnonzero(lowest >= margin_m + params.max_base_height_m):
        centre = voxels[parts == k, :2].mean(axis=0)
        if footprints and not any(np.all((centre >= lo) & (centre <= hi)) for lo, hi in footprints):
            apart.append(int(k))
    taken = np.zeros(len(parts), dtype=np.int64)
    if not apart:
        return parts.copy() if _each_stands(heights, parts, params) else taken
    if not _connected(voxels[~np.isin(parts, apart)], params.cluster_eps_m):
        return taken  # what hangs holds the rest together: parts of one thing
    for label, part in enumerate(apart, start=1):
        taken[parts == part] = label
    return taken


def _connected(voxels: FloatArray, link_m: float) -> bool:
    """Whether voxels form one piece, each linked to another within ``link_m``."""
    pairs = cKDTree(voxels).query_pairs(link_m, output_type="ndarray")
    graph = coo_matrix(
        (np.ones(len(pairs)), (pairs[:, 0], pairs[:, 1])), shape=(len(voxels), len(voxels))
    )
    return int(connected_components(graph, directed=False)[0]) == 1


def _clear_of_the_base(heights: FloatArray, params: SegmentationParams) -> npt.NDArray[np.bool_]:
    """The voxels of a cluster over which the splitter reads how noisy its normals are: those
    ``max_base_height_m`` or more over the support. Below, every standing object meets the
    support in a concave corner, a true seam, not noise (on a box beside a telephone, 28 % of
    the voxels of the lowest 2 cm are seam against 13 % above 4 cm). A flat thing, with less
    than half of its voxels above that height, is read whole: its seams there are its own."""
    clear = heights >= params.max_base_height_m
    return clear if 2 * int(clear.sum()) >= len(heights) else np.ones(len(heights), dtype=bool)


def _split(
    labels: npt.NDArray[np.int64],
    voxels: FloatArray,
    viewpoint: FloatArray | None,
    params: SegmentationParams,
    sigma_1m: float,
    heights: FloatArray | None = None,
    margin_m: float = 0.0,
) -> npt.NDArray[np.int64]:
    """Labels with every cluster cut along its concave seams (:mod:`shapes.split`), where
    :func:`_taken_cut` takes the cut (``heights``: each voxel's height over the support, when
    known; ``margin_m``: the support's noise margin), and where no part lies along another
    (:mod:`shapes.nested_parts`: a handset in its cradle is one thing with its base)."""
    out = labels.copy()
    next_label = int(labels.max(initial=-1)) + 1
    order = np.argsort(labels, kind="stable")
    bounds = np.searchsorted(labels[order], np.arange(next_label + 1))
    cut, noise = [], []
    for label in range(next_label):
        members = order[bounds[label] : bounds[label + 1]]
        if len(members) < 2 * params.min_cluster_voxels:
            continue
        if column_span(voxels[members, :2]).max() < params.min_split_extent_m:
            continue  # narrower than two of the smallest objects side by side
        ranges = 1.0 if viewpoint is None else np.linalg.norm(voxels[members] - viewpoint, axis=1)
        cut.append(members)
        noise.append(sigma_1m * float(np.median(ranges)) ** 2)
    found = split_each(
        [voxels[m] for m in cut],
        viewpoint,
        min_voxels=params.min_cluster_voxels,
        noise_m=noise,
        judged=None if heights is None else [_clear_of_the_base(heights[m], params) for m in cut],
    )
    for members, parts in zip(cut, found, strict=True):
        if parts.max() == 0 or _stacked(voxels[members], parts, params.cluster_eps_m):
            continue
        if heights is not None:
            parts = _taken_cut(voxels[members], heights[members], parts, margin_m, params)
        parts = joined_where_nested(
            voxels[members], parts, near_m=params.cluster_eps_m, slice_m=params.voxel_m
        )
        for part in range(1, int(parts.max()) + 1):
            out[members[parts == part]] = next_label
            next_label += 1
    return out


def _clusters(
    candidates: npt.NDArray[np.intp],
    voxels: FloatArray,
    voxel_of: npt.NDArray[np.intp],
    points: FloatArray,
    depth: FloatArray,
    colours: tuple[FloatArray, npt.NDArray[np.intp]] | None,
    pixels: npt.NDArray[np.intp] | None,
    support: SupportPlane,
    margin: float,
    sigma_1m: float,
    params: SegmentationParams,
    organised: bool,
    viewpoint: FloatArray | None,
) -> tuple[list[Cluster], int]:
    """DBSCAN clusters of the candidate voxels above one support, and how many were too small.

    ``colours``: the frame's colours and the index in the frame of each of ``points``;
    ``pixels``: the image pixel of each of ``points`` on an organised frame."""
    cloud = _cloud(voxels[candidates])
    _, kept = cloud.remove_statistical_outlier(params.outlier_neighbours, params.outlier_std_ratio)
    candidates = candidates[np.asarray(kept, dtype=np.intp)]
    labels = np.asarray(
        _cloud(voxels[candidates]).cluster_dbscan(params.cluster_eps_m, params.cluster_min_points),
        dtype=np.int64,
    )
    if params.split_touching:
        labels = _split(
            labels,
            voxels[candidates],
            viewpoint,
            params,
            sigma_1m,
            support.signed_distance(voxels[candidates]),
            margin,
        )
    voxel_label = np.full(len(voxels), -1, dtype=np.int64)
    voxel_label[candidates] = labels
    # Only the points of labelled voxels (a few percent of a frame) from here on.
    member = np.flatnonzero(voxel_label[voxel_of] >= 0)
    cut = np.maximum(params.above_margin_m, 2 * sigma_1m * depth[member] ** 2)
    member = member[support.signed_distance(points[member]) > np.minimum(cut, margin)]
    point_label = voxel_label[voxel_of[member]]
    clusters = []
    small = 0
    order = member[np.argsort(point_label, kind="stable")]
    bounds = np.searchsorted(np.sort(point_label), np.arange(labels.max(initial=-1) + 2))
    for label in range(labels.max(initial=-1) + 1):
        n_vox = int((labels == label).sum())
        idx = order[bounds[label] : bounds[label + 1]]
        if n_vox < params.min_cluster_voxels or len(idx) < params.min_cluster_voxels:
            small += 1
            continue
        if not organised:
            idx = idx[~sparse_points(points[idx])]
        clusters.append(
            Cluster(
                points[idx],
                None if colours is None else colours[0][colours[1][idx]],
                voxels[candidates[labels == label]],
                support,
                sigma_1m * float(np.median(depth[idx])) ** 2,
                None if pixels is None else pixels[idx],
            )
        )
    return clusters, small
