"""A cut through things stacked in the image, taken where colour says the things are two.

The splitter (:mod:`shapes.split`) cuts a cluster along its concave seams, and its glue
(:mod:`shapes.segment.splitting`) refuses the whole cut when two of its parts stand on top of
each other (their centres closer than the linking distance across the support): one object cut
along an occlusion line or its own fold. Lying objects that touch are cut so too: a drill on its
side is cut along its own fold into an upper and a lower part, and the whole cut, which also
parts the drill from the clamp and the box it touches, is refused.

:func:`joined_where_stacked` joins the stacked parts, and :func:`touching_parts_differ` keeps
the cut between what remains only when every two touching parts differ in colour by more than
a threshold: distinct objects set down against each other. One object's faces may differ in
colour too, but a textured object cut in several parts leaves some touching pair alike. Colours
are compared in CIELAB (:func:`lab`), where a distance is a perceived difference (CIE76 delta
E), on each part's median colour.
"""

from __future__ import annotations

import numpy as np
import numpy.typing as npt
from scipy.spatial import cKDTree

from shapes.types import FloatArray

__all__ = ["joined_where_stacked", "lab", "touching_parts_differ", "voxel_colours"]

_XYZ_FROM_LINEAR_RGB = np.array(
    [[0.4124, 0.3576, 0.1805], [0.2126, 0.7152, 0.0722], [0.0193, 0.1192, 0.9505]]
)
_D65_WHITE = np.array([0.95047, 1.0, 1.08883])


def lab(rgb: FloatArray) -> FloatArray:
    """CIELAB (L* 0-100, a*, b*) of ``(N, 3)`` sRGB colours in [0, 1], D65 white.

    >>> lab(np.array([[1.0, 1.0, 1.0], [0.0, 0.0, 0.0]])).round(1) + 0.0
    array([[100.,   0.,   0.],
           [  0.,   0.,   0.]])
    """
    rgb = np.asarray(rgb, dtype=np.float64).reshape(-1, 3)
    linear = np.where(rgb > 0.04045, ((rgb + 0.055) / 1.055) ** 2.4, rgb / 12.92)
    xyz = linear @ _XYZ_FROM_LINEAR_RGB.T / _D65_WHITE
    f = np.where(xyz > (6 / 29) ** 3, np.cbrt(xyz), xyz / (3 * (6 / 29) ** 2) + 4 / 29)
    return np.column_stack(
        (116 * f[:, 1] - 16, 500 * (f[:, 0] - f[:, 1]), 200 * (f[:, 1] - f[:, 2]))
    )


def voxel_colours(voxel_of: npt.NDArray[np.intp], colours: FloatArray, n_voxels: int) -> FloatArray:
    """Each voxel's mean colour (``(n_voxels, 3)``), from its points' colours (``colours``,
    one row per point, and ``voxel_of``, each point's voxel); NaN for a voxel with no point."""
    count = np.bincount(voxel_of, minlength=n_voxels).astype(np.float64)
    mean = np.column_stack(
        [np.bincount(voxel_of, weights=colours[:, c], minlength=n_voxels) for c in range(3)]
    )
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.asarray(mean / count[:, None], dtype=np.float64)


