"""Objects taller than the height band: clusters cut at the band's top, grown upwards.

Segmentation looks for objects in a band over each support (``max_height_m``). A cluster that
stands on the support and reaches the band's top may be the lower part of something taller (a
rack case, a chair's back, a bin) or of something that does not end (a wall, a door, a person
whose head is out of view). :func:`grow_upwards` joins to such clusters the free voxels above
the band that connect to them, so that :mod:`shapes.segment` can judge the whole: what ends
under the higher limit is an object, what still reaches it is a part of something larger.
Only the clusters given grow, and only through voxels above the band, so the clusters within
the band stay as they were.
"""

from __future__ import annotations

import numpy as np
import numpy.typing as npt
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components
from scipy.spatial import cKDTree

from shapes.types import FloatArray

__all__ = ["grow_upwards"]


def grow_upwards(
    seeds: list[FloatArray], above: FloatArray, link_m: float
) -> list[tuple[list[int], npt.NDArray[np.intp]]]:
    """The seeds joined through the voxels ``above`` that link to them: for each group of seeds
    that the voxels above join into one piece (voxels closer than ``link_m`` are linked), the
    seeds' indices in ``seeds`` and the indices in ``above`` of the voxels added to them. A seed
    that nothing links to comes back alone with no voxel added. Groups come in the order of
    their first seed.

    Raises ValueError when ``link_m`` is not positive.

    >>> column = np.array([[0.0, 0, 0.6], [0.0, 0, 0.62], [0.0, 0, 0.64], [1.0, 0, 0.7]])
    >>> base = np.array([[0.0, 0, 0.58], [0.0, 0, 0.56]])
    >>> other = np.array([[0.5, 0, 0.58]])
    >>> [(s, a.tolist()) for s, a in grow_upwards([base, other], column, 0.03)]
    [([0], [0, 1, 2]), ([1], [])]
    """
    if link_m <= 0:
        raise ValueError(f"link_m must be positive, got {link_m}")
    if not seeds:
        return []
    sizes = [len(s) for s in seeds]
    voxels = np.vstack([*seeds, above.reshape(-1, 3)])
    seed_of = np.repeat(np.arange(len(seeds)), sizes)
    pairs = cKDTree(voxels).query_pairs(link_m, output_type="ndarray")
    graph = coo_matrix(
        (np.ones(len(pairs)), (pairs[:, 0], pairs[:, 1])), shape=(len(voxels), len(voxels))
    )
    _, labels = connected_components(graph, directed=False)
    first = int(sum(sizes))
    seed_labels, above_labels = labels[:first], labels[first:]
    # Seeds sharing a piece are one group: the pieces of the seeds' voxels joined on a graph
    # of seeds and pieces.
    n, pieces = len(seeds), int(labels.max()) + 1
    links = coo_matrix((np.ones(first), (seed_of, n + seed_labels)), shape=(n + pieces, n + pieces))
    _, group = connected_components(links, directed=False)
    piece_group = group[n:]
    out = []
    for g in dict.fromkeys(group[:n].tolist()):
        members = np.flatnonzero(group[:n] == g).tolist()
        out.append((members, np.flatnonzero(piece_group[above_labels] == g).astype(np.intp)))
    return out
