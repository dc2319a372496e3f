"""Objects whose bottom lies in the support's margin band: a cluster grown down under itself.

Segmentation takes what lies less than a support's noise margin over it for the support. On a
smoothed or noisy floor that margin is 2 cm or more, and a thin object's lowest layer (a
laptop's base, a banana's underside) lies in it, cut off from the object. :func:`grow_downwards`
gives a cluster back the voxels of that band that lie under its own footprint, seen from above,
and connect to it: the support under an object is hidden by the object, so what shows there is
the object. The footprint keeps the growth off the bare support around the object, which lies
in the same band; connectivity keeps a stray return under the footprint out.
"""

from __future__ import annotations

import numpy as np
import numpy.typing as npt
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components
from scipy.spatial import cKDTree

from shapes.types import FloatArray

__all__ = ["footprint_cells", "grow_downwards"]


def footprint_cells(voxels: FloatArray, cell_m: float) -> npt.NDArray[np.int64]:
    """The cells of a ``cell_m`` grid across the support (x, y) that ``voxels`` occupy, one
    row ``(i, j)`` per voxel.

    Raises ValueError when ``cell_m`` is not positive.

    >>> footprint_cells(np.array([[0.004, 0.012, 0.3], [-0.001, 0.0, 0.1]]), 0.01).tolist()
    [[0, 1], [-1, 0]]
    """
    if cell_m <= 0:
        raise ValueError(f"cell_m must be positive, got {cell_m}")
    return np.floor(np.asarray(voxels)[:, :2] / cell_m).astype(np.int64)


def grow_downwards(
    clusters: list[FloatArray], band: FloatArray, cell_m: float, link_m: float
) -> list[npt.NDArray[np.intp]]:
    """For each of ``clusters`` (voxels of clusters on one support), the indices in ``band``
    (voxels of the support's margin band) of its bottom: the band voxels under its footprint
    (a cell of the ``cell_m`` grid across the support that one of its voxels occupies,
    :func:`footprint_cells`) that connect to it, linked to one of its voxels, or to a band voxel
    under its footprint so connected, closer than ``link_m``. A band voxel under the footprints
    of two clusters goes to neither. Each array sorted; empty when nothing is added.

    Raises ValueError when ``cell_m`` or ``link_m`` is not positive.

    >>> laptop = np.array([[0.0, 0.0, 0.03], [0.01, 0.0, 0.03], [0.02, 0.0, 0.03]])
    >>> band = np.array(
    ...     [[0.0, 0.0, 0.015], [0.01, 0.0, 0.005], [0.05, 0.0, 0.015], [0.02, 0.0, -0.04]]
    ... )
    >>> [a.tolist() for a in grow_downwards([laptop], band, 0.01, 0.02)]  # not beside, not far
    [[0, 1]]
    """
    if link_m <= 0:
        raise ValueError(f"link_m must be positive, got {link_m}")
    band = np.asarray(band).reshape(-1, 3)
    band_cells = footprint_cells(band, cell_m)
    out = [np.zeros(0, dtype=np.intp) for _ in clusters]
    if len(band) == 0 or sum(len(c) for c in clusters) == 0:
        return out
    voxels = np.vstack(clusters)
    owner = np.repeat(np.arange(len(clusters)), [len(c) for c in clusters])
    cells = footprint_cells(voxels, cell_m)
    lo = np.minimum(cells.min(axis=0), band_cells.min(axis=0))
    band_owner = _cell_owner(_keys(cells, lo), owner, _keys(band_cells, lo))
    under = np.flatnonzero(band_owner >= 0)
    if len(under) == 0:
        return out
    # Only the clusters' voxels within reach of the band take part in the links, and a link
    # joins two voxels of one cluster's footprint only.
    gap, _ = cKDTree(band[under]).query(voxels, distance_upper_bound=link_m)
    linked = np.flatnonzero(np.isfinite(gap))
    nodes = np.vstack([voxels[linked], band[under]])
    node_owner = np.concatenate([owner[linked], band_owner[under]])
    pairs = cKDTree(nodes).query_pairs(link_m, output_type="ndarray")
    pairs = pairs[node_owner[pairs[:, 0]] == node_owner[pairs[:, 1]]]
    graph = coo_matrix(
        (np.ones(len(pairs)), (pairs[:, 0], pairs[:, 1])), shape=(len(nodes), len(nodes))
    )
    _, labels = connected_components(graph, directed=False)
    joined = np.isin(labels[len(linked) :], labels[: len(linked)])
    for k in range(len(clusters)):
        out[k] = np.sort(under[joined & (band_owner[under] == k)]).astype(np.intp)
    return out


def _cell_owner(
    cells: npt.NDArray[np.int64], owner: npt.NDArray[np.int64], wanted: npt.NDArray[np.int64]
) -> npt.NDArray[np.int64]:
    """For each of the ``wanted`` cells, the one ``owner`` among those of ``cells`` that match
    it, or -1 (no match, or matches of two owners)."""
    n = int(owner.max()) + 1
    pairs = np.unique(cells * n + owner)
    keys, start, count = np.unique(pairs // n, return_index=True, return_counts=True)
    key_owner = np.where(count == 1, pairs[start] % n, -1)
    pos = np.minimum(np.searchsorted(keys, wanted), len(keys) - 1)
    return np.asarray(np.where(keys[pos] == wanted, key_owner[pos], -1), dtype=np.int64)


def _keys(cells: npt.NDArray[np.int64], lo: npt.NDArray[np.int64]) -> npt.NDArray[np.int64]:
    """One integer per cell, for cells at or past ``lo`` (a support spans far fewer than 2**20
    cells each way)."""
    shifted = cells - lo
    return np.asarray(shifted[:, 0] * (1 << 20) + shifted[:, 1], dtype=np.int64)
