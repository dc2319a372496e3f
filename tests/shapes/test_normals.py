"""Normals in closed form agree with LAPACK's eigenvectors."""

import numpy as np
import pytest

from shapes.normals import patch_normals, smallest_axes


def test_the_closed_form_axis_is_lapacks_smallest_eigenvector():
    rng = np.random.default_rng(0)
    spread = rng.normal(size=(2000, 3, 3)) * [1.0, 1.0, 1e-3]  # flat patches and random ones
    cov = spread @ spread.transpose(0, 2, 1)
    expected = np.linalg.eigh(cov)[1][:, :, 0]
    cosine = np.abs(np.einsum("ni,ni->n", smallest_axes(cov), expected))
    np.testing.assert_allclose(cosine, 1.0, atol=1e-9)


def test_a_line_or_a_point_still_gets_a_unit_axis():
    line = np.zeros((1, 3, 3))
    line[0, 0, 0] = 1.0
    axes = smallest_axes(np.concatenate((line, np.zeros((1, 3, 3)))))
    np.testing.assert_allclose(np.linalg.norm(axes, axis=1), 1.0)
    assert abs(axes[0, 0]) < 1e-12  # normal to the line


@pytest.mark.parametrize("seed", range(3))
def test_patch_normals_are_the_smallest_axes_of_each_patchs_covariance(seed):
    rng = np.random.default_rng(seed)
    points = rng.normal(size=(500, 3)) * (0.05, 0.03, 0.002) + (0.4, -0.2, 1.3)
    neighbours = rng.integers(0, 500, size=(300, 10))
    patches = points[neighbours]
    centred = patches - patches.mean(axis=1, keepdims=True)
    expected = smallest_axes(np.einsum("nki,nkj->nij", centred, centred))
    np.testing.assert_array_equal(patch_normals(points, neighbours), expected)


def test_neighbours_that_are_not_a_table_are_refused():
    with pytest.raises(ValueError, match=r"neighbours: expected an \(N, k\) array"):
        patch_normals(np.zeros((4, 3)), np.arange(4))
