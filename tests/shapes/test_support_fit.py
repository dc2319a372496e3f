"""The support measured again with the depth noise model (shapes.segment.support_fit)."""

import numpy as np
import pytest

from shapes.segment.support_fit import measured_support
from shapes.types import SupportPlane

FLAT = SupportPlane((0.0, 0.0, 1.0), 0.0, (0.0, 0.0, 0.0), (2.0, 2.0))


@pytest.fixture
def table_near_and_far() -> tuple[np.ndarray, np.ndarray]:
    """A table at z = 0: the near half (x < 0) within 1 mm, the far half ten times as noisy
    and bent 2 cm up at its far edge (x = 1), as far rows in depth terraces are."""
    rng = np.random.default_rng(3)
    xy = rng.uniform(-1.0, 1.0, (4000, 2))
    far = xy[:, 0] > 0
    sigma = np.where(far, 0.01, 0.001)
    z = rng.normal(0.0, sigma) + np.where(far, 0.02 * xy[:, 0], 0.0)
    return np.column_stack((xy, z)), 3 * sigma


def test_the_near_precise_points_fix_the_plane(
    table_near_and_far: tuple[np.ndarray, np.ndarray],
) -> None:
    table, tolerance = table_near_and_far
    plain = measured_support(FLAT, table, np.full(len(table), tolerance.max()))
    weighed = measured_support(FLAT, table, tolerance)
    near_edge = np.array([[-1.0, 0.0, 0.0]])
    assert abs(weighed.signed_distance(near_edge)[0]) < 0.001
    assert abs(plain.signed_distance(near_edge)[0]) > 0.003  # equal weights: pulled by the far


def test_what_stands_on_the_support_does_not_pull_it() -> None:
    rng = np.random.default_rng(4)
    xy = rng.uniform(-1.0, 1.0, (3000, 2))
    table = np.column_stack((xy, rng.normal(0.0, 0.002, 3000)))
    base = np.column_stack((rng.uniform(0.2, 0.4, (300, 2)), np.full(300, 0.012)))  # a low box
    found = measured_support(FLAT, np.vstack((table, base)), np.full(3300, 0.006))
    np.testing.assert_allclose(found.normal, (0.0, 0.0, 1.0), atol=5e-4)
    assert abs(found.offset) < 5e-4


def test_the_normal_keeps_its_side_and_the_centre_its_place() -> None:
    table = np.array([[0.0, 0.0, 0.01], [1.0, 0.0, 0.01], [0.0, 1.0, 0.01], [1.0, 1.0, 0.01]])
    found = measured_support(FLAT, table, np.full(4, 0.03))
    np.testing.assert_allclose(found.normal, (0.0, 0.0, 1.0), atol=1e-9)
    np.testing.assert_allclose(found.offset, -0.01, atol=1e-9)
    np.testing.assert_allclose(found.centre, (0.0, 0.0, 0.01), atol=1e-9)  # FLAT's, moved up
    assert found.extent == FLAT.extent


@pytest.mark.parametrize(
    "table",
    [np.zeros((2, 3)), np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [2.0, 0.0, 0.0]])],
    ids=["two voxels", "a line"],
)
def test_too_few_voxels_or_a_line_leave_the_support_as_it_was(table: np.ndarray) -> None:
    assert measured_support(FLAT, table, np.full(len(table), 0.03)) is FLAT