def joined_where_stacked(
    voxels: FloatArray, parts: npt.NDArray[np.int64], min_apart_m: float
) -> npt.NDArray[np.int64]:
    """The cut ``parts`` (labels 0, 1, ... of ``voxels``) with its stacked parts joined: those
    whose centres across the support lie closer than ``min_apart_m``, and so on through one
    another; relabelled 0, 1, ... (all zeros: every part was stacked with another, no cut left).

    Raises ValueError when ``parts`` does not give one label per voxel.

    >>> voxels = np.array([[0.0, 0, 0], [0.005, 0, 0.02], [0.1, 0, 0]])
    >>> joined_where_stacked(voxels, np.array([0, 1, 2]), 0.03).tolist()
    [0, 0, 1]
    """
    if len(parts) != len(voxels):
        raise ValueError(f"parts: expected one label per voxel ({len(voxels)}), got {len(parts)}")
    count = int(parts.max(initial=-1)) + 1
    size = np.bincount(parts, minlength=count)
    centres = np.column_stack(
        [
            np.bincount(parts, weights=voxels[:, axis], minlength=count) / np.maximum(size, 1)
            for axis in (0, 1)
        ]
    )
    near = np.linalg.norm(centres[:, None, :] - centres[None, :, :], axis=2) < min_apart_m
    group = np.arange(count)
    while True:  # each part takes the least label among its stacked neighbours, until none moves
        least = np.where(near, group[None, :], count).min(axis=1)
        if (least >= group).all():
            break
        group = np.minimum(group, least)
    return np.asarray(np.unique(group, return_inverse=True)[1], dtype=np.int64)[parts]


def touching_parts_differ(
    voxels: FloatArray,
    parts: npt.NDArray[np.int64],
    colours_lab: FloatArray,
    *,
    near_m: float,
    min_difference: float,
) -> bool:
    """Whether a cut into two parts or more (``parts``: labels 0, 1, ... of ``voxels``) has
    every two parts that touch (nearest voxels within ``near_m``) more than ``min_difference``
    apart in median colour (``colours_lab``: CIELAB, one row per voxel; rows with a NaN, voxels
    without a colour, are left out; a part with none is alike to every other).

    Raises ValueError when ``parts`` or ``colours_lab`` does not give one row per voxel, a
    label under the largest holds no voxel, or ``min_difference`` is not positive.
    """
    if len(parts) != len(voxels) or len(colours_lab) != len(voxels):
        raise ValueError(
            f"parts and colours_lab: expected one row per voxel ({len(voxels)}), "
            f"got {len(parts)} and {len(colours_lab)}"
        )
    if not min_difference > 0:
        raise ValueError(f"min_difference must be positive, got {min_difference}")
    count = int(parts.max(initial=-1)) + 1
    if count < 2:
        return False
    seen = np.isfinite(colours_lab).all(axis=1)
    medians = _medians(colours_lab[seen], parts[seen], count)
    with np.errstate(invalid="ignore"):
        apart = np.linalg.norm(medians[:, None, :] - medians[None, :, :], axis=2)
    order = np.argsort(parts, kind="stable")
    starts = np.searchsorted(parts[order], np.arange(count))
    if (np.diff(np.r_[starts, len(parts)]) == 0).any():
        raise ValueError(f"parts: expected every label 0..{count - 1} to hold a voxel")
    low = np.minimum.reduceat(voxels[order], starts) - near_m
    high = np.maximum.reduceat(voxels[order], starts) + near_m
    # Only the pairs alike in colour can refuse: whether they touch is asked of them alone.
    for a, b in zip(*np.nonzero(np.triu(~(apart > min_difference), 1)), strict=True):
        if (low[a] > high[b]).any() or (low[b] > high[a]).any():
            continue  # their boxes, grown by near_m, do not meet
        gaps, _ = cKDTree(voxels[parts == b]).query(voxels[parts == a], distance_upper_bound=near_m)
        if np.isfinite(gaps).any():
            return False
    return True


def _medians(values: FloatArray, labels: npt.NDArray[np.int64], count: int) -> FloatArray:
    """The median of each column of ``values`` over each label 0 .. ``count`` - 1 (NaN for a
    label with no row), by one sort per column rather than one median per label."""
    out = np.full((count, values.shape[1]), np.nan)
    sizes = np.bincount(labels, minlength=count)
    starts = np.r_[0, np.cumsum(sizes)[:-1]]
    held = sizes > 0
    lower = (starts + (sizes - 1) // 2)[held]
    upper = (starts + sizes // 2)[held]
    for column in range(values.shape[1]):
        ordered = values[np.lexsort((values[:, column], labels)), column]
        out[held, column] = (ordered[lower] + ordered[upper]) / 2
    return out
