"""Separating objects that touch: cut the voxel graph of a cluster along its concave seams.

A Euclidean cluster joins objects closer than its distance (3 cm): two cans 0-1 cm apart are one
cluster. Each object of a tabletop scene is convex (sphere, cylinder, cone, box), so where two of
them meet, their visible surfaces form a *valley*: the normals on either side turn toward each
other. The rule (after the local convexity criterion of LCCP, Stein et al. 2014):

- every voxel gets a normal from its ``neighbours`` nearest voxels (smallest principal axis),
  turned toward the camera (the viewpoint) or, without one, away from the cluster's vertical
  axis and upward;
- two voxels closer than ``link_m`` are linked unless the link is *concave*, i.e. the normals
  converge, ``(n_i - n_j) . (p_i - p_j) < 0``, by more than ``concave_deg`` between them;
  a voxel with ``seam_links`` or more concave links is part of the seam and loses all its
  links (normals are smoothed across the seam, so a few links over it look flat); when more
  than ``max_seam_share`` of the voxels are seam, the normals are too noisy to tell and the
  cluster stays whole (the caller may say which voxels that share is read over: those clear
  of the support, whose corner with every standing object is a true seam);
- the objects are the connected parts of what is left; parts with fewer than ``min_voxels``
  voxels go back to the part of their nearest voxel. A single convex object has no concave
  seam across it (noise makes only scattered concave links, which cut nothing), so it stays
  whole.

>>> rng = np.random.default_rng(0)
>>> def dome(cx):  # the upper half of a ball of radius 4 cm, seen from above
...     d = rng.normal(size=(3000, 3)); d /= np.linalg.norm(d, axis=1)[:, None]
...     d[:, 2] = np.abs(d[:, 2])
...     return d * 0.04 + (cx, 0.0, 0.0)
>>> from shapes.segment import voxel_grid
>>> voxels, _ = voxel_grid(np.vstack((dome(-0.041), dome(0.041))), 0.01)
>>> labels = split_touching(voxels, viewpoint=np.array([0.0, 0.0, 1.0]))
>>> sorted(np.bincount(labels).tolist()) > [50, 50]
True
>>> len(set(labels.tolist()))
2
>>> len(set(split_touching(voxel_grid(dome(0.0), 0.01)[0], np.array([0, 0, 1.0])).tolist()))
1
"""

from __future__ import annotations

import logging
import math

import numpy as np
import numpy.typing as npt
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components
from scipy.spatial import cKDTree

from shapes.arrays import unique_inverse
from shapes.normals import patch_normals
from shapes.types import FloatArray

__all__ = ["split_each", "split_touching"]

log = logging.getLogger(__name__)


def split_touching(
    voxels: FloatArray,
    viewpoint: FloatArray | None,
    *,
    link_m: float = 0.018,
    neighbours: int = 10,
    concave_deg: float = 20.0,
    seam_links: int = 2,
    min_voxels: int = 12,
    noise_m: float = 0.0,
    max_seam_share: float = 0.15,
) -> npt.NDArray[np.int64]:
    """A part label (0, 1, ...) for each voxel of one cluster (see the module docstring).

    ``noise_m``: the depth noise at the cluster's range; above 2 mm the concave angle grows by
    3 degrees per millimetre, as noisy normals bend more at random.
    """
    return split_each(
        [voxels],
        viewpoint,
        link_m=link_m,
        neighbours=neighbours,
        concave_deg=concave_deg,
        seam_links=seam_links,
        min_voxels=min_voxels,
        noise_m=[noise_m],
        max_seam_share=max_seam_share,
    )[0]


