"""A cut through things stacked in the image, taken where colour says the things are two.

The splitter (:mod:`shapes.split`) cuts a cluster along its concave seams, and its glue
(:mod:`shapes.segment.splitting`) refuses the whole cut when two of its parts stand on top of
each other (their centres closer than the linking distance across the support): one object cut
along an occlusion line or its own fold. Lying objects that touch are cut so too: a drill on its
side is cut along its own fold into an upper and a lower part, and the whole cut, which also
parts the drill from the clamp and the box it touches, is refused.

:func:`parted_by_colour` joins the stacked parts and keeps the cut between what remains only
when each pair of touching remainders differs in colour by more than the spread of colours
within one object: distinct objects set down against each other, rather than one object's
faces. Colours are compared in CIELAB (:func:`lab`), where a distance is a perceived
difference (CIE76 delta E), on each part's median colour.
"""

from __future__ import annotations

import numpy as np
import numpy.typing as npt
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components
from scipy.spatial import cKDTree

from shapes.types import FloatArray

__all__ = ["lab", "parted_by_colour", "voxel_colours"]

_XYZ_FROM_LINEAR_RGB = np.array(
    [[0.4124, 0.3576, 0.1805], [0.2126, 0.7152, 0.0722], [0.0193, 0.1192, 0.9505]]
)
_D65_WHITE = np.array([0.95047, 1.0, 1.08883])


def lab(rgb: FloatArray) -> FloatArray:
    """CIELAB (L* 0-100, a*, b*) of ``(N, 3)`` sRGB colours in [0, 1], D65 white.

    >>> lab(np.array([[1.0, 1.0, 1.0], [0.0, 0.0, 0.0]])).round(1)
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


def parted_by_colour(
    voxels: FloatArray,
    parts: npt.NDArray[np.int64],
    colours_lab: FloatArray,
    *,
    min_apart_m: float,
    min_difference: float,
) -> npt.NDArray[np.int64]:
    """The cut ``parts`` (labels 0, 1, ... of ``voxels``) with its stacked parts joined (centres
    across the support closer than ``min_apart_m``, and so on through one another), when what
    remains is two parts or more and every two of them that touch (nearest voxels within
    ``min_apart_m``) have median colours (``colours_lab``, CIELAB, one row per voxel; NaN rows
    are left out) more than ``min_difference`` apart; otherwise all zeros: the cut is refused.

    Raises ValueError when ``parts`` or ``colours_lab`` does not give one row per voxel, or
    ``min_difference`` is not positive.
    """
    if len(parts) != len(voxels) or len(colours_lab) != len(voxels):
        raise ValueError(
            f"parts and colours_lab: expected one row per voxel ({len(voxels)}), "
            f"got {len(parts)} and {len(colours_lab)}"
        )
    if not min_difference > 0:
        raise ValueError(f"min_difference must be positive, got {min_difference}")
    refused = np.zeros(len(parts), dtype=np.int64)
    count = int(parts.max(initial=-1)) + 1
    centres = np.array([voxels[parts == k, :2].mean(axis=0) for k in range(count)])
    pairs = cKDTree(centres).query_pairs(min_apart_m, output_type="ndarray")
    graph = coo_matrix((np.ones(len(pairs)), (pairs[:, 0], pairs[:, 1])), shape=(count, count))
    groups = connected_components(graph, directed=False)[1].astype(np.int64)
    joined = groups[parts]
    if joined.max() == 0:
        return refused
    medians = []
    for g in range(int(joined.max()) + 1):
        seen = colours_lab[joined == g]
        seen = seen[np.isfinite(seen).all(axis=1)]
        if not len(seen):
            return refused
        medians.append(np.median(seen, axis=0))
    trees = [cKDTree(voxels[joined == g]) for g in range(len(medians))]
    least = np.inf
    for a in range(len(medians)):
        for b in range(a + 1, len(medians)):
            gap, _ = trees[b].query(voxels[joined == a], distance_upper_bound=min_apart_m)
            if not np.isfinite(gap).any():
                continue  # not touching: DBSCAN joined them through a third
            least = min(least, float(np.linalg.norm(medians[a] - medians[b])))
    return joined if np.isfinite(least) and least > min_difference else refused
