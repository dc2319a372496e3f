"""A cut whose parts close a ring around a common centre is one thing seen from above
(shapes.ring_cut; docs/perception.md, "A cut that closes a ring (stop 39)")."""

import numpy as np
import pytest

from shapes.ring_cut import closes_a_ring, largest_gap_deg


def _ring(n_parts: int, radius: float = 0.1, per_part: int = 20) -> tuple[np.ndarray, np.ndarray]:
    """Voxels on a circle, cut into ``n_parts`` equal arcs."""
    angles = np.linspace(0, 2 * np.pi, n_parts * per_part, endpoint=False)
    voxels = np.column_stack([radius * np.cos(angles), radius * np.sin(angles), angles * 0])
    return voxels, np.repeat(np.arange(n_parts), per_part)


def test_a_bowl_cut_into_arcs_closes_a_ring() -> None:
    voxels, parts = _ring(6)
    assert largest_gap_deg(voxels, parts) == pytest.approx(60.0)
    assert closes_a_ring(voxels, parts, 125.0)


def test_objects_side_by_side_do_not() -> None:
    """Two boxes touching, and three in a row: their centres do not surround the middle."""
    two = np.array([[0.0, 0, 0], [0.01, 0, 0], [0.05, 0, 0], [0.06, 0, 0]])
    assert not closes_a_ring(two, np.array([0, 0, 1, 1]), 125.0)
    row = np.array([[0.0, 0, 0], [0.1, 0.001, 0], [0.2, 0, 0]])
    assert largest_gap_deg(row, np.array([0, 1, 2])) > 170
    assert not closes_a_ring(row, np.array([0, 1, 2]), 125.0)


def test_a_single_part_is_no_ring() -> None:
    voxels, _ = _ring(1)
    assert largest_gap_deg(voxels, np.zeros(len(voxels), dtype=np.int64)) == 360.0
    assert not closes_a_ring(voxels, np.zeros(len(voxels), dtype=np.int64), 125.0)


@pytest.mark.parametrize("gap", [0.0, 180.0, -5.0])
def test_a_gap_outside_zero_to_half_a_turn_is_refused(gap: float) -> None:
    voxels, parts = _ring(4)
    expected = f"max_gap_deg must lie between 0 and 180 degrees, got {gap}"
    with pytest.raises(ValueError, match=expected):
        closes_a_ring(voxels, parts, gap)