def split_each(
    clusters: list[FloatArray],
    viewpoint: FloatArray | None,
    *,
    link_m: float = 0.018,
    neighbours: int = 10,
    concave_deg: float = 20.0,
    seam_links: int = 2,
    min_voxels: int = 12,
    noise_m: list[float] | None = None,
    max_seam_share: float = 0.15,
    judged: list[npt.NDArray[np.bool_]] | None = None,
) -> list[npt.NDArray[np.int64]]:
    """:func:`split_touching` of each of several clusters (``noise_m``: each one's noise, 0 by
    default), with the same labels: each cluster's neighbours and links are its own, and the
    normals, the concave links, the seams and the connected parts of all of them are found in
    one set of array operations (a frame's clusters cost a few numpy calls, not a few each).

    ``judged``: for each cluster, the voxels over which the share of seam voxels is read
    against ``max_seam_share`` (every voxel by default; all of them again where none is
    judged).

    Raises ValueError when ``noise_m`` or ``judged`` does not give one entry per cluster, or
    a ``judged`` mask is not as long as its cluster.
    """
    noise = [0.0] * len(clusters) if noise_m is None else list(noise_m)
    if len(noise) != len(clusters):
        raise ValueError(
            f"noise_m: expected one noise per cluster ({len(clusters)}), got {len(noise)}"
        )
    masks = (
        [np.ones(len(v), dtype=bool) for v in clusters]
        if judged is None
        else [np.asarray(m, dtype=bool) for m in judged]
    )
    if len(masks) != len(clusters) or any(
        len(m) != len(v) for m, v in zip(masks, clusters, strict=True)
    ):
        raise ValueError(
            "judged: expected one mask per cluster, as long as its cluster "
            f"({[len(v) for v in clusters]}), got {[len(m) for m in masks]}"
        )
    out: list[npt.NDArray[np.int64]] = [np.zeros(len(v), dtype=np.int64) for v in clusters]
    work = [k for k, v in enumerate(clusters) if len(v) >= 2 * min_voxels]
    if not work:
        return out
    sizes = np.array([len(clusters[k]) for k in work])
    starts = np.concatenate(([0], np.cumsum(sizes)[:-1]))
    voxels = np.concatenate([clusters[k] for k in work])
    n = len(voxels)
    near, pairs = [], []
    for k, start in zip(work, starts, strict=True):
        tree = cKDTree(clusters[k], balanced_tree=False, compact_nodes=False)  # faster to build
        found = tree.query(clusters[k], k=min(neighbours, len(clusters[k])))[1]
        near.append(np.reshape(found, (len(clusters[k]), -1)) + start)  # (n, k) even for k = 1
        pairs.append(tree.query_pairs(link_m, output_type="ndarray") + start)
    if len({a.shape[1] for a in near}) == 1:
        normals = patch_normals(voxels, np.concatenate(near))
    else:  # fewer voxels than neighbours in some cluster (a tiny min_voxels)
        normals = np.concatenate([patch_normals(voxels, a) for a in near])
    if viewpoint is not None:
        toward = np.asarray(viewpoint) - voxels
    else:
        toward = np.concatenate([v - v.mean(axis=0) for v in (clusters[k] for k in work)])
        toward[:, 2] = np.abs(toward[:, 2]) + 0.01
    normals *= np.where(np.einsum("ij,ij->i", normals, toward) < 0, -1.0, 1.0)[:, None]
    group = np.repeat(np.arange(len(work)), sizes)
    linked = np.concatenate(pairs)
    i, j = linked[:, 0], linked[:, 1]
    # Above 2 mm of noise the concave angle grows by 3 degrees per millimetre.
    flat_cos = [
        math.cos(math.radians(concave_deg + 3000.0 * max(0.0, noise[k] - 0.002))) for k in work
    ]
    bend_cos = np.array(flat_cos)[group[i]]
    # np.take: the rows of ``a[i]``, at a third of the cost of an index on an (N, 3) array.
    normal_i, normal_j = np.take(normals, i, axis=0), np.take(normals, j, axis=0)
    voxel_i, voxel_j = np.take(voxels, i, axis=0), np.take(voxels, j, axis=0)
    converge = np.einsum("ij,ij->i", normal_i - normal_j, voxel_i - voxel_j) < 0
    bend = np.einsum("ij,ij->i", normal_i, normal_j) < bend_cos
    concave = converge & bend
    # Normals are smoothed over the seam, so some links across it still look flat: the voxels
    # at either end of ``seam_links`` or more concave links are set aside as the seam, and
    # only the links between the other voxels count.
    hits = np.bincount(i[concave], minlength=n) + np.bincount(j[concave], minlength=n)
    seam = hits >= seam_links
    # Concave links everywhere: the normals are too noisy to show a seam.
    read = np.concatenate([masks[k] if masks[k].any() else ~masks[k] for k in work])
    noisy = (
        np.bincount(group[read], weights=seam[read], minlength=len(work))
        / np.bincount(group[read], minlength=len(work))
        > max_seam_share
    )
    keep = ~concave & ~seam[i] & ~seam[j]
    graph = coo_matrix((np.ones(int(keep.sum())), (i[keep], j[keep])), shape=(n, n))
    # Components are numbered in the order of their lowest voxel, so each cluster's are a run
    # of numbers in the order its own graph would give them.
    _, labels = connected_components(graph, directed=False)
    for g, (k, start, size) in enumerate(zip(work, starts, sizes, strict=True)):
        if noisy[g] or not len(pairs[g]):
            if not noisy[g]:
                out[k] = np.arange(size, dtype=np.int64)  # no links at all: every voxel alone
            continue
        own = labels[start : start + size] - labels[start : start + size].min()
        out[k] = _parts(clusters[k], own, min_voxels, int(seam[start : start + size].sum()))
    return out


def _parts(
    voxels: FloatArray, labels: npt.NDArray[np.intp], min_voxels: int, seam: int
) -> npt.NDArray[np.int64]:
    """One cluster's connected parts as labels 0, 1, ...: all 0 unless two or more parts have
    ``min_voxels`` voxels; smaller parts join the part of their nearest voxel in a big one."""
    sizes = np.bincount(labels)
    big = np.flatnonzero(sizes >= min_voxels)
    if len(big) <= 1:
        return np.zeros(len(voxels), dtype=np.int64)
    log.debug(
        "cluster of %d voxels split in %d parts (%d seam voxels)", len(voxels), len(big), seam
    )
    labels = labels.copy()
    is_big = np.zeros(len(sizes), dtype=np.bool_)
    is_big[big] = True
    in_big = is_big[labels]  # np.isin(labels, big), without its sort
    # Small parts (seam voxels, specks) join the part of their nearest voxel in a big part.
    _, nearest = cKDTree(voxels[in_big]).query(voxels[~in_big])
    labels[~in_big] = labels[in_big][nearest]
    _, compact, _ = unique_inverse(labels)
    return np.asarray(compact, dtype=np.int64)
