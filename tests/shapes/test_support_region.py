"""The main piece of a support's plane and the outline it covers (shapes.support_region)."""

import numpy as np
import pytest
from scipy.spatial import ConvexHull

from shapes.support_region import _hull_candidates, support_region


def test_a_plane_kilometres_wide_is_joined_on_its_occupied_cells_only() -> None:
    """A cloud in map coordinates: a dense grid of 5 cm cells over 50 km would not fit in memory."""
    xy = np.array([[0.0, 0.0], [0.01, 0.0], [0.0, 0.01], [0.01, 0.01], [5e4, 5e4]])
    region = support_region(xy, cell_m=0.05)
    assert region.piece.tolist() == [True, True, True, True, False]
    assert region.contains(np.array([[0.005, 0.005], [5e4, 5e4]]), margin_m=0.0).tolist() == [
        True,
        False,
    ]


def test_cells_touching_at_a_corner_are_one_piece_and_a_gap_of_one_cell_is_not() -> None:
    xy = np.array([[0.0, 0.0], [0.06, 0.06], [0.12, 0.12], [0.30, 0.0], [0.30, 0.06]])
    region = support_region(xy, cell_m=0.05)
    assert region.piece.tolist() == [True, True, True, False, False]


def test_points_on_one_line_cover_their_bounding_box() -> None:
    xy = np.array([[0.0, 0.0], [0.02, 0.0], [0.04, 0.0]])
    region = support_region(xy, cell_m=0.05)
    assert region.contains(np.array([[0.03, 0.0], [0.03, 0.02]]), margin_m=0.01).tolist() == [
        True,
        False,
    ]


@pytest.mark.parametrize("seed", range(4))
def test_the_hull_of_the_filtered_points_is_the_hull_of_all(seed: int) -> None:
    """qhull sees only the points outside the octagon of extremes, and finds the same edges."""
    rng = np.random.default_rng(seed)
    xy = np.round(rng.uniform(-1.0, 1.0, (5000, 2)) * (1.0, 0.4), 2 + seed % 2)
    xy = np.vstack((xy, xy[:20]))  # repeated points, and extremes repeated along two directions
    kept = _hull_candidates(xy)
    assert kept.sum() < 0.1 * len(xy)
    full, filtered = ConvexHull(xy).equations, ConvexHull(xy[kept]).equations
    np.testing.assert_array_equal(full[np.lexsort(full.T)], filtered[np.lexsort(filtered.T)])
