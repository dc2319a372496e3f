"""Which of a frame's planes are supports, and which are faces of objects.

Step 3's judging and step 4's rule of :mod:`shapes.segment`, in the order :func:`judge_planes`
asks: the fronts or tops of objects in a row (:func:`_faces_on`), a plane standing on a larger
horizontal one, an object's face unless it is a step of the floor (:func:`_standing_on`), a
would-be support scattered in pieces (:func:`_supports_by_pieces`, :mod:`shapes.plane_pieces`),
and one crossing a larger one (:func:`_crosses`). What is left and horizontal is a support.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components
from scipy.spatial import cKDTree

from shapes.arrays import column_max, column_min, inside_box
from shapes.plane_pieces import is_scattered, main_piece
from shapes.segment.bands import one_plane_per_band
from shapes.segment.params import SegmentationParams
from shapes.segment.planes import Plane
from shapes.support_region import SupportRegion, support_region
from shapes.types import FloatArray


@dataclass(frozen=True, eq=False)
class JudgedPlanes:
    """The planes of a frame in the world frame, each judged: the supports among them, and
    those whose voxels stay free for the objects."""

    planes: list[Plane]
    """Every plane, a scattered would-be support reduced to its main piece."""
    supports: list[Plane]
    """The horizontal planes that are supports, in the planes' order."""
    faces: set[int]
    """The ids of the planes that are faces of objects (fronts, tops, an object's own tilted
    face, a slice through a support and what stands on it): their voxels stay free."""
    region_of: dict[int, SupportRegion]
    """Each support's main piece (:mod:`shapes.support_region`), by the plane's id."""


def judge_planes(
    planes: list[Plane], voxels: FloatArray, tolerance: FloatArray, params: SegmentationParams
) -> JudgedPlanes:
    """Which of ``planes`` (in the world frame, their inliers indexing ``voxels``) are supports
    and which are faces of objects, in this order: the fronts or tops of objects in a row
    (:func:`_faces_on`); a plane standing on a larger horizontal one (:func:`_standing_on`),
    a face unless it is a step of the floor (a rug, a seam), which is neither; a scattered
    would-be support (:func:`_supports_by_pieces`); one that crosses a larger one
    (:func:`_crosses`). ``tolerance``: per voxel, how far from a plane it may lie.

    First, horizontal planes in the band of a larger one are folded into it
    (:func:`shapes.segment.bands.one_plane_per_band`): one support, not a second support or a
    step."""
    planes = one_plane_per_band(planes, voxels, tolerance, params)
    level = [p for p in planes if p.horizontal]
    # A plane is judged against the other horizontal planes only (one under it, or a larger
    # one it stands on): with none, it is neither a face nor a step, and its voxels are not
    # worked out (a tabletop frame's only support, its largest plane).
    judged = {
        id(p): _judged_voxels(p, voxels, level, params)
        for p in planes
        if any(q is not p for q in level)
    }
    faces = {
        id(p)
        for p in planes
        if id(p) in judged and _faces_on(judged[id(p)], [q for q in level if q is not p], params)
    }
    steps: set[int] = set()
    for p in planes:
        if id(p) in faces or id(p) not in judged:
            continue
        below = _standing_on(voxels, judged[id(p)], p, level, params)
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
        if _crosses(p, region_of[id(p)], horizontal, voxels, tolerance, params)
    }
    faces |= crossing  # a slice through a support and what stands on it: its voxels stay free
    horizontal = [p for p in horizontal if id(p) not in crossing]
    return JudgedPlanes(planes, horizontal, faces, region_of)


def _judged_voxels(
    plane: Plane, voxels: FloatArray, level: list[Plane], params: SegmentationParams
) -> FloatArray:
    """The voxels by which ``plane`` is judged a face of objects or not (:func:`_faces_on`,
    :func:`_standing_on`): its main piece (:func:`shapes.plane_pieces.main_piece`) when
    ``params.faces_by_main_piece``, that piece holds at least ``min_main_piece_share`` of its
    voxels and fewer than ``min_cut_voxels`` of its other voxels lie ``max_height_m`` or more
    over the largest of the ``level`` planes; else all its inliers.

    A plane through objects' fronts or tops also takes, within its tolerance, a few voxels
    that line up with it elsewhere (a strip at the support's far edge, the wall under a table's
    back edge): they are other things. A plane scattered in smaller pieces is no surface of its
    own and is judged whole here (its main piece is judged by :func:`_supports_by_pieces`). A
    plane that rises past the height band elsewhere is a wall or a piece of furniture whose
    lower part is cut from its upper part (something hides its middle): judged whole, as a
    wall."""
    mine = voxels[plane.inliers]
    if not params.faces_by_main_piece:
        return mine
    main = main_piece(mine, plane.normal, params.support_cell_m)
    if float(main.mean()) < params.min_main_piece_share:
        return mine
    others = [q for q in level if q is not plane]
    if others:
        ground = max(others, key=lambda q: int(q.inliers.sum()))
        rest = mine[~main] @ ground.normal + ground.offset
        if int(np.count_nonzero(rest >= params.max_height_m)) >= params.min_cut_voxels:
            return mine
    return mine[main]


_FACES_LINK_M = 0.025
"""Voxels of a plane closer than this are one piece of it (see _faces_on)."""


def _faces_on(inliers: FloatArray, below: list[Plane], params: SegmentationParams) -> bool:
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
    points: FloatArray,
    mine: FloatArray,
    plane: Plane,
    level: list[Plane],
    params: SegmentationParams,
) -> float | None:
    """How high (median, metres) a plane stands over a larger horizontal plane that carries it
    as part of an object, or None when it is a support, a wall or a shelf of its own.

    ``points`` are the voxels the planes' inlier masks index; ``mine`` are the plane's voxels
    it is judged by (:func:`_judged_voxels`, or a reduced plane's own). A plane is part of what
    stands on a larger horizontal plane when all of ``mine`` but 2 % lie above it, over it
    (inside its bounding box shrunk by ``edge_margin_m``) and lower than ``min_support_rise_m``
    (a horizontal plane) or ``max_height_m`` (a tilted one) over it: the top of a box, the open
    lid of a laptop, a book lying flat. A table stands higher than ``min_support_rise_m`` over
    the floor; a wall rises at the edge of the floor or table it meets, not inside it.
    """
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
        if inside_box(mine, lo, hi).mean() < 0.98:
            continue
        return float(np.median(height))
    return None


def _supports_by_pieces(
    planes: list[Plane],
    candidates: list[Plane],
    level: list[Plane],
    faces: set[int],
    voxels: FloatArray,
    params: SegmentationParams,
) -> tuple[list[Plane], dict[int, SupportRegion], set[int]]:
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
                below = _standing_on(voxels, voxels[kept], main, others, params)
                if below is not None and below >= params.floor_step_m:
                    faces.add(id(main))
                scattered.add(id(main))
                plane = main
            else:
                regions[id(plane)] = region
        judged.append(plane)
    return judged, regions, scattered


def _crosses(
    plane: Plane,
    region: SupportRegion,
    level: list[Plane],
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
